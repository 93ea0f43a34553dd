//===- RunOptions.cpp - osl-run's command line ----------------------------===//
//
// The usage text, and parseRunOptions: each flag goes to its handler
// (RunFlags.cpp), a name without a dash is a shader, and what the flags say
// together is checked at the end.
//
//===----------------------------------------------------------------------===//
#include "RunOptions.h"
#include "RunFlags.h"

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
    "  -expr STATEMENT        shade testshade's shader around STATEMENT instead\n"
    "                         of a file: outputs result (color) and alpha,\n"
    "                         parameters s = u and t = v (-v prints it)\n"
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
    "  --entry LAYER          run LAYER (repeatable: in the order given, each\n"
    "                         with the layers it reads; default: the last\n"
    "                         layer and the layers OSL never skips)\n"
    "  --entryoutput L.NAME   run the layer of output L.NAME instead of the\n"
    "                         --entry layers (repeatable)\n"
    "  -v                     print the group as testshade does (its\n"
    "                         statements, then its layers)\n"
    "  --oslquery             with it, each layer's parameters\n"
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
    "  --scaleuv U V, --offsetst U V  scale, then offset u and v (and P,\n"
    "                         dudx, dvdy) as testshade does (its --offsetuv\n"
    "                         is ignored, as testshade 1.13 ignores it)\n"
    "  -I DIR                 search DIR for #include files\n"
    "  -D NAME[=VALUE], -U NAME  define or undefine a macro, as oslc does\n"
    "  -Werror                warnings are errors, as with oslc -Werror\n"
    "  -M, -MM                print the shader's make dependencies instead of\n"
    "                         compiling (-MM: not osl-mlir's standard headers)\n"
    "  -MD, -MMD              compile and write them to -MF FILE (default\n"
    "                         SOURCE.d); -MT TARGET names the target (default\n"
    "                         SOURCE.oso)\n"
    "  --debugnan             report the points where a value stored into a\n"
    "                         variable has a NaN or infinite component\n"
    "  -w                     print no warnings\n"
    "  --debug                report the globals the optimized shader reads\n"
    "                         (\"Need N globals: ...\"), as testshade -debug does\n"
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
    "  --info-json            the same as JSON (what python/oslquery.py reads)\n"
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
    "                         order, the later ones seeing that Ci,\n"
    "                         llvm_debug_layers=1 prints where each layer\n"
    "                         is entered and left\n"
    "  --texture-cache-mb N   size of the shared texture cache\n"
    "  --cache-dir DIR        keep compiled kernels in DIR, so a second run\n"
    "                         with the same source and options compiles\n"
    "                         nothing (default: $OSL_MLIR_CACHE_DIR, else\n"
    "                         ~/.cache/osl-mlir); noise routines compiled\n"
    "                         once are kept in its library/ for every shader\n"
    "  --no-cache             always compile; read and write no cache\n"
    "  --inline-library       noise inline at each call in the kernel, not\n"
    "                         shared functions compiled once per process and\n"
    "                         kept in the cache (longer compiles)\n"
    "  --outline-every-routine\n"
    "                         every noise routine a shared function, even\n"
    "                         cell and hash noise called once or twice\n"
    "                         (by default inline: cheaper than a call)\n"
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

/// testshade takes its long flags with one dash too (-param, -layer, ...):
/// the single-dash forms become the double-dash ones osl-run parses.
std::string testshadeSpelling(std::string a) {
  static const char *const kLong[] = {
      "param", "layer", "connect", "center", "debugnan", "scaleuv", "offsetuv", "offsetst", "iters", "entry", "reparam", "group",
      "shader", "od", "vary_udxdy", "vary_vdxdy", "vary_pdxdy", "colorspace",
      "options", "debug", "res", "raytype", "raytype_opt", "groupoutputs",
      "batched", "groupname", "jbufferMB", "inbuffer", "userdata_isconnected", "expr",
      "userdata", "print", "oslquery", "llvm_opt"};
  if (a.size() > 2 && a[0] == '-' && a[1] != '-') {
    llvm::StringRef name = llvm::StringRef(a).drop_front().split(':').first;
    for (const char *flag : kLong)
      if (name == flag)
        return "-" + a;
  }
  return a;
}

} // namespace

