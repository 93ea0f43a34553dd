//===- GroupAssembly.h - Building a group as testshade reports it -*- C++ -*-===//
//
// testshade builds a shader group one statement at a time and reports each
// step: a shader it cannot find (and goes on without it), each connection as it makes it ("Connect
// a.x to b.y") and a connection it refuses (a missing layer, an input with
// allowconnect=0), after which it stops; then the entry layers it was
// given. OSL's testsuite compares that transcript, so osl-run walks the
// group the same way before compiling it.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUN_GROUPASSEMBLY_H
#define OSLRUN_GROUPASSEMBLY_H

#include "RunOptions.h"

#include "llvm/Support/raw_ostream.h"

namespace osl {

/// Reports the group's layers and connections in testshade's words:
/// progress on `out`, errors on `errs`. A layer whose shader is missing is
/// reported and left out of options.group, as testshade leaves it out.
/// False if no layer is left or a connection is refused.
bool assembleGroup(RunOptions &options, llvm::raw_ostream &out, llvm::raw_ostream &errs);

} // namespace osl

#endif // OSLRUN_GROUPASSEMBLY_H
