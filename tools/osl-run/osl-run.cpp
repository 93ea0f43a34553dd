//===- osl-run.cpp - Compile an OSL shader and shade a grid ---------------===//
//
// Like OSL's testshade: each point of an X x Y grid gets testshade's
// globals, batches of W points run through the JIT-compiled kernel, and
// outputs are written as images through OpenImageIO.
//
//===----------------------------------------------------------------------===//
#include "OslRuntime/Jit.h"
#include "Dependencies.h"
#include "GroupAssembly.h"
#include "GroupSummary.h"
#include "RunOptions.h"

#include "OslFrontend/Frontend.h"

#include "OslRuntime/ImageOutput.h"
#include "OslRuntime/PointCloud.h"
#include "OslRuntime/PrintCall.h"
#include "OslRuntime/LaneStats.h"
#include "OslRuntime/StringCall.h"
#include "OslRuntime/TextureCall.h"
#include "OslRuntime/ThreadPool.h"

#include "llvm/IR/Module.h"
#include "llvm/Support/FormatVariadic.h"
#include "llvm/Support/InitLLVM.h"
#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/raw_ostream.h"

#include <csignal>
#include <cstdio>
#include <cstring>
#include <unistd.h>

using namespace osl;

/// --lane-stats and --stats (defined below).
void reportRun(const RunOptions &options, ShaderCompiler &compiler,
               const CompiledShader &shader, ThreadPool &pool, Stats &stats,
               double shading);

namespace {

/// testshade's line before the images' lines: the --entry layers (printed
/// with the group when no image is asked for).
void printEntryLayers(const RunOptions &options) {
  if (!options.outputs.empty())
    llvm::outs() << options.entryLayersLine;
}

/// testshade's line after the images' lines: the --entryoutput outputs.
void printEntryOutputs(const RunOptions &options) {
  if (options.group.entryOutputs.empty())
    return;
  llvm::outs() << "Entry outputs:";
  for (const std::string &output : options.group.entryOutputs)
    llvm::outs() << " " << output;
  llvm::outs() << "\n";
}

int fail(const std::string &message) {
  llvm::errs() << "osl-run: error: " << message << "\n";
  return 1;
}

/// A requested output: its kernel row block, its file ("null": none) and
/// the name it was asked for by.
struct OutputFile {
  size_t index;
  std::string file, name;
};

/// Maps each requested output to its kernel row block.
bool resolveOutputs(const RunOptions &options, const CompiledShader &shader,
                    std::vector<OutputFile> &files,
                    std::string &error) {
  auto requested = options.outputs;
  if (requested.empty()) {
    // The default image is a PNG: an output of at most 4 channels (not a
    // matrix's 16).
    auto pictured = [](const OutputSpec &o) { return !o.closure && o.channels <= 4; };
    auto image = std::find_if(shader.outputs.begin(), shader.outputs.end(), pictured);
    // A shader without image outputs still runs (for its printf output,
    // as testshade runs it); no image is written.
    if (image == shader.outputs.end())
      return true;
    // A group's root layer writes plain names; other layers' outputs
    // ("layer.name") come first in the kernel when every layer runs.
    auto rootImage = std::find_if(image, shader.outputs.end(), [&](const OutputSpec &o) {
      return pictured(o) && o.name.find('.') == std::string::npos;
    });
    if (rootImage != shader.outputs.end())
      image = rootImage;
    requested.push_back({image->name, shader.name + ".png"});
  }
  for (const auto &request : requested) {
    const std::string &name = request.first, &file = request.second;
    // A group's root layer outputs are also ROOT.NAME, as testshade has them.
    auto it = std::find_if(shader.outputs.begin(), shader.outputs.end(), [&](const OutputSpec &o) {
      return o.name == name || (options.isGroup && name == shader.name + "." + o.name);
    });
    if (it == shader.outputs.end()) {
      error = "shader '" + shader.name + "' has no output '" + name + "'; outputs:";
      for (const OutputSpec &o : shader.outputs)
        error += " " + o.name;
      return false;
    }
    if (it->closure) {
      if (file == "null")
        continue; // nothing to write (testshade skips it with a note)
      error = "output '" + name + "' is a closure, not an image; render it with --scene";
      return false;
    }
    files.push_back({size_t(it - shader.outputs.begin()), file, name});
  }
  return true;
}

/// --print: each pixel's requested outputs, as testshade prints them
/// ("Pixel (X, Y):" then "  NAME : V V V" per output, %g numbers).
void printPixelValues(const RunOptions &options, const CompiledShader &shader,
                      const std::vector<OutputFile> &files,
                      const ShadeResult &result) {
  // testshade labels LAYER.NAME as NAME.
  std::vector<llvm::StringRef> labels;
  for (const OutputFile &f : files) {
    auto [layer, name] = llvm::StringRef(f.name).split('.');
    bool layered = options.isGroup && !name.empty() && options.group.findLayer(layer.str());
    labels.push_back(layered ? name : llvm::StringRef(f.name));
  }
  int w = imageWidth(options.grid), h = imageHeight(options.grid);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      llvm::outs() << "Pixel (" << x + options.grid.colBegin << ", "
                   << y + options.grid.rowBegin << "):\n";
      for (size_t i = 0; i < files.size(); ++i) {
        const OutputSpec &spec = shader.outputs[files[i].index];
        const float *pixel =
            result.images[files[i].index].data() + (size_t(y) * w + x) * spec.channels;
        llvm::outs() << "  " << labels[i] << " :";
        for (int c = 0; c < spec.channels; ++c) {
          if (spec.integer)
            llvm::outs() << " " << intOutputValue(pixel[c]);
          else
            llvm::outs() << llvm::format(" %g", double(pixel[c]));
        }
        llvm::outs() << "\n";
      }
    }
}

