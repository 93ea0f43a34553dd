//===- StringCall.h - Strings computed at run time: the host side -*- C++ -*-===//
//
// The runtime's side of string handles (OslAbi/Strings.h): the intern
// table's text and the errors string calls reported while shading.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_STRINGCALL_H
#define OSLRUNTIME_STRINGCALL_H

#include "OslAbi/Strings.h"

#include <cstdint>
#include <string>

namespace osl {

/// The text of a string handle ("" for one never issued).
std::string stringText(int32_t handle);

/// How many errors string calls have reported at run time (each once per
/// call site and cause), for a tool's exit status.
int stringErrors();

} // namespace osl

#endif // OSLRUNTIME_STRINGCALL_H
