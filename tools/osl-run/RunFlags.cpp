//===- RunFlags.cpp - osl-run's flags, one handler each -------------------===//
//
// testshade's flags, so conformance commands run unchanged (-g X Y, -o NAME
// FILE, --param NAME VALUE, --shader, --connect, ...), testrender's for
// --scene (-r, -aa, --seed, --path), and osl-run's own. The handlers are
// grouped as kUsage lists the flags.
//
//===----------------------------------------------------------------------===//
#include "RunFlags.h"
#include "OslFrontend/Frontend.h"

#include "llvm/ADT/STLExtras.h"
#include "llvm/Support/FileSystem.h"
#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/Path.h"

#include <cmath>
#include <cstdlib>
#include <cstring>

using namespace osl;

bool osl::parseInt(const char *text, int &out) {
  char *end = nullptr;
  long v = std::strtol(text, &end, 10);
  if (!*text || *end || v < -(1L << 30) || v > (1L << 30))
    return false;
  out = int(v);
  return true;
}

std::string osl::shaderFile(std::string name) {
  if (llvm::StringRef(name).ends_with(".osl") || llvm::sys::fs::is_regular_file(name))
    return name;
  if (llvm::sys::fs::is_regular_file(name + ".osl"))
    // Keep the path as given: messages name the file as testshade's do.
    return name + ".osl";
  // Else a source in NAME's directory declaring shader NAME.
  llvm::StringRef dir = llvm::sys::path::parent_path(name);
  std::string found = findShaderSource(llvm::sys::path::filename(name),
                                       {dir.empty() ? std::string(".") : dir.str()});
  return found.empty() ? name + ".osl" : found;
}

