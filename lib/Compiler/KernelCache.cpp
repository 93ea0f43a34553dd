//===- KernelCache.cpp - Compiled kernels kept on disk between runs -------===//
#include "OslCompiler/KernelCache.h"

#include "llvm/Support/FileSystem.h"
#include "llvm/Support/Format.h"
#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/Path.h"
#include "llvm/Support/raw_ostream.h"
#include "llvm/Support/xxhash.h"

#include <cstdlib>
#include <cstring>
#include <dlfcn.h>
#include <sys/stat.h>

using namespace osl;

namespace {

constexpr char kMagic[8] = {'O', 'S', 'L', 'K', 'R', 'N', '0', '2'};

void putField(std::string &out, llvm::StringRef field) {
  uint64_t size = field.size();
  out.append(reinterpret_cast<const char *>(&size), sizeof size);
  out.append(field.data(), field.size());
}

/// Reads the fields putField wrote, never past the end of the data.
struct FieldReader {
  llvm::StringRef rest;
  bool next(llvm::StringRef &field) {
    uint64_t size;
    if (rest.size() < sizeof size)
      return false;
    std::memcpy(&size, rest.data(), sizeof size);
    rest = rest.drop_front(sizeof size);
    if (size > rest.size())
      return false;
    field = rest.take_front(size);
    rest = rest.drop_front(size);
    return true;
  }
};

std::string outputsText(const std::vector<OutputSpec> &outputs) {
  std::string text;
  for (const OutputSpec &o : outputs)
    text += o.name + " " + std::to_string(o.channels) + (o.closure ? " closure" : "") +
            (o.integer ? " int" : "") + "\n";
  return text;
}

bool parseOutputs(llvm::StringRef text, std::vector<OutputSpec> &outputs) {
  llvm::SmallVector<llvm::StringRef> lines;
  text.split(lines, '\n', -1, /*KeepEmpty=*/false);
  for (llvm::StringRef line : lines) {
    bool integer = line.consume_back(" int");
    bool closure = line.consume_back(" closure");
    auto [name, channels] = line.rsplit(' ');
    int n;
    if (name.empty() || channels.getAsInteger(10, n) || n < 1)
      return false;
    outputs.push_back({name.str(), n, closure, integer});
  }
  return true;
}

} // namespace

