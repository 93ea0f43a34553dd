//===- OiioModule.cpp - Loading OpenImageIO on first use ------------------===//
//
// The host side of OiioModule.h: finds and opens libOslOiio.so once, and
// forwards the texture entry points and the images the native code leaves
// to OpenImageIO.
//
//===----------------------------------------------------------------------===//
#include "OiioModule.h"
#include "ImageFormats.h"

#include "OslAbi/EntryPoints.h"
#include "OslRuntime/PrintCall.h"
#include "OslRuntime/StringCall.h"

#include <dlfcn.h>
#include <unistd.h>

#include <atomic>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <vector>

namespace osl {

namespace {

std::atomic<const OiioModuleApi *> loadedModule{nullptr};
std::once_flag loadOnce;
std::string loadError;
std::mutex pendingMutex;
float pendingCacheMegabytes = -1; // set before the module was needed

std::string directoryOf(const std::string &path) {
  size_t slash = path.rfind('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

/// Where the module may be: beside the program or library that holds this
/// code, in ../lib from it (an installed tree), where it was installed and
/// where it was built; OSL_MLIR_OIIO_MODULE names it explicitly.
std::vector<std::string> candidatePaths() {
  std::vector<std::string> dirs, paths;
  if (const char *explicitPath = std::getenv("OSL_MLIR_OIIO_MODULE"))
    paths.push_back(explicitPath);
  Dl_info info;
  if (dladdr(reinterpret_cast<void *>(&oiioModule), &info) && info.dli_fname &&
      info.dli_fname[0] == '/')
    dirs.push_back(directoryOf(info.dli_fname));
  char exe[PATH_MAX];
  ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n > 0)
    dirs.push_back(directoryOf(std::string(exe, size_t(n))));
  for (const std::string &dir : dirs) {
    paths.push_back(dir + kOiioModuleFile);
    paths.push_back(dir + "../lib/" + kOiioModuleFile);
  }
#ifdef OSL_OIIO_MODULE_INSTALLED
  paths.push_back(OSL_OIIO_MODULE_INSTALLED);
#endif
#ifdef OSL_OIIO_MODULE_BUILT
  paths.push_back(OSL_OIIO_MODULE_BUILT);
#endif
  return paths;
}

void load() {
  static const OiioModuleHost host = {osl_rt_string_intern, [](const char *text) {
                                        // Uniform calls report on the batch's first point.
                                        keepLaneText(printStreamCode("renderer_error"), 0, "",
                                                     text);
                                      }};
  std::string tried;
  for (const std::string &path : candidatePaths()) {
    if (access(path.c_str(), R_OK) != 0)
      continue;
    void *library = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!library) {
      loadError = dlerror();
      return;
    }
    auto entry = reinterpret_cast<OiioModuleEntry>(dlsym(library, kOiioModuleEntry));
    if (!entry) {
      loadError = path + " has no " + kOiioModuleEntry;
      return;
    }
    const OiioModuleApi *api = entry(&host);
    std::lock_guard<std::mutex> lock(pendingMutex);
    if (pendingCacheMegabytes >= 0)
      api->setTextureCacheMegabytes(pendingCacheMegabytes);
    loadedModule.store(api);
    return;
  }
  loadError = std::string("cannot find ") + kOiioModuleFile +
              " (OpenImageIO support; set OSL_MLIR_OIIO_MODULE to its path)";
}

/// Lookups that could not reach the module: reported once, counted as a
/// texture error, and their results are zero.
std::atomic<int> unreachableTextures{0};

void reportUnreachable(const char *where, const std::string &why) {
  if (unreachableTextures.fetch_add(1) == 0)
    std::fprintf(stderr, "%s: error: textures are unavailable: %s\n", where, why.c_str());
}

/// A file written by OpenImageIO in the module.
class OiioWriter : public image::Writer {
public:
  OiioWriter(const OiioModuleApi *api, void *handle) : api(api), handle(handle) {}
  ~OiioWriter() override {
    std::string ignored;
    if (handle)
      api->closeImage(handle, ignored);
  }
  bool writeRows(int rowBegin, int rowEnd, const float *data, std::string &error) override {
    return api->writeRows(handle, rowBegin, rowEnd, data, error);
  }
  bool close(std::string &error) override {
    void *closing = handle;
    handle = nullptr;
    return api->closeImage(closing, error);
  }

private:
  const OiioModuleApi *api;
  void *handle;
};

} // namespace

const OiioModuleApi *oiioModule(std::string &error) {
  std::call_once(loadOnce, load);
  const OiioModuleApi *api = loadedModule.load();
  if (!api)
    error = loadError;
  return api;
}

const OiioModuleApi *oiioModuleIfLoaded() { return loadedModule.load(); }

int textureFileErrors() {
  const OiioModuleApi *api = oiioModuleIfLoaded();
  return (api ? api->textureFileErrors() : 0) + (unreachableTextures.load() > 0);
}

void setTextureCacheMegabytes(float megabytes) {
  {
    std::lock_guard<std::mutex> lock(pendingMutex);
    if (!loadedModule.load()) {
      pendingCacheMegabytes = megabytes;
      return;
    }
  }
  loadedModule.load()->setTextureCacheMegabytes(megabytes);
}

namespace image {

std::unique_ptr<Writer> openWithOiio(const std::string &path, const std::string &formatFrom,
                                     const WriteSpec &spec, std::string &error) {
  const OiioModuleApi *api = oiioModule(error);
  if (!api) {
    error = "cannot write " + formatFrom + ": " + error;
    return nullptr;
  }
  void *handle = api->openImage(path, formatFrom, spec.xres, spec.yres, spec.channels,
                                spec.dataType, spec.intBits, spec.displayConvert, error);
  if (!handle)
    return nullptr;
  return std::make_unique<OiioWriter>(api, handle);
}

bool readWithOiio(const std::string &path, ImageData &image, std::string &error) {
  const OiioModuleApi *api = oiioModule(error);
  if (!api) {
    error = "cannot read " + path + ": " + error;
    return false;
  }
  return api->readImage(path, image, error);
}

} // namespace image

/// Calls fn(file, lanes) once per file the lanes of `laneMask` name by
/// string handle (handles[lane]), with the lanes that name it.
template <typename Fn>
void forEachFileNamed(const int32_t *handles, int32_t width, uint32_t laneMask, Fn fn) {
  for (uint32_t left = laneMask; left;) {
    int32_t handle = handles[__builtin_ctz(left)];
    uint32_t same = 0;
    for (int32_t lane = 0; lane < width; ++lane)
      if ((left >> lane & 1u) && handles[lane] == handle)
        same |= 1u << lane;
    std::string name = stringText(handle);
    fn(name.c_str(), same);
    left &= ~same;
  }
}

} // namespace osl

