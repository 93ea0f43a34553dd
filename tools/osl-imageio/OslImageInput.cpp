//===- OslImageInput.cpp - Shaders read as images by OpenImageIO ----------===//
//
// osl.imageio.so: an OpenImageIO plugin that makes a shader an image, as
// OSL's own plugin does, so any OpenImageIO program (oiiotool, a texture
// system) can read "NAME.osl?RES=256&MIP=1&color base=1,0,0". The name is
//   NAME.osl        a shader's source;
//   NAME.oso        the shader oslc would have compiled to NAME.oso
//                   (osl-mlir compiles from source: osl-run finds NAME.osl
//                   or the source declaring NAME);
//   BODY.oslbody    the statements of a shader with s, t, output color
//                   result and output float alpha (osl-run -expr's);
//   FILE.oslgroup   a serialized shader group, in a file or inline.
// Options after '?', '&'-separated: RES=WxH (default 1024x1024), TILE=WxH,
// MIP=1 (every MIP level, each shaded at its own resolution), OUTPUT=NAME
// (repeatable; default result then alpha); anything else is a parameter,
// "[type] name=value" with comma-separated components.
//
// The image has 4 float channels filled by the outputs in order. Pixels
// are shaded at their centres by osl-run, once per MIP level when it is
// first read: the plugin runs osl-run (OSLMLIR_OSL_RUN, else ../bin/osl-run
// beside this plugin, else PATH) rather than linking the compiler, so
// OpenImageIO programs load it in milliseconds.
//
//===----------------------------------------------------------------------===//
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/strutil.h>

#include <dlfcn.h>
#include <fcntl.h>
#include <limits.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

extern char **environ;

using namespace OIIO;