/// --emit: runs the compile stages up to the one asked for and prints its
/// result. False after an error.
bool emit(ShaderCompiler &compiler, const RunOptions &options, llvm::StringRef source,
          Stats *statsPtr) {
  if (!(options.isGroup ? compiler.parseGroup(options.group)
                        : compiler.parse(source, options.shaderPath)))
    return false;
  if (options.emit == "mlir") {
    compiler.module().print(llvm::outs());
    return true;
  }
  compiler.keepLibraryInModule(); // the whole kernel, noise included
  if (!compiler.lower())
    return false;
  if (options.emit == "lowered") {
    compiler.module().print(llvm::outs());
    return true;
  }
  if (!compiler.translate())
    return false;
  if (options.emit == "llvm") {
    compiler.llvmModule()->print(llvm::outs(), nullptr);
    return true;
  }
  auto asmText = Jit::emitAssembly(*compiler.llvmModule(), statsPtr);
  if (!asmText) {
    fail(llvm::toString(asmText.takeError()));
    return false;
  }
  llvm::outs() << *asmText;
  return true;
}

const char *cacheUseText(CacheUse use) {
  switch (use) {
  case CacheUse::Off:
    return "off";
  case CacheUse::Hit:
    return "hit (nothing compiled)";
  case CacheUse::Miss:
    return "miss (compiled and stored)";
  case CacheUse::Rebuilt:
    return "corrupt or stale entry, compiled and replaced";
  }
  return "";
}

/// A crash ends the process at once with a message. LLVM's own handler
/// prints a stack trace, which allocates: after heap corruption it can
/// wait forever on malloc's lock, turning a crash into a hang.
extern "C" void dieOnSignal(int signal) {
  static const char message[] = "osl-run: internal error: the compiler or runtime crashed "
                                "(signal ";
  (void)!write(2, message, sizeof message - 1);
  char digits[4] = {char('0' + signal / 10 % 10), char('0' + signal % 10), ')', '\n'};
  (void)!write(2, digits, sizeof digits);
  _exit(70);
}

/// --timeout: the message, made before the alarm is armed (a signal
/// handler must not allocate), and the images being written, removed so no
/// partial file is left behind.
char timeoutMessage[160];
constexpr int kMaxFilesWritten = 64;
const char *volatile imagesBeingWritten[kMaxFilesWritten] = {};

extern "C" void stopOnTimeout(int) {
  (void)!write(2, timeoutMessage, std::strlen(timeoutMessage));
  for (int i = 0; i < kMaxFilesWritten; ++i)
    if (const char *file = imagesBeingWritten[i])
      unlink(file);
  _exit(1);
}

/// Names the files a timeout must remove (at most kMaxFilesWritten; the
/// rest are not removed), or none.
void setImagesBeingWritten(const std::vector<const char *> &files) {
  for (int i = 0; i < kMaxFilesWritten; ++i)
    imagesBeingWritten[i] = size_t(i) < files.size() ? files[size_t(i)] : nullptr;
}

void armTimeout(int seconds) {
  std::snprintf(timeoutMessage, sizeof timeoutMessage,
                "osl-run: error: stopped after the --timeout of %d s (a shader that does "
                "not end?)\n",
                seconds);
  std::signal(SIGALRM, stopOnTimeout);
  alarm(unsigned(seconds));
}


