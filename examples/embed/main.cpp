// Embeds osl-mlir: compiles a shader from a string for 8 lanes, shades a
// 16x16 grid and prints the mean of its output. Exits non-zero on failure.
#include "OslCompiler/ShaderCompiler.h"

#include "llvm/Support/raw_ostream.h"

int main() {
  const char *source = "shader ramp(output float f = 0) { f = u * v; }";
  osl::CompileOptions options;
  options.width = 8;
  osl::ShaderCompiler compiler(options, llvm::errs());
  std::unique_ptr<osl::CompiledShader> shader = compiler.compile(source, "ramp.osl");
  if (!shader)
    return 1;
  osl::GridOptions grid;
  grid.xres = grid.yres = 16;
  osl::ShadeResult result = osl::shadeGrid(shader->kernel, shader->width, shader->outputs, grid);
  double sum = 0;
  for (float f : result.images[0])
    sum += f;
  double mean = sum / result.images[0].size();
  llvm::outs() << "mean " << mean << "\n";
  // u and v are independent and uniform over [0,1] on the grid: mean 0.25.
  return (mean > 0.24 && mean < 0.26) ? 0 : 1;
}
