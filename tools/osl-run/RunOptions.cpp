//===- RunOptions.cpp - osl-run's command line ----------------------------===//
//
// testshade's flags, so conformance commands run unchanged: -g X Y, -o NAME
// FILE, --param NAME VALUE (also --param:type=T NAME VALUE), --center,
// --vary_udxdy/--vary_vdxdy/--vary_pdxdy, --colorspace NAME, -t N, --iters N.
//
//===----------------------------------------------------------------------===//
#include "RunOptions.h"

#include "OslCompiler/KernelCache.h"

#include "llvm/Support/FileSystem.h"
#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/Path.h"

#include <cstdlib>
#include <cstring>

using namespace osl;

const char *const osl::kUsage =
    "usage: osl-run SHADER.osl [options]\n"
    "       osl-run [--param NAME V] --shader SHADER LAYER... [--connect A OUT B IN]\n"
    "               [options]   (a shader group, see below)\n"
    "       osl-run --scene SCENE.xml -o OUT.exr [render options]\n"
    "Compiles an OSL shader and shades a grid of points with it, like\n"
    "testshade, writing each requested output as an image; or path traces\n"
    "a testrender scene whose shaders answer with closures.\n"
    "\n"
    "render options (with --scene):\n"
    "  -o FILE                the image (exr, png, tif...)\n"
    "  --path DIR             where the scene's shaders are (NAME.osl);\n"
    "                         repeatable; then the scene's folder, its\n"
    "                         shaders/ folder and the current one\n"
    "  -r W H                 resolution (default 256 256)\n"
    "  -aa N                  N x N paths per pixel (default 1)\n"
    "  --seed N               random seed (default 0)\n"
    "  --width, -t, --math, --stats, --cache-dir, --no-cache, --crop as below\n"
    "\n"
    "shading options:\n"
    "  -g X Y                 grid size (default 512 512)\n"
    "  -o NAME FILE           write output NAME to FILE (exr, tif, png...;\n"
    "                         'null' discards); default: first output to\n"
    "                         <shader>.png\n"
    "  --param NAME VALUE     set a parameter (numbers, 'a,b,c' for triples)\n"
    "  --param:type=T NAME V  the same, with testshade's type annotation\n"
    "                         (and :lockgeom=0 for per-geometry data)\n"
    "  --userdata:type=T NAME VALUE\n"
    "                         per-geometry data on every point (testshade's):\n"
    "                         getattribute(NAME) finds it, a lockgeom=0\n"
    "                         parameter NAME takes it; T is int, float,\n"
    "                         color, point, vector, normal or string\n"
    "  --userdata_isconnected isconnected() counts a lockgeom=0 parameter as\n"
    "                         connected (to the geometry)\n"
    "\n"
    "Shader groups (testshade's flags): each --param applies to the next\n"
    "--shader; the last layer is the root, whose outputs -o names (another\n"
    "layer's as LAYER.NAME).\n"
    "  --shader SHADER LAYER  add a layer (SHADER or SHADER.osl)\n"
    "  --connect A OUT B IN   layer A's output OUT feeds layer B's input IN\n"
    "  --group STATEMENTS|FILE\n"
    "                         'param TYPE NAME VALUE... ; shader NAME LAYER ;\n"
    "                         connect A.OUT B.IN ;' as a string or a file\n"
    "  --reparam LAYER NAME V change an instance value (re-specialises)\n"
    "  --entry LAYER          run LAYER unconditionally (repeatable; default:\n"
    "                         the last layer)\n"
    "  -O0 | -O1 | -O2        parameters stay loads and every layer runs |\n"
    "                         parameters are constants | also lazy layers and\n"
    "                         no unread layers or outputs (default)\n"
    "\n"
    "  --width N              lanes per batch: 1, 4, 8 or 16 (default: widest\n"
    "                         the CPU supports)\n"
    "  --math=LEVEL           how math functions are computed: default\n"
    "                         (OSL's own results), fast (the faster of OSL's\n"
    "                         and MLIR's approximations, and a*b+c fused)\n"
    "                         or precise (within 1 ULP); measured bounds in\n"
    "                         bench/MATH.md.\n"
    "                         double: precise math and all arithmetic in f64\n"
    "                         (a reference for measuring errors)\n"
    "  --center               shade pixel centres: u = (x+0.5)/X\n"
    "  -I DIR                 search DIR for #include files\n"
    "  -D NAME[=VALUE], -U NAME  define or undefine a macro, as oslc does\n"
    "  -Werror                warnings are errors, as with oslc -Werror\n"
    "  -w                     print no warnings\n"
    "  --verify-each          verify the IR after every compiler pass (for\n"
    "                         debugging the compiler; slower)\n"
    "  --timeout SECONDS      stop with an error when the run takes longer\n"
    "  --keep-going           a texture that cannot be read or a failed string\n"
    "                         call is reported but exits 0 (testshade's way;\n"
    "                         by default it makes the exit status 1)\n"
    "  --crop X0 Y0 X1 Y1     shade and write only the pixels [X0,X1) x [Y0,Y1)\n"
    "                         of the grid (or with --scene, of the image), each\n"
    "                         as in the whole image (tiles assemble into it bit\n"
    "                         for bit)\n"
    "  --image-memory MB      memory for output images (default 8); larger grids \n"
    "                         are shaded and written a band of rows at a time\n"
    "  --print                print every pixel's requested outputs as text\n"
    "  --info                 print the shader's parameters, defaults and metadata\n"
    "                         as oslinfo -v does, and stop\n"
    "  --interpret            reference mode: one point at a time, ordinary\n"
    "                         branches, no masking (what the differential\n"
    "                         tester compares the SIMD kernels with)\n"
    "  --raytype NAME         the ray type raytype() is 1 for (default camera)\n"
    "  --colorspace NAME      working RGB space of the color functions:\n"
    "                         Rec709 (default), sRGB, ACEScg, ACES2065-1,\n"
    "                         AdobeRGB, NTSC, EBU, PAL, SECAM, SMPTE, HDTV,\n"
    "                         CIE, XYZ\n"
    "  --vary_udxdy, --vary_vdxdy, --vary_pdxdy\n"
    "                         testshade's varying derivatives\n"
    "  -t N                   threads (default: all cores)\n"
    "  --iters N              shade the grid N times, write once\n"
    "  --options LIST         ShadingSystem options as testshade takes them;\n"
    "                         error_repeats=1 reports repeated errors too,\n"
    "                         lazyglobals=0 runs layers that assign Ci in\n"
    "                         order, the later ones seeing that Ci\n"
    "  --texture-cache-mb N   size of the shared texture cache\n"
    "  --cache-dir DIR        keep compiled kernels in DIR, so a second run\n"
    "                         with the same source and options compiles\n"
    "                         nothing (default: $OSL_MLIR_CACHE_DIR, else\n"
    "                         ~/.cache/osl-mlir)\n"
    "  --no-cache             always compile; read and write no cache\n"
    "  --llvm-pipeline=kernel|O3\n"
    "                         LLVM passes before codegen: only the clean-ups\n"
    "                         a vectorized kernel needs (default; marble:\n"
    "                         4.4 ms against O3's 23 in a fresh process), or\n"
    "                         all of O3\n"
    "  --lane-stats           count the active lanes of every masked block\n"
    "                         (varying if arms, varying loop iterations) and\n"
    "                         print their mean fraction\n"
    "  --stats                time of each compile stage and of shading,\n"
    "                         and whether the kernel cache was used\n"
    "  --emit=mlir|lowered|llvm|asm\n"
    "                         print the front end's osl dialect, the lowered\n"
    "                         LLVM dialect, optimized LLVM IR or assembly,\n"
    "                         and stop\n";

