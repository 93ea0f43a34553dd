//===- GroupSummary.h - The group as testshade -v prints it -----*- C++ -*-===//
//
// Under -v or --oslquery testshade prints the group it built: serialized as
// OSL's group statements (each layer's instance values, its shader, the
// connections into it), then its layers by name, each followed by its
// parameters under --oslquery. OSL's testsuite compares that text.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUN_GROUPSUMMARY_H
#define OSLRUN_GROUPSUMMARY_H

#include "RunOptions.h"

#include "llvm/Support/raw_ostream.h"

namespace osl {

/// Prints the group options run (the one layer of a single shader or of
/// -expr) as testshade does; each layer's parameters are read from its
/// shader's source.
void printGroupSummary(const RunOptions &options, llvm::raw_ostream &out);

} // namespace osl

#endif // OSLRUN_GROUPSUMMARY_H