/// Shades and writes a grid whose images exceed --image-memory, `bandRows`
/// rows at a time, each image written as it goes (under a temporary name,
/// renamed when whole). What the shader prints comes band by band, before
/// the "Output ... to ..." lines.
int shadeInBands(RunOptions &options, ShaderCompiler &compiler, const CompiledShader &shader,
                 const std::vector<OutputFile> &files, int bandRows,
                 ThreadPool &pool, Stats &stats) {
  std::string error;
  std::vector<std::pair<size_t, ImageStream>> streams;
  for (auto &[index, file, name] : files) {
    if (file == "null")
      continue;
    ImageStream stream;
    if (!stream.open(file, imageWidth(options.grid), imageHeight(options.grid),
                     shader.outputs[index].channels, error, options.dataType,
                     shader.outputs[index].integer, /*asTestshade=*/true))
      return fail(error);
    streams.emplace_back(index, std::move(stream));
  }
  std::vector<const char *> temporaries;
  for (auto &[index, stream] : streams)
    temporaries.push_back(stream.temporaryPath());
  setImagesBeingWritten(temporaries);
  ShadeResult band;
  double shading = 0;
  // The window's rows (all of the grid's without --crop), band by band.
  int top = options.grid.rowBegin, bottom = top + imageHeight(options.grid);
  for (int row = top; row < bottom; row += bandRows) {
    options.grid.rowBegin = row;
    options.grid.rowEnd = std::min(bottom, row + bandRows);
    for (int i = 0; i < options.iters; ++i) {
      shadeGridInto(band, shader.kernel, shader.width, shader.outputs, options.grid, pool);
      shading += band.seconds;
    }
    emitPrints(band.printed, shader.name, options.errorRepeats);
    for (auto &[index, stream] : streams)
      if (!stream.writeRows(options.grid.rowBegin - top, options.grid.rowEnd - top,
                            band.images[index].data(), error))
        return fail(error);
  }
  for (auto &[index, stream] : streams)
    if (!stream.close(error))
      return fail(error);
  setImagesBeingWritten({});
  stats.add("shading", shading);
  llvm::outs() << "\n";
  printEntryLayers(options);
  for (size_t i = 0; i < files.size(); ++i)
    if (files[i].file != "null" && !options.outputs.empty())
      llvm::outs() << "Output " << files[i].name << " to " << files[i].file << "\n";
  printEntryOutputs(options);
  // The whole window again, for the per-point figures (--stats printed
  // nothing for a banded grid before).
  options.grid.rowBegin = top;
  options.grid.rowEnd = bottom;
  reportRun(options, compiler, shader, pool, stats, shading);
  return statusAfterShading(options);
}

} // namespace

int osl::statusAfterShading(const RunOptions &options) {
  // The clouds pointcloud_write made are files once shading is over, as
  // testshade's are when it ends.
  std::string error;
  if (!savePointClouds(error)) {
    llvm::errs() << "osl-run: error: " << error << "\n";
    return 1;
  }
  return !options.keepGoing &&
                 (textureFileErrors() > 0 || pointCloudFileErrors() > 0 || stringErrors() > 0)
             ? 1
             : 0;
}

/// Marks the outputs written to files (or printed, --print) as kept;
/// returns the bytes one row of their images takes.
double keepWrittenImages(RunOptions &options, const CompiledShader &shader,
                         const std::vector<OutputFile> &files) {
  options.grid.keepImages.assign(shader.outputs.size(), false);
  double rowBytes = 0;
  for (auto &[index, file, name] : files)
    if ((file != "null" || options.printValues) && !options.grid.keepImages[index]) {
      options.grid.keepImages[index] = true;
      rowBytes += 4.0 * imageWidth(options.grid) * shader.outputs[index].channels;
    }
  return rowBytes;
}

/// Shades the grid --iters times into one set of images; what the passes
/// printed goes to `printed` in order. False (reported) if the shader as
/// given before --reparam does not compile. `shading`: the seconds spent.
bool shadePasses(const RunOptions &options, ShaderCompiler &compiler,
                 const CompiledShader &shader, ThreadPool &pool, ShadeResult &result,
                 PrintLog &printed, Stats &stats, double &shading) {
  shading = 0;
  for (int i = 0; i < options.iters; ++i) {
    // With --reparam, testshade's first pass shades the values as given,
    // the later ones the changed values.
    const CompiledShader *pass = &shader;
    std::unique_ptr<CompiledShader> beforeReparams;
    if (i == 0 && options.iters > 1 && !options.reparams.empty()) {
      beforeReparams = compiler.compileGroup(options.groupBeforeReparams);
      if (!beforeReparams)
        return false;
      pass = beforeReparams.get();
    }
    // One set of images, allocated and paged in by the first pass.
    shadeGridInto(result, pass->kernel, pass->width, pass->outputs, options.grid, pool);
    shading += result.seconds;
    appendPrints(printed, std::move(result.printed), options.errorRepeats);
  }
  stats.add("shading", shading);
  return true;
}

