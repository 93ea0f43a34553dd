//===- Dependencies.h - oslc's make dependencies ------------------*- C++ -*-===//
//
// oslc -M, -MM, -MD and -MMD (as gcc's) tell make which headers a shader's
// compiled form depends on; osl-run takes the same flags so that a build
// that compiles shaders with it keeps its dependency files.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUN_DEPENDENCIES_H
#define OSLRUN_DEPENDENCIES_H

#include "RunOptions.h"

#include "llvm/ADT/StringRef.h"

namespace osl {

/// Prints and/or writes options.dependencies for the shader `source`
/// (options.shaderPath). False with `error` set if the file cannot be
/// written, or with it empty after reporting why the source does not
/// preprocess.
bool emitDependencies(const RunOptions &options, llvm::StringRef source, std::string &error);

} // namespace osl

#endif // OSLRUN_DEPENDENCIES_H
