//===- TextureSystem.cpp - Texture lookups through OpenImageIO ------------===//
//
// Part of the OpenImageIO module (OiioModule.h). One TextureSystem shared by every thread and shader (OpenImageIO's shared
// cache). Each lane is looked up with OpenImageIO's per-point API: the
// options OSL lets vary per point (blur, width, fill, missingcolor,
// missingalpha) vary here too, which OpenImageIO's batched options take once
// per batch, and the results equal OSL's scalar lookups exactly.
//
//===----------------------------------------------------------------------===//
#include "OiioModuleParts.h"

#include <Imath/ImathVec.h>
#include <OpenImageIO/texture.h>
#include <OpenImageIO/ustring.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <limits>
#include <mutex>
#include <set>
#include <string>

using namespace OIIO;

static_assert(int(Tex::Wrap::Black) == osl::textureWrapCode("black") &&
                  int(Tex::Wrap::Mirror) == osl::textureWrapCode("mirror") &&
                  int(Tex::Wrap::PeriodicSharedBorder) ==
                      osl::textureWrapCode("periodic_sharedborder"),
              "wrap codes must be OpenImageIO's");
static_assert(int(Tex::InterpMode::Closest) == osl::textureInterpCode("closest") &&
                  int(Tex::InterpMode::SmartBicubic) == osl::textureInterpCode("smartcubic"),
              "interp codes must be OpenImageIO's");

namespace {

/// A 32-bit handle stored in a float row, bit for bit.
float bitCastToFloat(int32_t handle) {
  float f;
  std::memcpy(&f, &handle, sizeof f);
  return f;
}

TextureSystem &sharedTextureSystem() {
  static TextureSystem *ts = [] {
    TextureSystem *t = TextureSystem::create(/*shared=*/true);
    t->attribute("automip", 1);
    return t;
  }();
  return *ts;
}

std::mutex missingMutex;
std::set<std::string> missingFiles;

/// Reports a file that cannot be read once, not once per point.
void reportMissing(const char *where, const char *file, const std::string &why) {
  std::lock_guard<std::mutex> lock(missingMutex);
  if (!missingFiles.insert(file).second)
    return;
  std::fprintf(stderr, "%s: error: texture '%s' could not be read%s%s\n", where, file,
               why.empty() ? "" : ": ", why.c_str());
}

} // namespace