/// Writes the images and prints what the shader printed, in testshade's
/// order: after the reports of the images it was asked to write, or before
/// its closing blank line when it writes none. False (reported) if an
/// image cannot be written.
bool writeResults(const RunOptions &options, const CompiledShader &shader,
                  const std::vector<OutputFile> &files,
                  const ShadeResult &result, const PrintLog &printed, Stats *statsPtr) {
  ScopedTimer timer(statsPtr, "write images");
  bool imagesFirst = !options.outputs.empty();
  if (!imagesFirst)
    emitPrints(printed, shader.name, options.errorRepeats);
  llvm::outs() << "\n";
  if (imagesFirst)
    printEntryLayers(options);
  for (size_t i = 0; i < files.size(); ++i) {
    auto &[index, file, name] = files[i];
    if (file == "null")
      continue;
    std::string error;
    // (writeImage writes a partial file and renames it: a timeout removes
    // that.)
    std::string beingWritten = partialImagePath(file);
    setImagesBeingWritten({beingWritten.c_str()});
    bool written = writeImage(file, imageWidth(options.grid), imageHeight(options.grid),
                              shader.outputs[index].channels, result.images[index].data(),
                              error, options.dataType, shader.outputs[index].integer,
                              /*asTestshade=*/true);
    setImagesBeingWritten({});
    if (!written) {
      fail("cannot write '" + file + "': " + error);
      return false;
    }
    // testshade's report of each image it was asked for.
    if (imagesFirst)
      llvm::outs() << "Output " << name << " to " << file << "\n";
  }
  if (imagesFirst)
    printEntryOutputs(options);
  if (options.printValues)
    printPixelValues(options, shader, files, result);
  if (imagesFirst) {
    llvm::outs().flush();
    emitPrints(printed, shader.name, options.errorRepeats);
  }
  return true;
}

/// --lane-stats and --stats.
void reportRun(const RunOptions &options, ShaderCompiler &compiler,
               const CompiledShader &shader, ThreadPool &pool, Stats &stats,
               double shading) {
  if (options.compile.countLanes) {
    // Summed over every pass: --iters repeats the same work.
    LaneStats lanes = laneStats();
    llvm::outs() << "lane stats: " << lanes.blocks << " masked blocks executed, "
                 << llvm::format("%.1f%%", 100.0 * lanes.meanActiveFraction(shader.width))
                 << " of " << shader.width << " lanes active on average\n";
  }
  if (options.stats) {
    llvm::errs() << "shader " << shader.name << ", width " << shader.width
                 << ", grid " << options.grid.xres << "x" << options.grid.yres
                 << ", " << pool.size() << " thread(s), " << options.iters
                 << " iteration(s)\n";
    stats.print(llvm::errs());
    llvm::errs() << "kernel cache: " << cacheUseText(compiler.cacheUse()) << "\n";
    if (const LibraryUse &lib = compiler.libraryUse(); !lib.objects.empty())
      llvm::errs() << "library functions: " << lib.objects.size() << " ("
                   << lib.compiled << " compiled, " << lib.fromDisk << " from the cache, "
                   << lib.fromMemory << " compiled earlier in this run, " << lib.prebuilt
                   << " prebuilt)\n";
    const GroupStats &g = compiler.groupStats();
    if (options.isGroup && g.opsBefore > 0)
      llvm::errs() << "group: before specialisation " << g.layersBefore << " layers, "
                   << g.opsBefore << " ops; after " << g.layersAfter << " layers, "
                   << g.opsAfter << " ops\n";
    double points = double(imageWidth(options.grid)) * imageHeight(options.grid) * options.iters;
    llvm::errs() << llvm::format("shading: %.2f ns per point\n", shading * 1e9 / points);
  }
}

