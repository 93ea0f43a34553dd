//===- OiioModuleEntry.cpp - libOslOiio.so's one exported symbol ----------===//
#include "OiioModuleParts.h"

namespace {
osl::OiioModuleHost theHost{};
} // namespace

const osl::OiioModuleHost &osl::oiio::host() { return theHost; }

extern "C" __attribute__((visibility("default"))) const osl::OiioModuleApi *
osl_oiio_module(const osl::OiioModuleHost *host) {
  using namespace osl::oiio;
  static const osl::OiioModuleApi api = {
      openImage,      writeRows, closeImage,         readImage,
      texture,        gettextureinfo, udimTile,          textureFileErrors,
      setTextureCacheMegabytes,
  };
  theHost = *host;
  return &api;
}
