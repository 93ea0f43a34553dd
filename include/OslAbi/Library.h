//===- Library.h - Library functions shared by kernels ----------*- C++ -*-===//
//
// Each library function of a kernel (a noise routine for one signature)
// is named with this prefix; the compiler moves the
// definitions so named out of the kernel and compiles each once
// (OslCompiler/LibraryObjects.h).
//
//===----------------------------------------------------------------------===//
#ifndef OSLABI_LIBRARY_H
#define OSLABI_LIBRARY_H

namespace osl::abi {

constexpr const char *kLibrarySymbolPrefix = "osl.lib.";

} // namespace osl::abi

#endif // OSLABI_LIBRARY_H
