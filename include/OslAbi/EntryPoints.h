//===- EntryPoints.h - The runtime functions compiled kernels call -*- C++ -*-===//
//
// Each entry point is declared once, here, as a C function. The lowering
// makes its LLVM declaration from the C type (decltype, so it needs no
// definition), the JIT binds its address by name from the same list, and
// the runtime's definition must match the declaration (a C function cannot
// be overloaded, so a different signature does not compile).
//
// Rows are blocks of W 32-bit values per operand (Strings.h's layout);
// `laneMask` has bit i set for lane i; `where` is the call's file:line:col.
//
//===----------------------------------------------------------------------===//
#ifndef OSLABI_ENTRYPOINTS_H
#define OSLABI_ENTRYPOINTS_H

#include <cstdint>

extern "C" {

//--- Textures (Texture.h) ---------------------------------------------------//

/// One lookup for the lanes in `laneMask` of a batch of `width` lanes; reads
/// and writes `rows` (kTextureRows x width floats). A null `file` means each
/// lane names its own in kTextureFileRow (lanes naming the same file are
/// looked up together). A file that cannot be read is reported once, at
/// `where`, unless missingcolor or errormessage is given; its lanes get
/// missingcolor, or zeros.
void osl_rt_texture(const char *where, const char *file, const char *subimageName,
                    int32_t subimage, int32_t kind, int32_t nchannels, int32_t swrap,
                    int32_t twrap, int32_t rwrap, int32_t interp, int32_t flags, float *rows,
                    int32_t width, uint32_t laneMask);

/// gettextureinfo(): writes `count` values of `kind` (TextureInfoKind)
/// answering `name` about `file` to `data`; returns 1 if the texture system
/// knew the answer, else 0 (and `data` is unchanged).
int32_t osl_rt_gettextureinfo(const char *file, const char *name, int32_t kind, int32_t count,
                              void *data);

/// gettextureinfo() about files named at run time: point i asks about the
/// file whose string handle is handles[i], writes its `count` values to
/// data[k * width + i] (unchanged where unknown) and 1 or 0 to found[i].
/// Points naming the same file ask once.
void osl_rt_gettextureinfo_lanes(const int32_t *handles, const char *name, int32_t kind,
                                 int32_t count, void *data, int32_t *found, int32_t width,
                                 uint32_t laneMask);

/// A UDIM pattern's tile at (s, t): point i's file is the string whose
/// handle is handles[i]; tiles[i] gets the handle of the concrete tile's
/// file name, of "" where the pattern has no tile there, or handles[i]
/// itself where the file is not a UDIM pattern.
void osl_rt_udim_tile_lanes(const int32_t *handles, const float *s, const float *t,
                            int32_t *tiles, int32_t width, uint32_t laneMask);

//--- Strings (Strings.h) and printing (Print.h) ------------------------------//

/// The handle of `text` (NUL-terminated), interned on first use.
int32_t osl_rt_string_intern(const char *text);

/// osl_rt_string_intern for a constant: `*slot` (the kernel's own, -1 until
/// then) keeps the handle after the first call, so later batches skip the
/// intern table's lock and hash.
int32_t osl_rt_string_intern_cached(const char *text, int32_t *slot);

/// The bytes of the string `handle` names ("" for a handle never issued),
/// its length in `*length`. They stay valid and unchanged for the process's
/// life: the intern table never moves or frees a string.
const char *osl_rt_string_bytes(int32_t handle, int32_t *length);

/// Calls string function `function` (an index into kStringFunctions) for the
/// lanes in `laneMask`. `kinds` names the operands' kinds (s, i, f, t;
/// NUL-terminated); `rows` holds their rows then the result row. Lanes not
/// in the mask get 0. An error (a bad regular expression or format) is
/// reported once at `where`, and its lanes get OSL's 0 or "".
void osl_rt_string_call(const char *where, int32_t function, const char *kinds, int32_t *rows,
                        int32_t width, uint32_t laneMask);

/// Formats the active lanes' operands (stream `stream` of kPrintStreams;
/// `kinds` as osl.print's) and keeps each lane's text for the batch. A
/// format error is reported once at `where`.
void osl_rt_print(const char *where, int32_t stream, const char *kinds, int32_t *rows,
                  int32_t width, uint32_t laneMask);

//--- Lane statistics ---------------------------------------------------------//

/// Adds one executed masked block with `activeLanes` lanes set (kernels
/// compiled with lane counting). Safe to call from several threads.
void osl_rt_count_lanes(int32_t activeLanes);

//--- Messages ---------------------------------------------------------------//
// setmessage in one layer, getmessage in a later one, kept per shading
// thread for one batch: a kernel that uses them calls osl_rt_message_reset
// on entry. `kinds` has one letter per operand (s i f k one row, t three).

/// Forgets the messages of the previous batch.
void osl_rt_message_reset();

/// Stores message `name` (OSL type `typeName`) for the lanes in `laneMask`.
/// Setting it again, or after a getmessage of it found nothing, is reported
/// at `where` (file:line) as OSL does, and changes nothing.
void osl_rt_setmessage(const char *where, const char *name, const char *typeName,
                       const char *kinds, const int32_t *rows, int32_t width, uint32_t laneMask);

/// For the lanes in `laneMask`: where message `name` was set with the same
/// kinds, copies it over the value rows and sets the row after them (found)
/// to 1; else sets found to 0, reporting a type mismatch at `where`, or
/// remembering that the message was asked for.
void osl_rt_getmessage(const char *where, const char *name, const char *typeName,
                       const char *kinds, int32_t *rows, int32_t width, uint32_t laneMask);

//--- Point clouds (PointCloud.h) ---------------------------------------------//

/// pointcloud_search, _get or _write (`function`, a PointCloudFunction) for
/// the lanes in `laneMask`: `rows` as PointCloud.h lays them out for
/// `layout` and `kinds`. Errors (a file that cannot be read, an attribute
/// it lacks) are reported per point in OSL's renderer's words.
void osl_rt_pointcloud(int32_t function, const char *layout, const char *kinds, int32_t *rows,
                       int32_t width, uint32_t laneMask);

//--- Closures (Closures.h) ---------------------------------------------------//

/// Makes a primitive node of closure `id` for the lanes in `laneMask`: `rows`
/// holds its parameters' rows (closureParamKinds order) then the result row
/// of handles. Other lanes get 0.
void osl_rt_closure_component(int32_t id, int32_t *rows, int32_t width, uint32_t laneMask);

/// closure * color: rows are the closure's handles, the weight's r, g, b
/// (float bits), then the result.
void osl_rt_closure_mul(int32_t *rows, int32_t width, uint32_t laneMask);

/// closure + closure: rows are the two handles, then the result.
void osl_rt_closure_add(int32_t *rows, int32_t width, uint32_t laneMask);

} // extern "C"