namespace {

bool parseInt(const char *text, int &out) {
  char *end = nullptr;
  long v = std::strtol(text, &end, 10);
  if (!*text || *end || v < -(1L << 30) || v > (1L << 30))
    return false;
  out = int(v);
  return true;
}

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

/// testshade names shaders without extension.
std::string shaderFile(std::string name) {
  if (!llvm::StringRef(name).ends_with(".osl") && !llvm::sys::fs::is_regular_file(name))
    name += ".osl";
  return name;
}

/// testshade takes its long flags with one dash too (-param, -layer, ...):
/// the single-dash forms become the double-dash ones osl-run parses.
std::string testshadeSpelling(std::string a) {
  static const char *const kLong[] = {
      "param", "layer", "connect", "center", "iters", "entry", "reparam", "group",
      "shader", "od", "vary_udxdy", "vary_vdxdy", "vary_pdxdy", "colorspace",
      "options", "debug", "res", "raytype", "raytype_opt", "groupoutputs",
      "batched", "groupname", "jbufferMB", "inbuffer", "userdata_isconnected"};
  if (a.size() > 2 && a[0] == '-' && a[1] != '-') {
    llvm::StringRef name = llvm::StringRef(a).drop_front().split(':').first;
    for (const char *flag : kLong)
      if (name == flag)
        return "-" + a;
  }
  return a;
}

} // namespace