int main(int argc, char **argv) {
  // Kernels compile faster without it (Jit.h).
  osl::Jit::disableMachineScheduler();
  llvm::InitLLVM init(argc, argv);
  for (int signal : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT})
    std::signal(signal, dieOnSignal);
  if (argc == 1) {
    llvm::outs() << kUsage;
    return 0;
  }
  RunOptions options;
  std::string error;
  if (!parseRunOptions(argc, argv, options, error)) {
    if (error.empty()) {
      llvm::outs() << kUsage;
      return 0;
    }
    // The error alone: a page of usage would bury it.
    llvm::errs() << "osl-run: error: " << error << " (osl-run --help lists the options)\n";
    return 2;
  }
  if (options.timeoutSeconds > 0)
    armTimeout(options.timeoutSeconds);
  if (!options.scenePath.empty())
    return renderScene(options);
  std::unique_ptr<llvm::MemoryBuffer> source = llvm::MemoryBuffer::getMemBuffer("");
  if (!options.expression.empty()) {
    std::string text = exprShaderText(options.expression);
    if (options.verbose)
      llvm::outs() << "Expression-based shader text is:\n---\n" << text << "---\n";
    source = llvm::MemoryBuffer::getMemBufferCopy(text, options.shaderPath);
  } else if (!options.isGroup) {
    auto buffer = llvm::MemoryBuffer::getFile(options.shaderPath, /*IsText=*/true);
    if (!buffer)
      return fail("cannot read '" + options.shaderPath + "': " +
                  buffer.getError().message());
    source = std::move(*buffer);
  }
  if (options.dependencies.print) {
    // -M and -MM, as oslc's (and gcc's): the dependencies instead of a
    // compile.
    if (emitDependencies(options, source->getBuffer(), error))
      return 0;
    return error.empty() ? 1 : fail(error);
  }
  if (options.infoOnly || options.infoJson) {
    auto describe = options.infoJson ? shaderQueryJson : shaderInfoText;
    std::optional<std::string> info =
        describe(source->getBuffer(), options.shaderPath, llvm::errs(),
                 options.compile.includePaths, options.compile.defines);
    if (!info)
      return 1;
    llvm::outs() << *info;
    return 0;
  }

  bool running = options.emit.empty() && !options.checkOnly;
  if (running && options.verbose && !options.groupSpec.empty())
    llvm::outs() << "Processing group specification:\n---\n"
                 << options.groupSpec << "\n---\n";
  if (options.isGroup && running && !assembleGroup(options, llvm::outs(), llvm::errs()))
    return 1;
  if (std::string error; options.isGroup && !options.group.useEntryOutputs(error))
    return fail(error);
  if (running && (options.verbose || options.oslquery))
    printGroupSummary(options, llvm::outs());
  llvm::outs().flush(); // before anything the shaders print

  options.compile.camera = {options.grid.xres, options.grid.yres};
  Stats stats;
  Stats *statsPtr = options.stats ? &stats : nullptr;
  ShaderCompiler compiler(options.compile, llvm::errs(), statsPtr);
  std::unique_ptr<CompiledShader> shader;
  if (options.emit.empty()) {
    shader = options.isGroup ? compiler.compileGroup(options.group)
                             : compiler.compile(source->getBuffer(), options.shaderPath);
    if (!shader)
      return 1;
    if (!options.isGroup && !emitDependencies(options, source->getBuffer(), error))
      return error.empty() ? 1 : fail(error);
    if (options.checkOnly)
      return 0;
  } else if (!emit(compiler, options, source->getBuffer(), statsPtr)) {
    return 1;
  } else {
    return 0;
  }

  std::vector<OutputFile> files;
  if (!resolveOutputs(options, *shader, files, error))
    return fail(error);
  double rowBytes = keepWrittenImages(options, *shader, files);
  double memoryBytes = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
  if (memoryBytes > 0 && rowBytes > memoryBytes)
    return fail(llvm::formatv("one row of the images of a {0}x{1} grid needs {2:F1} GB, "
                              "more than this machine's {3:F1} GB; write fewer outputs "
                              "(-o NAME null discards one) or shade a narrower grid",
                              options.grid.xres, options.grid.yres, rowBytes / 1e9,
                              memoryBytes / 1e9)
                    .str());
  if (options.textureCacheMB > 0)
    setTextureCacheMegabytes(float(options.textureCacheMB));
  double budget = double(options.imageMemoryMB) * (1 << 20);
  if (rowBytes * imageHeight(options.grid) > budget) {
    ThreadPool pool(options.grid.threads);
    int bandRows =
        int(std::clamp(budget / rowBytes, 1.0, double(imageHeight(options.grid))));
    return shadeInBands(options, compiler, *shader, files, bandRows, pool, stats);
  }

  options.grid.progress = true;
  ThreadPool pool(options.grid.threads);
  ShadeResult result;
  PrintLog printed; // every pass's, in order, as testshade prints each
  double shading = 0;
  if (!shadePasses(options, compiler, *shader, pool, result, printed, stats, shading))
    return 1;

  if (!writeResults(options, *shader, files, result, printed, statsPtr))
    return 1;
  reportRun(options, compiler, *shader, pool, stats, shading);
  return statusAfterShading(options);
}