/// Every entry point, once: X(name) for each.
#define OSL_ABI_ENTRY_POINTS(X)                                                              \
  X(osl_rt_texture)                                                                          \
  X(osl_rt_gettextureinfo)                                                                   \
  X(osl_rt_gettextureinfo_lanes)                                                             \
  X(osl_rt_udim_tile_lanes)                                                                  \
  X(osl_rt_string_intern)                                                                    \
  X(osl_rt_string_intern_cached)                                                             \
  X(osl_rt_string_bytes)                                                                     \
  X(osl_rt_string_call)                                                                      \
  X(osl_rt_print)                                                                            \
  X(osl_rt_count_lanes)                                                                      \
  X(osl_rt_message_reset)                                                                    \
  X(osl_rt_setmessage)                                                                       \
  X(osl_rt_getmessage)                                                                       \
  X(osl_rt_pointcloud)                                                                       \
  X(osl_rt_closure_component)                                                                \
  X(osl_rt_closure_mul)                                                                      \
  X(osl_rt_closure_add)

namespace osl::abi {

/// An entry point as the lowering sees it: its symbol, and its C type `Fn`
/// from which the LLVM declaration is made.
template <typename Fn> struct EntryPoint {
  const char *name;
};

/// osl::abi::entry::osl_rt_texture and so on.
namespace entry {
#define OSL_ABI_DEFINE_ENTRY(fn) inline constexpr EntryPoint<decltype(::fn)> fn{#fn};
OSL_ABI_ENTRY_POINTS(OSL_ABI_DEFINE_ENTRY)
#undef OSL_ABI_DEFINE_ENTRY
} // namespace entry

/// Calls `visit(name, address)` for every entry point: how the JIT binds
/// them. Only code that links the runtime instantiates it.
template <typename Visit> void forEachEntryPointAddress(Visit visit) {
#define OSL_ABI_VISIT_ENTRY(fn) visit(#fn, reinterpret_cast<void *>(&::fn));
  OSL_ABI_ENTRY_POINTS(OSL_ABI_VISIT_ENTRY)
#undef OSL_ABI_VISIT_ENTRY
}

} // namespace osl::abi

#endif // OSLABI_ENTRYPOINTS_H
