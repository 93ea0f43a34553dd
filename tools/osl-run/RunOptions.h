//===- RunOptions.h - osl-run's command line --------------------*- C++ -*-===//
#ifndef OSLRUN_RUNOPTIONS_H
#define OSLRUN_RUNOPTIONS_H

#include "OslCompiler/ShaderCompiler.h"

#include <string>
#include <utility>
#include <vector>

namespace osl {

struct RunOptions {
  std::string shaderPath;
  /// -expr EXPR: the shader is testshade's shader around the statement EXPR
  /// (exprShaderText); -v prints it and the group as testshade does.
  std::string expression;
  bool verbose = false;
  /// --oslquery: -v's group summary also lists each layer's parameters.
  bool oslquery = false;
  /// The text of --group's statements, which -v prints first.
  std::string groupSpec;
  CompileOptions compile;
  GridOptions grid;
  bool gridGiven = false;
  /// --crop X0 Y0 X1 Y1: shade and write only the pixels [X0, X1) x
  /// [Y0, Y1) of the grid (grid.colBegin... hold the window once parsed).
  bool cropGiven = false;
  int crop[4] = {0, 0, 0, 0};
  /// (output name, file); "null" discards.
  std::vector<std::pair<std::string, std::string>> outputs;
  bool stats = false;
  /// --time-kernels: a render's --stats also times its shading kernels.
  bool timeKernels = false;
  /// --check: compile (reporting errors) and stop, like oslc.
  bool checkOnly = false;
  /// oslc's make dependencies of a shader: -M/-MM print them instead of
  /// compiling, -MD/-MMD write them to -MF FILE (else SOURCE's stem +
  /// ".d") once it compiles; -MT
  /// names the target (else SOURCE's stem + ".oso"); the -MM forms leave
  /// out osl-mlir's standard headers.
  struct Dependencies {
    bool print = false, write = false, standardHeaders = true;
    std::string file, target;
  } dependencies;
  /// --timeout SECONDS: stop (exit 1) when the run takes longer; 0: never.
  int timeoutSeconds = 0;
  /// --keep-going: a texture that cannot be read or a failed string call is
  /// still reported but leaves the exit status 0, as testshade does.
  bool keepGoing = false;
  /// --print: every pixel's requested outputs as text, as testshade prints.
  bool printValues = false;
  /// --image-memory MB: the most the output images of a grid may hold in
  /// memory; larger grids are shaded and written a band of rows at a time.
  int imageMemoryMB = 8;
  /// --info: print the shader's parameters and metadata as oslinfo -v does.
  bool infoOnly = false;
  /// --info-json: the same as JSON, for python/oslquery.py.
  bool infoJson = false;
  /// -od: the images' data type (float, half, uint8, uint16); "" keeps the
  /// format's own choice.
  std::string dataType;
  int iters = 1;
  /// --options error_repeats=1: every warning and error reported, repeats
  /// too (by default each distinct text once, as testshade does).
  bool errorRepeats = false;
  /// The shared texture cache's size in MB (0: OpenImageIO's default).
  int textureCacheMB = 0;
  std::string emit; // "", "mlir", "lowered", "llvm", "asm"
  /// --no-cache: compile even if the kernel cache has the kernel.
  bool noCache = false;
  bool cacheDirGiven = false;
  /// --shader/--connect/--group/--entry build a group instead of the one
  /// positional shader; --reparam values are applied once it is built.
  ShaderGroup group;
  bool isGroup = false;
  struct Reparam {
    std::string layer, name, value;
  };
  std::vector<Reparam> reparams;
  /// The group as given, before --reparam: testshade shades its first pass
  /// (of --iters) with these values.
  ShaderGroup groupBeforeReparams;
  /// testshade's "Entry layers: NAME(INDEX)..." line for the --entry layers
  /// as given (empty: none), printed with the images' lines.
  std::string entryLayersLine;

  /// Render mode (--scene FILE.xml -o OUT): testrender's flags.
  std::string scenePath;
  std::string sceneOutput;
  std::vector<std::string> shaderDirs; // --path
  int renderX = 256, renderY = 256;    // -r
  int aa = 1;                          // -aa: aa x aa paths per pixel
  int seed = 0;
};

/// The images a grid run writes: the grid, or its --crop window.
inline int imageWidth(const GridOptions &g) {
  return (g.colEnd < 0 ? g.xres : g.colEnd) - g.colBegin;
}
inline int imageHeight(const GridOptions &g) {
  return (g.rowEnd < 0 ? g.yres : g.rowEnd) - g.rowBegin;
}

/// The shader testshade -expr makes of `expression`: parameters s and t
/// (u and v), outputs result (a color) and alpha, and the statement.
std::string exprShaderText(const std::string &expression);
/// The name testshade gives that shader (its layer is expr_0_0).
constexpr const char *kExprShaderName = "expr_0";

/// Renders options.scenePath (RenderScene.cpp); the process exit status.
int renderScene(const RunOptions &options);

/// The exit status once the images are written: a texture that could not
/// be read or a string call that failed (a bad regex) is an error
/// (reported once, where it happened), unless --keep-going (osl-run.cpp).
int statusAfterShading(const RunOptions &options);

/// testshade-style arguments (testrender's with --scene). On error returns
/// false with a message.
bool parseRunOptions(int argc, char **argv, RunOptions &options,
                     std::string &error);

extern const char *const kUsage;

} // namespace osl

#endif // OSLRUN_RUNOPTIONS_H