namespace osl::oiio {

int textureFileErrors() {
  std::lock_guard<std::mutex> lock(missingMutex);
  return int(missingFiles.size());
}

void setTextureCacheMegabytes(float megabytes) {
  sharedTextureSystem().attribute("max_memory_MB", megabytes);
}

void texture(const char *where, const char *file, const char *subimageName, int32_t subimage,
             int32_t kind, int32_t nchannels, int32_t swrap, int32_t twrap, int32_t rwrap,
             int32_t interp, int32_t flags, float *rows, int32_t width, uint32_t laneMask) {
  TextureSystem &ts = sharedTextureSystem();
  TextureSystem::Perthread *thread = ts.get_perthread_info();
  TextureSystem::TextureHandle *handle = ts.get_texture_handle(ustring(file), thread);
  auto row = [&](int r) { return rows + size_t(r) * size_t(width); };
  TextureOpt opt;
  opt.subimage = subimage;
  if (subimageName && *subimageName)
    opt.subimagename = ustring(subimageName);
  opt.swrap = TextureOpt::Wrap(swrap);
  opt.twrap = TextureOpt::Wrap(twrap);
  opt.rwrap = TextureOpt::Wrap(rwrap);
  opt.interpmode = TextureOpt::InterpMode(interp);
  bool missingGiven = flags & (kTextureHasMissingColor | kTextureHasMissingAlpha);
  int channels = nchannels + 1; // and alpha
  int fileChannels = -1;        // a volume's, asked once per call when needed
  for (int lane = 0; lane < width; ++lane) {
    if (!(laneMask >> lane & 1u))
      continue;
    auto at = [&](int r) { return row(r)[lane]; };
    const int o = kTextureOptionRow;
    opt.sblur = at(o + 0);
    opt.tblur = at(o + 1);
    opt.rblur = at(o + 2);
    opt.swidth = at(o + 3);
    opt.twidth = at(o + 4);
    opt.rwidth = at(o + 5);
    opt.fill = at(o + 6);
    // OpenImageIO's per-point calls take the first channel per point too.
    std::memcpy(&opt.firstchannel, &row(kTextureFirstChannelRow)[lane], sizeof(int32_t));
    // missingcolor's channels line up with the result's: the color, then
    // alpha.
    float missing[4] = {0, 0, 0, 0};
    for (int c = 0; c < nchannels; ++c)
      missing[c] = (flags & kTextureHasMissingColor) ? at(o + 8 + c) : 0.0f;
    missing[nchannels] = (flags & kTextureHasMissingAlpha) ? at(o + 7) : 1.0f;
    opt.missingcolor = missingGiven ? missing : nullptr;
    float result[4] = {0, 0, 0, 0};
    // The result's slopes along s and t: a 2D lookup's derivatives are
    // these times the coordinates' (osl-derivatives reads them).
    float dresultds[4] = {0, 0, 0, 0}, dresultdt[4] = {0, 0, 0, 0};
    const int d = kTextureDerivRow;
    bool ok = false;
    if (kind == kTexture2D) {
      bool slopes = flags & kTextureWantsDerivatives;
      ok = ts.texture(handle, thread, opt, at(kTextureCoordRow), at(kTextureCoordRow + 1),
                      at(d), at(d + 1), at(d + 2), at(d + 3), channels, result,
                      slopes ? dresultds : nullptr, slopes ? dresultdt : nullptr);
      // OpenImageIO's closest-texel lookup leaves the slopes it was given
      // holding whatever its stack held (testshade's derivatives are
      // garbage there too): a texel's value is constant, its slope 0, and
      // the result the same from run to run and at every width.
      if (opt.interpmode == TextureOpt::InterpClosest) {
        std::fill(std::begin(dresultds), std::end(dresultds), 0.0f);
        std::fill(std::begin(dresultdt), std::end(dresultdt), 0.0f);
      }
    } else {
      Imath::V3f p(at(kTextureCoordRow), at(kTextureCoordRow + 1), at(kTextureCoordRow + 2));
      Imath::V3f dx(at(d), at(d + 1), at(d + 2)), dy(at(d + 3), at(d + 4), at(d + 5));
      if (kind == kTexture3D) {
        Imath::V3f dz(at(d + 6), at(d + 7), at(d + 8));
        // OpenImageIO's 3D lookup asserts (aborts) when a first channel
        // past 0 reaches beyond the volume's channels: ask for those it
        // has, and the rest are fill. (From channel 0 it fills them itself.)
        int asked = channels;
        if (opt.firstchannel > 0) {
          if (fileChannels < 0 &&
              !ts.get_texture_info(handle, thread, 0, ustring("channels"), TypeDesc::INT,
                                   &fileChannels))
            fileChannels = std::numeric_limits<int>::max(); // unknown: ask for all
          asked = std::max(0, std::min(channels, fileChannels - opt.firstchannel));
        }
        for (int c = asked; c < channels; ++c)
          result[c] = opt.fill;
        ok = asked == 0 || ts.texture3d(handle, thread, opt, p, dx, dy, dz, asked, result);
      } else {
        ok = ts.environment(handle, thread, opt, p, dx, dy, channels, result);
      }
    }
    if (flags & kTextureWantsErrorMessage) {
      // OSL's errormessage: the texture system's error where the lookup
      // failed ("unknown" if it has none: a file already known broken).
      std::string error = ok ? "" : ts.geterror();
      if (!ok && error.empty())
        error = "unknown";
      row(kTextureErrorRow)[lane] = bitCastToFloat(host().internString(error.c_str()));
    } else if (!ok && !missingGiven) {
      reportMissing(where, file, ts.geterror());
    }
    for (int c = 0; c < channels; ++c) {
      row(kTextureResultRow + c)[lane] = result[c];
      row(kTextureDsRow + c)[lane] = dresultds[c];
      row(kTextureDtRow + c)[lane] = dresultdt[c];
    }
    if (nchannels == 1) {
      row(kTextureAlphaRow)[lane] = result[1];
      row(kTextureDsRow + 3)[lane] = dresultds[1];
      row(kTextureDtRow + 3)[lane] = dresultdt[1];
    }
  }
}

int32_t gettextureinfo(const char *file, const char *name, int32_t kind, int32_t count,
                       void *data) {
  // A string answer is a ustring, whose text lasts as long as the process.
  TypeDesc type(kind == osl::kTextureInfoString  ? TypeDesc::STRING
                : kind == osl::kTextureInfoFloat ? TypeDesc::FLOAT
                                            : TypeDesc::INT);
  if (count > 1)
    type.arraylen = count;
  TextureSystem &ts = sharedTextureSystem();
  if (ts.get_texture_info(ustring(file), 0, ustring(name), type, data))
    return 1;
  // A file that cannot be read is reported as OSL's renderer services
  // report it; an attribute the file lacks is no error.
  // (It counts among the files that could not be read, for the exit status.)
  std::string error = ts.geterror();
  if (!error.empty()) {
    host().rendererError(("[RendererServices::get_texture_info] " + error).c_str());
    std::lock_guard<std::mutex> lock(missingMutex);
    missingFiles.insert(file);
  }
  return 0;
}

const char *udimTile(const char *pattern, float s, float t) {
  TextureSystem &ts = sharedTextureSystem();
  ustring file(pattern);
  if (!ts.is_udim(file))
    return nullptr;
  TextureSystem::TextureHandle *tile = ts.resolve_udim(file, s, t);
  // A ustring's text lasts as long as the process.
  return tile ? ts.filename_from_handle(tile).c_str() : "";
}

} // namespace osl::oiio