bool osl::parseRunOptions(int argc, char **argv, RunOptions &o,
                          std::string &error) {
  auto need = [&](int i, int n, const char *flag) {
    if (i + n < argc)
      return true;
    error = std::string(flag) + " needs " + std::to_string(n) + " argument" +
            (n > 1 ? "s" : "");
    return false;
  };
  bool render = false;
  for (int i = 1; i < argc; ++i)
    render |= std::strcmp(argv[i], "--scene") == 0;
  // testshade's layers: `--layer NAME SHADER` or several positional shaders.
  std::string pendingLayer;
  int positional = 0;
  for (int i = 1; i < argc; ++i) {
    std::string a = testshadeSpelling(argv[i]);
    if (a == "--scene") {
      if (!need(i, 1, "--scene"))
        return false;
      o.scenePath = argv[++i];
    } else if (render && a == "-o") {
      if (!need(i, 1, "-o"))
        return false;
      o.sceneOutput = argv[++i];
    } else if (a == "--path") {
      if (!need(i, 1, "--path"))
        return false;
      o.shaderDirs.push_back(argv[++i]);
    } else if (a == "-r") {
      if (!need(i, 2, "-r") || !parseInt(argv[i + 1], o.renderX) ||
          !parseInt(argv[i + 2], o.renderY) || o.renderX < 1 || o.renderY < 1 ||
          o.renderX > 65536 || o.renderY > 65536) {
        error = "-r needs two positive integers";
        return false;
      }
      i += 2;
    } else if (a == "-aa") {
      if (!need(i, 1, "-aa") || !parseInt(argv[++i], o.aa) || o.aa < 1 || o.aa > 1024) {
        error = "-aa needs a positive count (N x N paths per pixel)";
        return false;
      }
    } else if (a == "--seed") {
      if (!need(i, 1, "--seed") || !parseInt(argv[++i], o.seed)) {
        error = "--seed needs an integer";
        return false;
      }
    } else if (a == "--userdata_isconnected") {
      o.compile.userdataIsConnected = true;
    } else if (a == "--inbuffer") {
      // testshade reads the shader into memory before loading it: osl-run
      // always compiles from text it has read, so the flag changes nothing.
    } else if (a == "-v" || a == "--debug") {
      // testshade's verbosity: osl-run reports what it does with --stats.
    } else if (a == "--llvm_opt" || a == "--options") {
      // testshade's LLVM optimization level and ShadingSystem options:
      // osl-mlir optimizes its own way (-O0/-O1/-O2), so they are taken,
      // and of the options error_repeats and lazyglobals change what runs;
      // commands written for testshade run unchanged.
      if (!need(i, 1, a.c_str()))
        return false;
      ++i;
      if (a == "--options") {
        llvm::SmallVector<llvm::StringRef> settings;
        llvm::StringRef(argv[i]).split(settings, ',');
        for (llvm::StringRef setting : settings) {
          auto [name, value] = setting.split('=');
          if (name.trim() == "error_repeats")
            o.errorRepeats = value.trim() != "0";
          else if (name.trim() == "lazyglobals")
            o.group.lazyGlobals = value.trim() != "0";
          else if (name.trim() == "opt_warnings")
            o.compile.optimizationWarnings = value.trim() != "0";
        }
      }
    } else if (a == "-g" || a == "--g" || a == "--res") {
      if (!need(i, 2, "-g"))
        return false;
      if (!parseInt(argv[i + 1], o.grid.xres) || !parseInt(argv[i + 2], o.grid.yres) ||
          o.grid.xres < 1 || o.grid.yres < 1) {
        error = "-g needs two positive integers";
        return false;
      }
      o.gridGiven = true;
      i += 2;
    } else if (a == "--crop") {
      if (!need(i, 4, "--crop"))
        return false;
      for (int k = 0; k < 4; ++k)
        if (!parseInt(argv[i + 1 + k], o.crop[k]) || o.crop[k] < 0) {
          error = "--crop needs four integers X0 Y0 X1 Y1 of at least 0";
          return false;
        }
      o.cropGiven = true;
      i += 4;
    } else if (a == "-o") {
      if (!need(i, 2, "-o"))
        return false;
      o.outputs.push_back({argv[i + 1], argv[i + 2]});
      i += 2;
    } else if (a == "--groupname") {
      if (!need(i, 1, a.c_str()))
        return false;
      o.compile.groupName = argv[++i];
    } else if (a == "--jbufferMB") {
      // testshade's message-journal size: nothing here depends on it.
      if (!need(i, 1, a.c_str()))
        return false;
      ++i;
    } else if (a == "--od" || a == "-d") { // -d: testshade's older spelling
      if (!need(i, 1, "-od"))
        return false;
      o.dataType = argv[++i];
      if (o.dataType != "float" && o.dataType != "half" && o.dataType != "uint8" &&
          o.dataType != "uint16") {
        error = "-od must be float, half, uint8 or uint16 (got '" + o.dataType + "')";
        return false;
      }
    } else if (a == "--layer") {
      if (!need(i, 1, "--layer"))
        return false;
      pendingLayer = argv[++i];
    } else if (a == "--check") {
      o.checkOnly = true;
    } else if (a == "--timeout") {
      if (!need(i, 1, "--timeout"))
        return false;
      char *end = nullptr;
      long seconds = std::strtol(argv[++i], &end, 10);
      if (!end || *end || seconds <= 0 || seconds > 1000000) {
        error = "--timeout needs a whole number of seconds above 0 (got '" +
                std::string(argv[i]) + "')";
        return false;
      }
      o.timeoutSeconds = int(seconds);
    } else if (a == "--image-memory") {
      if (!need(i, 1, "--image-memory"))
        return false;
      char *end = nullptr;
      long mb = std::strtol(argv[++i], &end, 10);
      if (!end || *end || mb <= 0 || mb > (1L << 30)) {
        error = "--image-memory needs a whole number of megabytes above 0 (got '" +
                std::string(argv[i]) + "')";
        return false;
      }
      o.imageMemoryMB = int(mb);
    } else if (a == "--info") {
      o.infoOnly = true;
    } else if (a == "--param" || a.rfind("--param:", 0) == 0) {
      if (!need(i, 2, "--param"))
        return false;
      std::string type, value = argv[i + 2];
      bool userdata = false;
      llvm::SmallVector<llvm::StringRef> annotations;
      llvm::StringRef(a).split(annotations, ':');
      for (llvm::StringRef note : llvm::ArrayRef(annotations).drop_front()) {
        auto [key, v] = note.split('=');
        if (key == "type")
          type = v.str();
        else if (key == "lockgeom")
          userdata = v == "0";
      }
      if (!type.empty() && type != "string")
        value = numberList(value);
      o.compile.params.push_back({argv[i + 1], value});
      o.group.param(argv[i + 1], value, userdata);
      i += 2;
    } else if (a == "--userdata" || a.rfind("--userdata:", 0) == 0) {
      if (!need(i, 2, "--userdata"))
        return false;
      UserDatum d{argv[i + 1], "", argv[i + 2]};
      llvm::StringRef note = llvm::StringRef(a).drop_front(strlen("--userdata"));
      if (note.consume_front(":type="))
        d.type = note.str();
      else if (!note.empty()) {
        error = "unknown annotation in '" + a + "' (expected --userdata:type=T)";
        return false;
      } else {
        // No type: an int, a float or else a string, as the value reads.
        llvm::StringRef v(d.value);
        long long n;
        double x;
        d.type = !v.getAsInteger(10, n) ? "int" : !v.getAsDouble(x) ? "float" : "string";
      }
      static const char *const kTypes[] = {"int",    "float",  "color", "point",
                                           "vector", "normal", "string"};
      if (!llvm::is_contained(kTypes, d.type)) {
        error = "--userdata: unknown type '" + d.type +
                "' (int, float, color, point, vector, normal or string)";
        return false;
      }
      if (d.type != "string") {
        d.value = numberList(d.value);
        llvm::SmallVector<llvm::StringRef> items;
        llvm::StringRef(d.value).split(items, ',');
        double x;
        bool triple = d.type != "int" && d.type != "float";
        bool ok = items.size() == 1 || (triple && items.size() == 3);
        for (llvm::StringRef item : items)
          ok = ok && !item.getAsDouble(x);
        if (!ok) {
          error = "--userdata: '" + std::string(argv[i + 2]) + "' is not " +
                  (triple ? "one or three numbers" : "a number") + " for type " + d.type;
          return false;
        }
      }
      o.compile.userData.push_back(d);
      i += 2;
    } else if (a == "--shader") {
      if (!need(i, 2, "--shader") ||
          !o.group.shader(shaderFile(argv[i + 1]), argv[i + 2], error)) {
        if (error.empty())
          error = "--shader needs 2 arguments";
        return false;
      }
      o.isGroup = true;
      i += 2;
    } else if (a == "--connect") {
      if (!need(i, 4, "--connect") ||
          !o.group.connect({argv[i + 1], argv[i + 2], argv[i + 3], argv[i + 4]}, error))
        return false;
      o.connectFlags.push_back(o.group.connections.back());
      i += 4;
    } else if (a == "--group") {
      if (!need(i, 1, "--group"))
        return false;
      std::string text = argv[++i], dir;
      // A file of statements, or the statements themselves.
      if (auto file = llvm::MemoryBuffer::getFile(text, /*IsText=*/true)) {
        dir = llvm::sys::path::parent_path(text).str();
        text = (*file)->getBuffer().str();
      } else if (text.find(';') == std::string::npos) {
        error = "--group: cannot read '" + text + "': " + file.getError().message() +
                " (statements end in ';')";
        return false;
      }
      if (!o.group.parseStatements(text, dir, error))
        return false;
      o.isGroup = true;
    } else if (a == "--reparam" || a.rfind("--reparam:", 0) == 0) {
      // (--reparam:type=T:interactive=1, testshade's typed form: the type is
      // the parameter's own.)
      if (!need(i, 3, "--reparam"))
        return false;
      o.reparams.push_back({argv[i + 1], argv[i + 2], argv[i + 3]});
      i += 3;
    } else if (a == "--entry") {
      if (!need(i, 1, "--entry"))
        return false;
      o.group.entries.push_back(argv[++i]);
    } else if (a == "-O0" || a == "-O1" || a == "-O2") {
      o.group.optimization = GroupOptimization(a[2] - '0');
    } else if (a == "--width" || a.rfind("--width=", 0) == 0) {
      std::string v = a == "--width" ? (need(i, 1, "--width") ? argv[++i] : "")
                                     : a.substr(8);
      if (!parseInt(v.c_str(), o.compile.width) ||
          (o.compile.width != 1 && o.compile.width != 4 && o.compile.width != 8 &&
           o.compile.width != 16)) {
        error = "--width must be 1, 4, 8 or 16";
        return false;
      }
    } else if (a == "-t") {
      if (!need(i, 1, "-t") || !parseInt(argv[++i], o.grid.threads) ||
          o.grid.threads < 0) {
        error = "-t needs a thread count (0 = all cores)";
        return false;
      }
    } else if (a == "--iters") {
      if (!need(i, 1, "--iters") || !parseInt(argv[++i], o.iters) || o.iters < 1) {
        error = "--iters needs a positive count";
        return false;
      }
    } else if (a == "--texture-cache-mb") {
      if (!need(i, 1, "--texture-cache-mb") || !parseInt(argv[++i], o.textureCacheMB) ||
          o.textureCacheMB < 1) {
        error = "--texture-cache-mb needs a positive size in MB";
        return false;
      }
    } else if (a == "--math" || a.rfind("--math=", 0) == 0) {
      if (a == "--math" && !need(i, 1, "--math"))
        return false;
      std::string v = a == "--math" ? std::string(argv[++i]) : a.substr(7);
      auto level = mlir::osl::parseMathLevel(v);
      if (!level) {
        error = "--math must be fast, default, precise or double (got '" + v + "')";
        return false;
      }
      o.compile.math = *level;
    } else if (a == "--center") {
      o.grid.center = true;
    } else if (a == "--interpret") {
      o.compile.reference = true;
    } else if (a == "--verify-each") {
      o.compile.verifyEachPass = true;
    } else if (a == "-I" || (a.size() > 2 && a.rfind("-I", 0) == 0)) {
      if (a == "-I" && !need(i, 1, "-I"))
        return false;
      o.compile.includePaths.push_back(a == "-I" ? std::string(argv[++i]) : a.substr(2));
    } else if (a == "-Werror") {
      o.compile.warningsAsErrors = true;
    } else if (a == "--print") {
      o.printValues = true;
    } else if (a == "--keep-going") {
      o.keepGoing = true;
    } else if (a == "-w") {
      o.compile.showWarnings = false;
    } else if (a == "-D" || a == "-U" || (a.size() > 2 && (a.rfind("-D", 0) == 0 ||
                                                           a.rfind("-U", 0) == 0))) {
      // oslc's -D NAME[=VALUE] and -U NAME.
      std::string flag = a.substr(0, 2);
      if (a.size() == 2 && !need(i, 1, flag.c_str()))
        return false;
      std::string macro = a.size() == 2 ? std::string(argv[++i]) : a.substr(2);
      o.compile.defines.push_back(flag == "-U" ? "-" + macro : macro);
    } else if (a == "--raytype") {
      if (!need(i, 1, "--raytype"))
        return false;
      o.compile.rayType = argv[++i];
    } else if (a == "--batched") {
      // testshade's: use the batched backend. osl-run always shades in batches.
    } else if (a == "--groupoutputs") {
      // testshade's: -o names the group's outputs, which osl-run's always do.
    } else if (a == "--raytype_opt") {
      // testshade's: specialise on the ray type. Kernels here always are.
    } else if (a == "--colorspace") {
      if (!need(i, 1, "--colorspace"))
        return false;
      o.compile.colorSpace = argv[++i];
    } else if (a == "--vary_udxdy") {
      o.grid.varyUdxdy = true;
    } else if (a == "--vary_vdxdy") {
      o.grid.varyVdxdy = true;
    } else if (a == "--vary_pdxdy") {
      o.grid.varyPdxdy = true;
    } else if (a == "--cache-dir") {
      if (!need(i, 1, "--cache-dir"))
        return false;
      o.compile.cacheDir = argv[++i];
      if (o.compile.cacheDir.empty()) {
        error = "--cache-dir needs a directory";
        return false;
      }
      o.cacheDirGiven = true;
    } else if (a.rfind("--llvm-pipeline=", 0) == 0) {
      std::string v = a.substr(16);
      if (v != "kernel" && v != "O3") {
        error = "--llvm-pipeline must be kernel or O3";
        return false;
      }
      o.compile.llvmPipeline = v == "O3" ? LlvmPipeline::O3 : LlvmPipeline::Kernel;
    } else if (a == "--lane-stats") {
      o.compile.countLanes = true;
    } else if (a == "--no-cache") {
      o.noCache = true;
    } else if (a == "--stats") {
      o.stats = true;
    } else if (a.rfind("--emit=", 0) == 0) {
      o.emit = a.substr(7);
      if (o.emit != "mlir" && o.emit != "lowered" && o.emit != "llvm" && o.emit != "asm") {
        error = "--emit must be mlir, lowered, llvm or asm";
        return false;
      }
    } else if (a == "-h" || a == "--help") {
      error = "";
      return false;
    } else if (!a.empty() && a[0] == '-') {
      error = "unknown option '" + a + "'";
      return false;
    } else {
      // A positional shader is also a layer, in case a --layer or a second
      // shader makes this a group (testshade's form).
      std::string layer = pendingLayer.empty()
                              ? llvm::sys::path::stem(a).str()
                              : pendingLayer;
      // The same shader named twice (testshade runs both): the second
      // layer takes a name of its own.
      auto taken = [&](const std::string &name) {
        return llvm::any_of(o.group.layers,
                            [&](const GroupLayer &l) { return l.name == name; });
      };
      if (pendingLayer.empty())
        for (int n = 1; taken(layer); ++n)
          layer = llvm::sys::path::stem(a).str() + "_" + std::to_string(n);
      if (!o.group.shader(shaderFile(a), layer, error))
        return false;
      ++positional;
      // Per-geometry (lockgeom=0) parameters are loaded as the group runs,
      // which the group's linking arranges.
      if (!pendingLayer.empty() || positional > 1 || !o.group.layers.back().userdata.empty())
        o.isGroup = true;
      pendingLayer.clear();
      if (o.shaderPath.empty())
        o.shaderPath = shaderFile(a);
    }
  }
  if (o.isGroup && positional > 0)
    o.shaderPath.clear();
  if (render) {
    if (!o.shaderPath.empty() || o.isGroup) {
      error = "--scene takes its shaders from the scene, not '" +
              (o.isGroup ? std::string("--shader/--group") : o.shaderPath) + "'";
      return false;
    }
    if (o.sceneOutput.empty()) {
      error = "--scene needs -o FILE";
      return false;
    }
    if (!o.outputs.empty() || o.gridGiven || !o.emit.empty()) {
      error = "-g, -o NAME FILE and --emit are for shading a grid, not --scene";
      return false;
    }
  } else if (o.isGroup) {
    if (!o.shaderPath.empty()) {
      error = "a shader given both positionally ('" + o.shaderPath + "') and as a group layer";
      return false;
    }
    o.groupBeforeReparams = o.group;
    for (const RunOptions::Reparam &r : o.reparams)
      if (!o.group.reparam(r.layer, r.name, r.value, error))
        return false;
    if (!o.group.validate(error))
      return false;
    // testshade also takes the root layer's own outputs as ROOT.NAME.
    std::string rootPrefix = o.group.layers.back().name + ".";
    for (auto &[name, file] : o.outputs)
      o.group.outputs.push_back(llvm::StringRef(name).starts_with(rootPrefix)
                                    ? name.substr(rootPrefix.size())
                                    : name);
    o.compile.params.clear();
  } else {
    if (!o.group.connections.empty() || !o.group.entries.empty() || !o.reparams.empty()) {
      error = "--connect, --entry and --reparam need a group (--shader or --group)";
      return false;
    }
    if (o.shaderPath.empty()) {
      error = "no shader given";
      return false;
    }
    for (auto &[name, file] : o.outputs)
      o.compile.rendererOutputs.push_back(name);
  }
  if (!o.gridGiven)
    o.grid.xres = o.grid.yres = 512;
  if (o.cropGiven) {
    // A window of the grid, or of the image with --scene.
    const int *c = o.crop;
    int width = render ? o.renderX : o.grid.xres, height = render ? o.renderY : o.grid.yres;
    if (!(c[0] < c[2] && c[2] <= width && c[1] < c[3] && c[3] <= height)) {
      error = "--crop " + std::to_string(c[0]) + " " + std::to_string(c[1]) + " " +
              std::to_string(c[2]) + " " + std::to_string(c[3]) + " is no window of the " +
              std::to_string(width) + "x" + std::to_string(height) +
              (render ? " image" : " grid") +
              ": it needs 0 <= X0 < X1 <= width and 0 <= Y0 < Y1 <= height";
      return false;
    }
    if (!render) {
      o.grid.colBegin = c[0];
      o.grid.rowBegin = c[1];
      o.grid.colEnd = c[2];
      o.grid.rowEnd = c[3];
    }
  }
  if (o.noCache && o.cacheDirGiven) {
    error = "--cache-dir and --no-cache contradict each other";
    return false;
  }
  if (o.noCache)
    o.compile.cacheDir.clear();
  else if (!o.cacheDirGiven)
    o.compile.cacheDir = KernelCache::defaultDirectory();
  return true;
}
