//===- MessageCall.h - setmessage and getmessage: the ABI --------*- C++ -*-===//
//
// Messages pass values between the layers of a point (setmessage in one,
// getmessage in a later one). They live in the shading thread for one
// batch: a kernel that uses them calls osl_rt_message_reset on entry. Each
// osl.set_message / osl.get_message is one call per batch with the value as
// rows of W 32-bit values (StringCall.h's layout: `kinds` has one letter
// per operand, s i f k one row, t three).
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_MESSAGECALL_H
#define OSLRUNTIME_MESSAGECALL_H

#include <cstdint>

/// Forgets the messages of the previous batch.
extern "C" void osl_rt_message_reset();

/// Stores message `name` (OSL type `typeName`, rows as `kinds`) for the
/// lanes in `laneMask`. Setting it again, or after a getmessage of it found
/// nothing, is reported at `where` (file:line) as OSL does, and changes
/// nothing.
extern "C" void osl_rt_setmessage(const char *where, const char *name, const char *typeName,
                                  const char *kinds, const int32_t *rows, int32_t width,
                                  uint32_t laneMask);

/// For the lanes in `laneMask`: where message `name` was set with the same
/// kinds, copies it over the value rows and sets the row after them (found)
/// to 1; else sets found to 0, reporting a type mismatch at `where`, or
/// remembering that the message was asked for.
extern "C" void osl_rt_getmessage(const char *where, const char *name, const char *typeName,
                                  const char *kinds, int32_t *rows, int32_t width,
                                  uint32_t laneMask);

#endif // OSLRUNTIME_MESSAGECALL_H