namespace {

/// "1 0 0" -> "1,0,0": testshade's typed values may be space-separated.
std::string numberList(std::string value) {
  std::string out;
  bool gap = false;
  for (char c : value) {
    if (c == ' ' || c == ',') {
      gap = !out.empty();
      continue;
    }
    if (gap)
      out += ',';
    gap = false;
    out += c;
  }
  return out;
}

/// A whole number in (0, limit] from the next argument, else `message`.
bool positiveLong(FlagParser &p, long limit, int &out, const char *what) {
  if (!p.need(1))
    return false;
  char *end = nullptr;
  long v = std::strtol(p.next(), &end, 10);
  if (!end || *end || v <= 0 || v > limit)
    return p.fail(p.flag + " needs a whole number of " + what + " above 0 (got '" +
                  std::string(p.argv[p.i]) + "')");
  out = int(v);
  return true;
}

/// A flag whose value follows it or is attached to it after `prefix`
/// ("--width=", "-I"); "" if there is none.
std::string attachedOrNext(FlagParser &p, const char *prefix) {
  size_t n = std::strlen(prefix);
  if (p.flag.size() > n && p.flag.rfind(prefix, 0) == 0)
    return p.flag.substr(n);
  return p.need(1) ? std::string(p.next()) : std::string();
}

//===----------------------------------------------------------------------===//
// --scene (testrender's)
//===----------------------------------------------------------------------===//

bool sceneFlag(FlagParser &p) {
  if (!p.need(1))
    return false;
  p.o.scenePath = p.next();
  return true;
}

/// -expr: a shader made of one statement, as testshade's.
bool exprFlag(FlagParser &p) {
  if (!p.need(1))
    return false;
  if (!p.o.shaderPath.empty() || !p.o.expression.empty()) {
    p.error = "-expr makes the shader: no other shader can be given";
    return false;
  }
  p.o.expression = p.next();
  p.o.shaderPath = std::string(kExprShaderName) + ".osl";
  return true;
}

bool pathFlag(FlagParser &p) {
  if (!p.need(1))
    return false;
  p.o.shaderDirs.push_back(p.next());
  return true;
}

bool resolutionFlag(FlagParser &p) {
  RunOptions &o = p.o;
  if (!p.need(2) || !parseInt(p.argv[p.i + 1], o.renderX) ||
      !parseInt(p.argv[p.i + 2], o.renderY) || o.renderX < 1 || o.renderY < 1 ||
      o.renderX > 65536 || o.renderY > 65536)
    return p.fail("-r needs two positive integers");
  p.i += 2;
  return true;
}

bool antialiasFlag(FlagParser &p) {
  if (!p.need(1) || !parseInt(p.next(), p.o.aa) || p.o.aa < 1 || p.o.aa > 1024)
    return p.fail("-aa needs a positive count (N x N paths per pixel)");
  return true;
}

bool seedFlag(FlagParser &p) {
  if (!p.need(1) || !parseInt(p.next(), p.o.seed))
    return p.fail("--seed needs an integer");
  return true;
}

//===----------------------------------------------------------------------===//
// Shading a grid
//===----------------------------------------------------------------------===//

bool gridFlag(FlagParser &p) {
  RunOptions &o = p.o;
  if (!p.need(2, "-g"))
    return false;
  if (!parseInt(p.argv[p.i + 1], o.grid.xres) || !parseInt(p.argv[p.i + 2], o.grid.yres) ||
      o.grid.xres < 1 || o.grid.yres < 1)
    return p.fail("-g needs two positive integers");
  o.gridGiven = true;
  p.i += 2;
  return true;
}

/// A finite float (no trailing text).
bool parseFiniteFloat(const char *text, float &out) {
  char *end = nullptr;
  float v = std::strtof(text, &end);
  if (!*text || *end || !std::isfinite(v))
    return false;
  out = v;
  return true;
}

/// testshade's --scaleuv U V and --offsetst U V: u = U * u0 + offset.
template <float GridOptions::*U, float GridOptions::*V> bool uvPairFlag(FlagParser &p) {
  if (!p.need(2))
    return false;
  if (!parseFiniteFloat(p.argv[p.i + 1], p.o.grid.*U) ||
      !parseFiniteFloat(p.argv[p.i + 2], p.o.grid.*V))
    return p.fail(p.flag + " needs two finite numbers");
  p.i += 2;
  return true;
}

/// testshade 1.13's --offsetuv reads its two numbers and stores them
/// nowhere (its hidden old name, --offsetst, offsets): the same images
/// need the same, said aloud.
bool ignoredOffsetFlag(FlagParser &p) {
  float u = 0, v = 0;
  if (!p.need(2))
    return false;
  if (!parseFiniteFloat(p.argv[p.i + 1], u) || !parseFiniteFloat(p.argv[p.i + 2], v))
    return p.fail(p.flag + " needs two finite numbers");
  llvm::errs() << "osl-run: warning: --offsetuv is ignored, as testshade 1.13 ignores it; "
                  "--offsetst U V offsets u and v\n";
  p.i += 2;
  return true;
}

bool cropFlag(FlagParser &p) {
  if (!p.need(4))
    return false;
  for (int k = 0; k < 4; ++k)
    if (!parseInt(p.argv[p.i + 1 + k], p.o.crop[k]) || p.o.crop[k] < 0)
      return p.fail("--crop needs four integers X0 Y0 X1 Y1 of at least 0");
  p.o.cropGiven = true;
  p.i += 4;
  return true;
}

/// -o NAME FILE, or -o FILE with --scene.
bool outputFlag(FlagParser &p) {
  if (p.render) {
    if (!p.need(1))
      return false;
    p.o.sceneOutput = p.next();
    return true;
  }
  if (!p.need(2))
    return false;
  p.o.outputs.push_back({p.argv[p.i + 1], p.argv[p.i + 2]});
  p.i += 2;
  return true;
}

bool dataTypeFlag(FlagParser &p) { // -d: testshade's older spelling of -od
  if (!p.need(1, "-od"))
    return false;
  std::string &type = p.o.dataType;
  type = p.next();
  if (type != "float" && type != "half" && type != "uint8" && type != "uint16")
    return p.fail("-od must be float, half, uint8 or uint16 (got '" + type + "')");
  return true;
}

/// --param NAME VALUE, also --param:type=T:lockgeom=0 NAME VALUE.
bool paramFlag(FlagParser &p) {
  if (!p.need(2, "--param"))
    return false;
  std::string type, value = p.argv[p.i + 2];
  bool userdata = false;
  llvm::SmallVector<llvm::StringRef> annotations;
  llvm::StringRef(p.flag).split(annotations, ':');
  for (llvm::StringRef note : llvm::ArrayRef(annotations).drop_front()) {
    auto [key, v] = note.split('=');
    if (key == "type")
      type = v.str();
    else if (key == "lockgeom")
      userdata = v == "0";
  }
  if (!type.empty() && type != "string")
    value = numberList(value);
  p.o.compile.params.push_back({p.argv[p.i + 1], value});
  p.o.group.param(p.argv[p.i + 1], value, userdata);
  p.i += 2;
  return true;
}

/// --userdata[:type=T] NAME VALUE: per-geometry data on every point.
bool userdataFlag(FlagParser &p) {
  if (!p.need(2, "--userdata"))
    return false;
  UserDatum d{p.argv[p.i + 1], "", p.argv[p.i + 2]};
  llvm::StringRef note = llvm::StringRef(p.flag).drop_front(std::strlen("--userdata"));
  if (note.consume_front(":type=")) {
    d.type = note.str();
  } else if (!note.empty()) {
    return p.fail("unknown annotation in '" + p.flag + "' (expected --userdata:type=T)");
  } else {
    // No type: an int, a float or else a string, as the value reads.
    llvm::StringRef v(d.value);
    long long n;
    double x;
    d.type = !v.getAsInteger(10, n) ? "int" : !v.getAsDouble(x) ? "float" : "string";
  }
  static const char *const kTypes[] = {"int",    "float",  "color", "point",
                                       "vector", "normal", "string"};
  if (!llvm::is_contained(kTypes, d.type))
    return p.fail("--userdata: unknown type '" + d.type +
                  "' (int, float, color, point, vector, normal or string)");
  if (d.type != "string") {
    d.value = numberList(d.value);
    llvm::SmallVector<llvm::StringRef> items;
    llvm::StringRef(d.value).split(items, ',');
    double x;
    bool triple = d.type != "int" && d.type != "float";
    bool ok = items.size() == 1 || (triple && items.size() == 3);
    for (llvm::StringRef item : items)
      ok = ok && !item.getAsDouble(x);
    if (!ok)
      return p.fail("--userdata: '" + std::string(p.argv[p.i + 2]) + "' is not " +
                    (triple ? "one or three numbers" : "a number") + " for type " + d.type);
  }
  p.o.compile.userData.push_back(d);
  p.i += 2;
  return true;
}

/// testshade's --options: error_repeats, lazyglobals, lazyerror,
/// opt_warnings and llvm_debug_layers change what runs; the others are
/// taken.
bool shadingSystemOptionsFlag(FlagParser &p) {
  if (!p.need(1))
    return false;
  llvm::SmallVector<llvm::StringRef> settings;
  llvm::StringRef(p.next()).split(settings, ',');
  for (llvm::StringRef setting : settings) {
    auto [name, value] = setting.split('=');
    if (name.trim() == "error_repeats")
      p.o.errorRepeats = value.trim() != "0";
    else if (name.trim() == "lazyglobals")
      p.o.group.lazyGlobals = value.trim() != "0";
    else if (name.trim() == "llvm_debug_layers")
      p.o.group.traceLayers = value.trim() != "0";
    else if (name.trim() == "lazyerror")
      p.o.compile.lazyError = value.trim() != "0";
    else if (name.trim() == "opt_warnings")
      p.o.compile.optimizationWarnings = value.trim() != "0";
  }
  return true;
}

/// A testshade flag with one argument that changes nothing here (its
/// LLVM optimization level, the message journal's size).
bool ignoredWithArgument(FlagParser &p) {
  if (!p.need(1))
    return false;
  ++p.i;
  return true;
}

/// A testshade flag that changes nothing here: --inbuffer (osl-run always
/// compiles text it has read), --batched (osl-run always shades in
/// batches), --groupoutputs (-o names the group's outputs anyway),
/// --raytype_opt (kernels are specialised on the ray type anyway).
bool ignored(FlagParser &) { return true; }

bool threadsFlag(FlagParser &p) {
  if (!p.need(1) || !parseInt(p.next(), p.o.grid.threads) || p.o.grid.threads < 0)
    return p.fail("-t needs a thread count (0 = all cores)");
  // -t 1 compiles on one thread too (as OSL does, which bench/vs_osl.py
  // compares against).
  p.o.compile.compileThreads = p.o.grid.threads;
  return true;
}

bool itersFlag(FlagParser &p) {
  if (!p.need(1) || !parseInt(p.next(), p.o.iters) || p.o.iters < 1)
    return p.fail("--iters needs a positive count");
  return true;
}

/// oslc's -M, -MM (print the make dependencies), -MD, -MMD (write them).
bool dependenciesFlag(FlagParser &p) {
  RunOptions::Dependencies &d = p.o.dependencies;
  bool write = p.flag.back() == 'D';
  (write ? d.write : d.print) = true;
  d.standardHeaders = p.flag.rfind("-MM", 0) != 0;
  return true;
}

/// -MF FILE or -MFFILE.
bool dependencyFileFlag(FlagParser &p) {
  p.o.dependencies.file = attachedOrNext(p, "-MF");
  return !p.o.dependencies.file.empty() || p.fail("-MF needs a file name");
}

/// -MT TARGET or -MTTARGET.
bool dependencyTargetFlag(FlagParser &p) {
  p.o.dependencies.target = attachedOrNext(p, "-MT");
  return !p.o.dependencies.target.empty() || p.fail("-MT needs a target name");
}

/// A flag that stores its one argument in a compile option.
template <std::string CompileOptions::*Field> bool compileStringFlag(FlagParser &p) {
  if (!p.need(1))
    return false;
  p.o.compile.*Field = p.next();
  return true;
}

//===----------------------------------------------------------------------===//
// Shader groups
//===----------------------------------------------------------------------===//

bool layerFlag(FlagParser &p) {
  if (!p.need(1))
    return false;
  p.pendingLayer = p.next();
  return true;
}

bool shaderFlag(FlagParser &p) {
  if (!p.need(2) || !p.o.group.shader(shaderFile(p.argv[p.i + 1]), p.argv[p.i + 2], p.error)) {
    if (p.error.empty())
      p.error = "--shader needs 2 arguments";
    return false;
  }
  p.o.group.layers.back().shaderName = p.argv[p.i + 1];
  p.o.isGroup = true;
  p.i += 2;
  return true;
}

bool connectFlag(FlagParser &p) {
  char **a = p.argv + p.i;
  if (!p.need(4))
    return false;
  p.o.group.connect({a[1], a[2], a[3], a[4], ""});
  p.i += 4;
  return true;
}

/// --group FILE or --group "statements;".
bool groupFlag(FlagParser &p) {
  if (!p.need(1))
    return false;
  std::string text = p.next(), dir;
  if (auto file = llvm::MemoryBuffer::getFile(text, /*IsText=*/true)) {
    dir = llvm::sys::path::parent_path(text).str();
    text = (*file)->getBuffer().str();
  } else if (text.find_first_of(";,") == std::string::npos) {
    return p.fail("--group: cannot read '" + text + "': " + file.getError().message() +
                  " (statements end in ';' or ',')");
  }
  if (!p.o.group.parseStatements(text, dir, p.error))
    return false;
  p.o.groupSpec = text;
  // testshade makes a group of its own before the spec's, so OSL names
  // the spec's group unnamed_group_2 in its messages.
  if (p.o.compile.groupName.empty())
    p.o.compile.groupName = "unnamed_group_2";
  p.o.isGroup = true;
  return true;
}

/// --reparam LAYER NAME VALUE (also testshade's --reparam:type=T:..., whose
/// type is the parameter's own).
bool reparamFlag(FlagParser &p) {
  if (!p.need(3, "--reparam"))
    return false;
  p.o.reparams.push_back({p.argv[p.i + 1], p.argv[p.i + 2], p.argv[p.i + 3]});
  p.i += 3;
  return true;
}

bool entryFlag(FlagParser &p) {
  if (!p.need(1))
    return false;
  p.o.group.entries.push_back(p.next());
  return true;
}

bool entryOutputFlag(FlagParser &p) {
  if (!p.need(1))
    return false;
  p.o.group.entryOutputs.push_back(p.next());
  return true;
}

bool optimizationFlag(FlagParser &p) { // -O0, -O1, -O2
  p.o.group.optimization = GroupOptimization(p.flag[2] - '0');
  return true;
}

//===----------------------------------------------------------------------===//
// Compiling
//===----------------------------------------------------------------------===//

bool widthFlag(FlagParser &p) {
  int &width = p.o.compile.width;
  std::string v = attachedOrNext(p, "--width=");
  if (!parseInt(v.c_str(), width) || (width != 1 && width != 4 && width != 8 && width != 16))
    return p.fail("--width must be 1, 4, 8 or 16");
  return true;
}

bool mathFlag(FlagParser &p) {
  if (p.flag == "--math" && !p.need(1))
    return false;
  std::string v = attachedOrNext(p, "--math=");
  auto level = mlir::osl::parseMathLevel(v);
  if (!level)
    return p.fail("--math must be fast, default, precise or double (got '" + v + "')");
  p.o.compile.math = *level;
  return true;
}

bool includeFlag(FlagParser &p) { // -I DIR or -IDIR
  std::string dir = attachedOrNext(p, "-I");
  if (dir.empty())
    return false;
  p.o.compile.includePaths.push_back(dir);
  return true;
}

/// oslc's -D NAME[=VALUE] and -U NAME (also attached: -DNAME).
bool macroFlag(FlagParser &p) {
  std::string flag = p.flag.substr(0, 2);
  if (p.flag.size() == 2 && !p.need(1, flag.c_str()))
    return false;
  std::string macro = p.flag.size() == 2 ? std::string(p.next()) : p.flag.substr(2);
  p.o.compile.defines.push_back(flag == "-U" ? "-" + macro : macro);
  return true;
}

bool llvmPipelineFlag(FlagParser &p) {
  std::string v = p.flag.substr(std::strlen("--llvm-pipeline="));
  if (v != "kernel" && v != "O3")
    return p.fail("--llvm-pipeline must be kernel or O3");
  p.o.compile.llvmPipeline = v == "O3" ? LlvmPipeline::O3 : LlvmPipeline::Kernel;
  return true;
}

bool emitFlag(FlagParser &p) {
  p.o.emit = p.flag.substr(std::strlen("--emit="));
  const std::string &e = p.o.emit;
  if (e != "mlir" && e != "lowered" && e != "llvm" && e != "asm")
    return p.fail("--emit must be mlir, lowered, llvm or asm");
  return true;
}

//===----------------------------------------------------------------------===//
// Running
//===----------------------------------------------------------------------===//

bool timeoutFlag(FlagParser &p) {
  return positiveLong(p, 1000000, p.o.timeoutSeconds, "seconds");
}

bool imageMemoryFlag(FlagParser &p) {
  return positiveLong(p, 1L << 30, p.o.imageMemoryMB, "megabytes");
}

bool textureCacheFlag(FlagParser &p) {
  if (!p.need(1) || !parseInt(p.next(), p.o.textureCacheMB) || p.o.textureCacheMB < 1)
    return p.fail("--texture-cache-mb needs a positive size in MB");
  return true;
}

bool cacheDirFlag(FlagParser &p) {
  if (!p.need(1))
    return false;
  p.o.compile.cacheDir = p.next();
  if (p.o.compile.cacheDir.empty())
    return p.fail("--cache-dir needs a directory");
  p.o.cacheDirGiven = true;
  return true;
}

bool helpFlag(FlagParser &p) {
  p.error = "";
  return false;
}

/// A flag that only sets `field`.
template <bool RunOptions::*Field> bool setFlag(FlagParser &p) {
  p.o.*Field = true;
  return true;
}
template <bool CompileOptions::*Field> bool setCompileFlag(FlagParser &p) {
  p.o.compile.*Field = true;
  return true;
}
template <bool GridOptions::*Field> bool setGridFlag(FlagParser &p) {
  p.o.grid.*Field = true;
  return true;
}

bool noWarningsFlag(FlagParser &p) {
  p.o.compile.showWarnings = false;
  return true;
}

//===----------------------------------------------------------------------===//
// The table
//===----------------------------------------------------------------------===//

/// Up to six spellings of one flag (the rest null) and its handler.
struct Flag {
  const char *names[6];
  FlagHandler handle;
};

const Flag kFlags[] = {
    // --scene
    {{"--scene"}, sceneFlag},
    {{"--path"}, pathFlag},
    {{"-r"}, resolutionFlag},
    {{"-aa"}, antialiasFlag},
    {{"--seed"}, seedFlag},
    // Shading a grid
    {{"-g", "--g", "--res"}, gridFlag},
    {{"--crop"}, cropFlag},
    {{"-o"}, outputFlag},
    {{"--od", "-d"}, dataTypeFlag},
    {{"--param"}, paramFlag},
    {{"--userdata"}, userdataFlag},
    {{"--userdata_isconnected"}, setCompileFlag<&CompileOptions::userdataIsConnected>},
    {{"--options"}, shadingSystemOptionsFlag},
    {{"--llvm_opt", "--jbufferMB"}, ignoredWithArgument},
    {{"--expr"}, exprFlag},
    {{"-v"}, setFlag<&RunOptions::verbose>},
    {{"--oslquery"}, setFlag<&RunOptions::oslquery>},
    {{"--debug"}, setCompileFlag<&CompileOptions::reportGlobalsNeeded>},
    {{"--inbuffer", "--batched", "--groupoutputs", "--raytype_opt"}, ignored},
    {{"-t"}, threadsFlag},
    {{"--iters"}, itersFlag},
    {{"--center"}, setGridFlag<&GridOptions::center>},
    {{"--scaleuv"}, uvPairFlag<&GridOptions::uscale, &GridOptions::vscale>},
    {{"--offsetst"}, uvPairFlag<&GridOptions::uoffset, &GridOptions::voffset>},
    {{"--offsetuv"}, ignoredOffsetFlag},
    {{"--vary_udxdy"}, setGridFlag<&GridOptions::varyUdxdy>},
    {{"--vary_vdxdy"}, setGridFlag<&GridOptions::varyVdxdy>},
    {{"--vary_pdxdy"}, setGridFlag<&GridOptions::varyPdxdy>},
    {{"--print"}, setFlag<&RunOptions::printValues>},
    {{"--keep-going"}, setFlag<&RunOptions::keepGoing>},
    // Shader groups
    {{"--layer"}, layerFlag},
    {{"--shader"}, shaderFlag},
    {{"--connect"}, connectFlag},
    {{"--group"}, groupFlag},
    {{"--reparam"}, reparamFlag},
    {{"--entry"}, entryFlag},
    {{"--entryoutput"}, entryOutputFlag},
    {{"--groupname"}, compileStringFlag<&CompileOptions::groupName>},
    {{"-O0", "-O1", "-O2"}, optimizationFlag},
    // Compiling
    {{"--width"}, widthFlag},
    {{"--math"}, mathFlag},
    {{"--interpret"}, setCompileFlag<&CompileOptions::reference>},
    {{"--verify-each"}, setCompileFlag<&CompileOptions::verifyEachPass>},
    {{"--lane-stats"}, setCompileFlag<&CompileOptions::countLanes>},
    {{"-Werror"}, setCompileFlag<&CompileOptions::warningsAsErrors>},
    {{"--debugnan"}, setCompileFlag<&CompileOptions::debugNan>},
    {{"-w"}, noWarningsFlag},
    {{"-I"}, includeFlag},
    {{"-D", "-U"}, macroFlag},
    {{"--raytype"}, compileStringFlag<&CompileOptions::rayType>},
    {{"--colorspace"}, compileStringFlag<&CompileOptions::colorSpace>},
    // Running
    {{"--check"}, setFlag<&RunOptions::checkOnly>},
    {{"-M", "-MM", "-MD", "-MMD"}, dependenciesFlag},
    {{"--info"}, setFlag<&RunOptions::infoOnly>},
    {{"--info-json"}, setFlag<&RunOptions::infoJson>},
    {{"--timeout"}, timeoutFlag},
    {{"--image-memory"}, imageMemoryFlag},
    {{"--texture-cache-mb"}, textureCacheFlag},
    {{"--cache-dir"}, cacheDirFlag},
    {{"--no-cache"}, setFlag<&RunOptions::noCache>},
    {{"--inline-library"}, setCompileFlag<&CompileOptions::inlineLibrary>},
    {{"--outline-every-routine"}, setCompileFlag<&CompileOptions::outlineEveryRoutine>},
    {{"--stats"}, setFlag<&RunOptions::stats>},
    {{"--time-kernels"}, setFlag<&RunOptions::timeKernels>},
    {{"-h", "--help"}, helpFlag},
};

/// Flags written with their value attached, matched by prefix.
const Flag kPrefixFlags[] = {
    {{"--param:"}, paramFlag},
    {{"--userdata:"}, userdataFlag},
    {{"--reparam:"}, reparamFlag},
    {{"--width="}, widthFlag},
    {{"--math="}, mathFlag},
    {{"--llvm-pipeline="}, llvmPipelineFlag},
    {{"--emit="}, emitFlag},
    {{"-I"}, includeFlag},
    {{"-D", "-U"}, macroFlag},
    {{"-MF"}, dependencyFileFlag},
    {{"-MT"}, dependencyTargetFlag},
};

} // namespace

FlagHandler osl::findFlag(const std::string &flag) {
  for (const Flag &f : kFlags)
    for (const char *name : f.names)
      if (name && flag == name)
        return f.handle;
  for (const Flag &f : kPrefixFlags)
    for (const char *name : f.names)
      if (name && flag.rfind(name, 0) == 0)
        return f.handle;
  return nullptr;
}