namespace {

constexpr int kChannels = 4;

/// "NAME?a=1&b=2" split into NAME and its (id, value) options; a quoted
/// value may hold '&'.
std::string splitUri(const std::string &uri,
                     std::vector<std::pair<std::string, std::string>> &options) {
  size_t query = uri.find('?');
  if (query == std::string::npos)
    return uri;
  string_view rest = string_view(uri).substr(query + 1);
  while (!rest.empty()) {
    string_view id = Strutil::parse_until(rest, "=&");
    if (id.empty() || !Strutil::parse_char(rest, '=') || rest.empty())
      break;
    string_view value;
    if (rest.front() == '"')
      Strutil::parse_string(rest, value, true, Strutil::KeepQuotes);
    else
      value = Strutil::parse_until(rest, "&");
    options.emplace_back(std::string(id), std::string(value));
    Strutil::parse_char(rest, '&');
  }
  return uri.substr(0, query);
}

bool parseResolution(string_view text, int &x, int &y) {
  int a = 0, b = 0;
  if (!Strutil::parse_int(text, a) || a < 1)
    return false;
  b = a;
  if (Strutil::parse_char(text, 'x') && (!Strutil::parse_int(text, b) || b < 1))
    return false;
  x = a;
  y = b;
  return true;
}

enum class ShaderKind { Source, Compiled, Body, Group, None };

ShaderKind kindOf(const std::string &name) {
  if (Strutil::ends_with(name, ".osl"))
    return ShaderKind::Source;
  if (Strutil::ends_with(name, ".oso"))
    return ShaderKind::Compiled;
  if (Strutil::ends_with(name, ".oslbody"))
    return ShaderKind::Body;
  if (Strutil::ends_with(name, ".oslgroup"))
    return ShaderKind::Group;
  return ShaderKind::None;
}

/// osl-run: named by OSLMLIR_OSL_RUN, else ../bin/osl-run from the folder
/// this plugin was loaded from, else found on PATH by posix_spawnp.
std::string oslRunPath() {
  if (const char *named = std::getenv("OSLMLIR_OSL_RUN"); named && *named)
    return named;
  Dl_info info;
  char resolved[PATH_MAX];
  if (dladdr(reinterpret_cast<void *>(&oslRunPath), &info) && info.dli_fname &&
      realpath(info.dli_fname, resolved)) {
    std::string beside =
        Filesystem::parent_path(Filesystem::parent_path(resolved)) + "/bin/osl-run";
    if (Filesystem::exists(beside))
      return beside;
  }
  return "osl-run";
}

/// Runs `args` and waits; false with its standard error in `error` when it
/// cannot start or exits non-zero.
bool runTool(const std::vector<std::string> &args, const std::string &errorFile,
             std::string &error) {
  std::vector<char *> argv;
  for (const std::string &a : args)
    argv.push_back(const_cast<char *>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&files, 2, errorFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0600);
  pid_t pid = 0;
  int spawned = posix_spawnp(&pid, argv[0], &files, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  if (spawned != 0) {
    error = "cannot run " + args[0] + ": " + std::strerror(spawned) +
            " (set OSLMLIR_OSL_RUN to osl-run's path)";
    return false;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0)
    return true;
  std::ifstream text(errorFile);
  std::stringstream message;
  message << text.rdbuf();
  error = Strutil::strip(message.str());
  if (error.empty())
    error = args[0] + " failed";
  return false;
}

class OslImageInput final : public ImageInput {
public:
  ~OslImageInput() override { close(); }
  const char *format_name() const override { return "osl"; }
  int supports(string_view feature) const override {
    return feature == "procedural" || feature == "tiles" || feature == "mipmap";
  }
  bool valid_file(const std::string &filename) const override {
    std::vector<std::pair<std::string, std::string>> options;
    return kindOf(splitUri(filename, options)) != ShaderKind::None;
  }
  bool open(const std::string &name, ImageSpec &newspec) override;
  bool close() override;
  int current_subimage() const override { return 0; }
  int current_miplevel() const override { return level; }
  bool seek_subimage(int subimage, int miplevel) override;
  bool read_native_scanline(int subimage, int miplevel, int y, int z, void *data) override {
    return read_native_scanlines(subimage, miplevel, y, y + 1, z, data);
  }
  bool read_native_scanlines(int subimage, int miplevel, int ybegin, int yend, int z,
                             void *data) override;
  bool read_native_tile(int subimage, int miplevel, int x, int y, int z, void *data) override;

private:
  /// The shading command for a `width` x `height` image, its outputs
  /// written under `dir`.
  std::vector<std::string> command(int width, int height, const std::string &dir) const;
  /// Shades MIP level `miplevel` (m_spec's size) unless it already is.
  bool shadeLevel(int miplevel);
  /// Copies pixels [x0,x1) x [y0,y1) of the current level to `data`.
  bool copyPixels(int miplevel, int x0, int x1, int y0, int y1, void *data);

  ImageSpec top;
  std::vector<std::string> shaderArgs, paramArgs, outputs;
  bool mipmapped = false;
  int level = -1;
  std::map<int, std::vector<float>> levels; // shaded pixels per MIP level
};

bool OslImageInput::open(const std::string &name, ImageSpec &newspec) {
  close();
  std::vector<std::pair<std::string, std::string>> options;
  std::string shader = splitUri(name, options);
  ShaderKind kind = kindOf(shader);
  if (kind == ShaderKind::None) {
    errorfmt("\"{}\" is not a shader (.osl, .oso, .oslbody or .oslgroup)", shader);
    return false;
  }
  top = ImageSpec(1024, 1024, kChannels, TypeDesc::FLOAT);
  for (auto &[id, value] : options) {
    if (id == "RES") {
      if (!parseResolution(value, top.width, top.height)) {
        errorfmt("RES must be N or WxH, got \"{}\"", value);
        return false;
      }
    } else if (id == "TILE" || id == "TILES") {
      if (!parseResolution(value, top.tile_width, top.tile_height)) {
        errorfmt("TILE must be N or WxH, got \"{}\"", value);
        return false;
      }
      top.tile_depth = 1;
    } else if (id == "MIP") {
      mipmapped = Strutil::stoi(value) != 0;
    } else if (id == "OUTPUT") {
      outputs.push_back(value);
    } else {
      // "[type] name=value": a parameter; the value's components are
      // comma-separated, a string value may be quoted.
      size_t space = id.find_last_of(' ');
      std::string param = space == std::string::npos ? id : id.substr(space + 1);
      std::string type = space == std::string::npos ? "" : Strutil::strip(id.substr(0, space));
      std::string flag = type.empty() ? "--param" : "--param:type=" + type;
      std::string v = value;
      if (v.size() >= 2 && v.front() == '"' && v.back() == '"')
        v = v.substr(1, v.size() - 2);
      paramArgs.insert(paramArgs.end(), {flag, param, v});
    }
  }
  if (outputs.empty())
    outputs = {"result", "alpha"};
  top.full_width = top.width;
  top.full_height = top.height;
  switch (kind) {
  case ShaderKind::Source:
    shaderArgs = {shader};
    break;
  case ShaderKind::Compiled:
    shaderArgs = {shader.substr(0, shader.size() - 4)};
    break;
  case ShaderKind::Body:
    shaderArgs = {"-expr", shader.substr(0, shader.size() - 8)};
    break;
  case ShaderKind::Group: {
    // A file, else the statements themselves before the suffix.
    std::string text;
    if (!Filesystem::read_text_file(shader, text))
      text = shader.substr(0, shader.size() - 9);
    shaderArgs = {"--group", text};
    break;
  }
  case ShaderKind::None:
    break;
  }
  // Shading the top level now reports a shader that does not compile at
  // open, where programs expect errors; smaller levels wait to be read.
  if (!seek_subimage(0, 0) || !shadeLevel(0)) {
    close();
    return false;
  }
  newspec = spec();
  return true;
}

bool OslImageInput::close() {
  levels.clear();
  shaderArgs.clear();
  paramArgs.clear();
  outputs.clear();
  mipmapped = false;
  level = -1;
  return true;
}

bool OslImageInput::seek_subimage(int subimage, int miplevel) {
  if (subimage != 0 || miplevel < 0 || (miplevel > 0 && !mipmapped))
    return false;
  if (miplevel == level)
    return true;
  ImageSpec s = top;
  for (int l = 0; l < miplevel; ++l) {
    if (s.width == 1 && s.height == 1)
      return false;
    s.width = std::max(1, s.width / 2);
    s.height = std::max(1, s.height / 2);
  }
  s.full_width = s.width;
  s.full_height = s.height;
  m_spec = s;
  level = miplevel;
  return true;
}

std::vector<std::string> OslImageInput::command(int width, int height,
                                                const std::string &dir) const {
  std::vector<std::string> args = {oslRunPath(), "-w", "--center", "-g", std::to_string(width),
                                   std::to_string(height)};
  args.insert(args.end(), paramArgs.begin(), paramArgs.end());
  args.insert(args.end(), shaderArgs.begin(), shaderArgs.end());
  for (size_t i = 0; i < outputs.size(); ++i)
    args.insert(args.end(), {"-o", outputs[i], dir + "/" + std::to_string(i) + ".exr"});
  return args;
}

bool OslImageInput::shadeLevel(int miplevel) {
  if (levels.count(miplevel))
    return true;
  int width = m_spec.width, height = m_spec.height;
  std::string dir = Filesystem::temp_directory_path() + "/" +
                    Filesystem::unique_path("osl-imageio-%%%%-%%%%-%%%%");
  std::string error;
  if (!Filesystem::create_directory(dir, error)) {
    errorfmt("cannot make a folder for the shaded image: {}", error);
    return false;
  }
  bool ok = runTool(command(width, height, dir), dir + "/stderr.txt", error);
  std::vector<float> pixels(size_t(width) * height * kChannels, 0.0f);
  // Each output fills the next channels: a color three, a float one.
  int channel = 0;
  for (size_t i = 0; ok && i < outputs.size() && channel < kChannels; ++i) {
    std::string file = dir + "/" + std::to_string(i) + ".exr";
    auto in = ImageInput::open(file);
    if (!in) {
      error = "osl-run wrote no " + outputs[i] + ": " + OIIO::geterror();
      ok = false;
      break;
    }
    int n = std::min(in->spec().nchannels, kChannels - channel);
    std::vector<float> values(size_t(width) * height * in->spec().nchannels);
    ok = in->spec().width == width && in->spec().height == height &&
         in->read_image(0, 0, 0, in->spec().nchannels, TypeDesc::FLOAT, values.data());
    if (!ok)
      error = "cannot read osl-run's " + outputs[i] + ": " + in->geterror();
    for (size_t p = 0; ok && p < size_t(width) * height; ++p)
      for (int c = 0; c < n; ++c)
        pixels[p * kChannels + channel + c] = values[p * in->spec().nchannels + c];
    channel += n;
  }
  std::string removeError;
  Filesystem::remove_all(dir, removeError);
  if (!ok) {
    errorfmt("{}", error);
    return false;
  }
  levels[miplevel] = std::move(pixels);
  return true;
}

bool OslImageInput::copyPixels(int miplevel, int x0, int x1, int y0, int y1, void *data) {
  if (!shadeLevel(miplevel))
    return false;
  const std::vector<float> &pixels = levels[miplevel];
  float *out = static_cast<float *>(data);
  size_t row = size_t(x1 - x0) * kChannels;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      // A tile's part past the image's edge is zeros.
      bool inside = x < m_spec.width && y < m_spec.height;
      for (int c = 0; c < kChannels; ++c)
        out[size_t(y - y0) * row + size_t(x - x0) * kChannels + c] =
            inside ? pixels[(size_t(y) * m_spec.width + x) * kChannels + c] : 0.0f;
    }
  return true;
}

bool OslImageInput::read_native_scanlines(int subimage, int miplevel, int ybegin, int yend,
                                          int /*z*/, void *data) {
  lock_guard lock(*this);
  if (!seek_subimage(subimage, miplevel))
    return false;
  return copyPixels(miplevel, 0, m_spec.width, ybegin, yend, data);
}

bool OslImageInput::read_native_tile(int subimage, int miplevel, int x, int y, int /*z*/,
                                     void *data) {
  lock_guard lock(*this);
  if (!seek_subimage(subimage, miplevel) || m_spec.tile_width <= 0)
    return false;
  return copyPixels(miplevel, x, x + m_spec.tile_width, y, y + m_spec.tile_height, data);
}

} // namespace

// What OpenImageIO looks for in a plugin named osl.imageio.so.
OIIO_PLUGIN_EXPORTS_BEGIN
OIIO_EXPORT ImageInput *osl_input_imageio_create() { return new OslImageInput; }
OIIO_EXPORT int osl_imageio_version = OIIO_PLUGIN_VERSION;
OIIO_EXPORT const char *osl_imageio_library_version() { return "osl-mlir"; }
OIIO_EXPORT const char *osl_input_extensions[] = {"osl", "oso", "oslgroup", "oslbody", nullptr};
OIIO_PLUGIN_EXPORTS_END