extern "C" void osl_rt_texture(const char *where, const char *file, const char *subimageName,
                               int32_t subimage, int32_t kind, int32_t nchannels,
                               int32_t swrap, int32_t twrap, int32_t rwrap, int32_t interp,
                               int32_t flags, float *rows, int32_t width, uint32_t laneMask) {
  std::string error;
  if (const osl::OiioModuleApi *api = osl::oiioModule(error)) {
    if (file) {
      api->texture(where, file, subimageName, subimage, kind, nchannels, swrap, twrap, rwrap,
                   interp, flags, rows, width, laneMask);
      return;
    }
    // Names computed at run time: the lanes naming one file at a time.
    const int32_t *handles =
        reinterpret_cast<const int32_t *>(rows + size_t(osl::kTextureFileRow) * size_t(width));
    osl::forEachFileNamed(handles, width, laneMask, [&](const char *name, uint32_t lanes) {
      api->texture(where, name, subimageName, subimage, kind, nchannels, swrap, twrap, rwrap,
                   interp, flags, rows, width, lanes);
    });
    return;
  }
  osl::reportUnreachable(where, error);
  for (int32_t row = osl::kTextureResultRow; row < osl::kTextureResultRow + 4; ++row)
    for (int32_t lane = 0; lane < width; ++lane)
      if (laneMask >> lane & 1u)
        rows[size_t(row) * size_t(width) + size_t(lane)] = 0.0f;
}

extern "C" int32_t osl_rt_gettextureinfo(const char *file, const char *name, int32_t kind,
                                         int32_t count, void *data) {
  std::string error;
  const osl::OiioModuleApi *api = osl::oiioModule(error);
  if (!api)
    return 0;
  if (kind != osl::kTextureInfoString)
    return api->gettextureinfo(file, name, kind, count, data);
  // The module answers with the texture system's own (lasting) texts; the
  // kernel gets their handles in the string table.
  std::vector<const char *> texts(size_t(std::max(count, 0)), nullptr);
  if (!api->gettextureinfo(file, name, kind, count, texts.data()))
    return 0;
  for (int32_t k = 0; k < count; ++k)
    static_cast<int32_t *>(data)[k] = osl_rt_string_intern(texts[size_t(k)] ? texts[size_t(k)] : "");
  return 1;
}

extern "C" void osl_rt_udim_tile_lanes(const int32_t *handles, const float *s, const float *t,
                                       int32_t *tiles, int32_t width, uint32_t laneMask) {
  std::string error;
  const osl::OiioModuleApi *api = osl::oiioModule(error);
  for (int32_t lane = 0; lane < width; ++lane) {
    if (!(laneMask >> lane & 1u))
      continue;
    const char *tile =
        api ? api->udimTile(osl::stringText(handles[lane]).c_str(), s[lane], t[lane]) : nullptr;
    tiles[lane] = tile ? osl_rt_string_intern(tile) : handles[lane];
  }
}

extern "C" void osl_rt_gettextureinfo_lanes(const int32_t *handles, const char *name,
                                            int32_t kind, int32_t count, void *data,
                                            int32_t *found, int32_t width, uint32_t laneMask) {
  // Every value is 4 bytes (int, float or string handle).
  auto *values = static_cast<int32_t *>(data);
  std::vector<int32_t> answer(size_t(std::max(count, 0)));
  osl::forEachFileNamed(handles, width, laneMask, [&](const char *file, uint32_t lanes) {
    // No file (a UDIM pattern without a tile at the point): nothing known.
    int32_t known = *file ? osl_rt_gettextureinfo(file, name, kind, count, answer.data()) : 0;
    for (int32_t lane = 0; lane < width; ++lane) {
      if (!(lanes >> lane & 1u))
        continue;
      found[lane] = known;
      if (known)
        for (int32_t k = 0; k < count; ++k)
          values[size_t(k) * size_t(width) + size_t(lane)] = answer[size_t(k)];
    }
  });
}