std::string KernelCache::defaultDirectory() {
  if (const char *dir = std::getenv("OSL_MLIR_CACHE_DIR"))
    return dir;
  if (const char *xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return std::string(xdg) + "/osl-mlir";
  if (const char *home = std::getenv("HOME"); home && *home)
    return std::string(home) + "/.cache/osl-mlir";
  return "";
}

std::string KernelCache::compilerIdentity() {
  // Computed once: the file does not change under a running process, and a
  // relative path would resolve differently after a change of directory.
  static const std::string identity = []() -> std::string {
    Dl_info info;
    if (!dladdr(reinterpret_cast<void *>(&KernelCache::compilerIdentity), &info) || !info.dli_fname)
      return "unknown";
    // The main executable reports argv[0] (a bare name when found on PATH,
    // else as typed): its canonical path names it the same however it was
    // started, so the entries one invocation made serve the others.
    std::string path = info.dli_fname;
    if (path.find('/') == std::string::npos)
      path = "/proc/self/exe";
    llvm::SmallString<256> real;
    if (!llvm::sys::fs::real_path(path, real))
      path = real.str().str();
    struct stat st;
    if (stat(path.c_str(), &st) != 0)
      return "unknown";
    return path + " " + std::to_string(st.st_size) + " " + std::to_string(st.st_mtim.tv_sec) + "." +
           std::to_string(st.st_mtim.tv_nsec);
  }();
  return identity;
}

std::string KernelCache::pathFor(llvm::StringRef key) const {
  llvm::XXH128_hash_t h = llvm::xxh3_128bits(llvm::ArrayRef(key.bytes_begin(), key.size()));
  std::string name;
  llvm::raw_string_ostream(name) << llvm::format_hex_no_prefix(h.high64, 16)
                                 << llvm::format_hex_no_prefix(h.low64, 16) << ".oslk";
  llvm::SmallString<256> path(directory);
  llvm::sys::path::append(path, name);
  return path.str().str();
}

CacheLookup KernelCache::lookup(llvm::StringRef key, CachedKernel &entry) const {
  std::string path = pathFor(key);
  if (!llvm::sys::fs::exists(path))
    return CacheLookup::Miss;
  auto file = llvm::MemoryBuffer::getFile(path, /*IsText=*/false,
                                          /*RequiresNullTerminator=*/false);
  if (!file)
    return CacheLookup::Corrupt;
  llvm::StringRef data = (*file)->getBuffer();
  uint64_t checksum;
  if (data.size() < sizeof kMagic + sizeof checksum ||
      std::memcmp(data.data(), kMagic, sizeof kMagic) != 0)
    return CacheLookup::Corrupt;
  llvm::StringRef body = data.drop_back(sizeof checksum);
  std::memcpy(&checksum, body.end(), sizeof checksum);
  if (llvm::xxh3_64bits(body) != checksum)
    return CacheLookup::Corrupt;

  FieldReader reader{body.drop_front(sizeof kMagic)};
  llvm::StringRef storedKey, name, outputs, object, libraries, warnings, reports;
  if (!reader.next(storedKey) || !reader.next(name) || !reader.next(outputs) ||
      !reader.next(object) || !reader.next(libraries) || !reader.next(warnings) ||
      !reader.next(reports) || !reader.rest.empty())
    return CacheLookup::Corrupt;
  if (storedKey != key)
    return CacheLookup::Corrupt; // a hash collision or a foreign file
  entry = CachedKernel();
  if (!parseOutputs(outputs, entry.outputs) || object.empty())
    return CacheLookup::Corrupt;
  entry.shaderName = name.str();
  entry.object = object.str();
  for (FieldReader each{libraries}; !each.rest.empty();) {
    llvm::StringRef library;
    if (!each.next(library) || library.empty())
      return CacheLookup::Corrupt;
    entry.libraries.push_back(library.str());
  }
  entry.warnings = warnings.str();
  entry.reports = reports.str();
  return CacheLookup::Hit;
}

bool KernelCache::store(llvm::StringRef key, const CachedKernel &entry, std::string &error) const {
  if (std::error_code ec = llvm::sys::fs::create_directories(directory)) {
    error = "cannot create '" + directory + "': " + ec.message();
    return false;
  }
  std::string data(kMagic, sizeof kMagic);
  putField(data, key);
  putField(data, entry.shaderName);
  putField(data, outputsText(entry.outputs));
  putField(data, entry.object);
  std::string libraries;
  for (const std::string &library : entry.libraries)
    putField(libraries, library);
  putField(data, libraries);
  putField(data, entry.warnings);
  putField(data, entry.reports);
  uint64_t checksum = llvm::xxh3_64bits(data);
  data.append(reinterpret_cast<const char *>(&checksum), sizeof checksum);

  std::string path = pathFor(key);
  llvm::SmallString<256> temp;
  int fd;
  if (std::error_code ec = llvm::sys::fs::createUniqueFile(path + ".%%%%%%.tmp", fd, temp)) {
    error = "cannot write in '" + directory + "': " + ec.message();
    return false;
  }
  {
    llvm::raw_fd_ostream os(fd, /*shouldClose=*/true);
    os << data;
    os.close();
    if (os.has_error()) {
      error = "cannot write '" + temp.str().str() + "': " + os.error().message();
      os.clear_error();
      llvm::sys::fs::remove(temp);
      return false;
    }
  }
  if (std::error_code ec = llvm::sys::fs::rename(temp, path)) {
    error = "cannot write '" + path + "': " + ec.message();
    llvm::sys::fs::remove(temp);
    return false;
  }
  return true;
}