namespace {

/// A shader named on its own: a layer too, in case a --layer or a second
/// shader makes this a group (testshade's form).
bool addPositionalShader(FlagParser &p, const std::string &a, int &positional) {
  RunOptions &o = p.o;
  // An unnamed layer is named as testshade names it: the shader, then the
  // layer's index (so the same shader twice makes two layers).
  std::string layer = p.pendingLayer.empty()
                          ? llvm::sys::path::stem(a).str() + "_" +
                                std::to_string(o.group.layers.size())
                          : p.pendingLayer;
  if (!o.expression.empty()) {
    p.error = "-expr makes the shader: '" + a + "' cannot be given too";
    return false;
  }
  if (!o.group.shader(shaderFile(a), layer, p.error))
    return false;
  o.group.layers.back().shaderName = a;
  ++positional;
  // Per-geometry (lockgeom=0) parameters are loaded as the group runs,
  // which the group's linking arranges.
  if (!p.pendingLayer.empty() || positional > 1 || !o.group.layers.back().userdata.empty())
    o.isGroup = true;
  p.pendingLayer.clear();
  if (o.shaderPath.empty())
    o.shaderPath = shaderFile(a);
  return true;
}

} // namespace

std::string osl::exprShaderText(const std::string &expression) {
  return std::string("shader ") + kExprShaderName +
         " (\n"
         "    float s = u [[ int interpolated=1 ]],\n"
         "    float t = v [[ int interpolated=1 ]],\n"
         "    output color result = 0,\n"
         "    output float alpha = 1,\n"
         "  )\n"
         "{\n"
         "    " +
         expression + "\n    ;\n}\n";
}

bool osl::parseRunOptions(int argc, char **argv, RunOptions &o,
                          std::string &error) {
  FlagParser p{argc, argv, 0, o, error, "", false, ""};
  for (int i = 1; i < argc; ++i)
    p.render |= std::strcmp(argv[i], "--scene") == 0;
  int positional = 0;
  for (p.i = 1; p.i < argc; ++p.i) {
    p.flag = testshadeSpelling(argv[p.i]);
    if (FlagHandler handle = findFlag(p.flag)) {
      if (!handle(p))
        return false;
    } else if (!p.flag.empty() && p.flag[0] == '-') {
      error = "unknown option '" + p.flag + "'";
      return false;
    } else if (!addPositionalShader(p, p.flag, positional)) {
      return false;
    }
  }
  bool render = p.render;
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
  } else if (o.timeKernels) {
    error = "--time-kernels times a render's shading batches: it needs --scene";
    return false;
  } else if (o.isGroup) {
    if (!o.shaderPath.empty()) {
      error = "a shader given both positionally ('" + o.shaderPath + "') and as a group layer";
      return false;
    }
    o.groupBeforeReparams = o.group;
    for (const RunOptions::Reparam &r : o.reparams)
      if (!o.group.reparam(r.layer, r.name, r.value, error))
        return false;
    // The group is checked as it is assembled (GroupAssembly.h: in
    // testshade's words) and again when it compiles.
    // (testshade also takes the root layer's own outputs as ROOT.NAME:
    // osl-link-group runs only the root for those.)
    for (auto &[name, file] : o.outputs)
      o.group.outputs.push_back(name);
    o.compile.params.clear();
  } else {
    if (!o.group.connections.empty() || !o.group.entries.empty() ||
        !o.group.entryOutputs.empty() || !o.reparams.empty()) {
      error = "--connect, --entry, --entryoutput and --reparam need a group (--shader or "
              "--group)";
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
