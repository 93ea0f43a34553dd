//===- LibraryFunctions.h - Library routines as functions -------*- C++ -*-===//
//
// A library routine (noise of every kind, spline inversion) is lowered to a
// call of a private function built from a recipe: a string naming
// everything its code is built from. Two calls of one recipe share the
// function, and its compiled object is keyed by the recipe, so a routine
// compiled before need not be built at all: its function is then a
// declaration (see LibraryRoutineNeeds). osl-derivatives differentiates
// through a call by its dual routine or a copy of its code, and
// osl-inline-library puts small routines back in place.
//
//===----------------------------------------------------------------------===//
#ifndef OSLLANES_LIBRARYFUNCTIONS_H
#define OSLLANES_LIBRARYFUNCTIONS_H

#include "mlir/Dialect/Func/IR/FuncOps.h"
#include "mlir/IR/Builders.h"

#include <functional>

namespace mlir::osl {

/// On a library function: the recipe its code is built from.
constexpr const char *kLibraryRecipeAttr = "osl.library_recipe";
/// On a call of a library function: it stays a call (osl-inline-library
/// does not inline it), decided at the call site alone, so that the kernel
/// is the same whether the function's code was built or found compiled.
constexpr const char *kKeepCallAttr = "osl.keep_call";

/// On a library function compiled before (a declaration): the library
/// functions its object calls (noise_by_kind calls each kind's routine),
/// kept in the module so that their objects are linked beside it.
constexpr const char *kLibraryCalleesAttr = "osl.library_callees";

/// On a library function: the indices of its arguments that are
/// derivatives themselves (Gabor noise's dP/dx and dP/dy for its filter):
/// OSL takes a derivative of a derivative as 0, so they have no tangents.
constexpr const char *kDerivativeArgsAttr = "osl.derivative_args";

/// Whether a recipe's compiled object is at hand (the compiler's library
/// cache answers; null: never, every routine is built).
using LibraryObjectAvailable = std::function<bool(StringRef recipe)>;

/// The function of library routine `routine` built from `recipe`, in the
/// module around `anchor`: found, or made now. It gets its code from
/// `build` (given the entry block's arguments) unless it has code already,
/// or it is new, `needCode` is unset and `compiled` (asked then only) says
/// its object is at hand: then it is a declaration (until a later call
/// needs its code).
func::FuncOp libraryFunction(OpBuilder &b, Operation *anchor, StringRef routine,
                             StringRef recipe, FunctionType type, bool needCode,
                             function_ref<bool()> compiled,
                             function_ref<SmallVector<Value>(OpBuilder &, ValueRange)> build);

/// The recipe of a routine's dual (its code and its derivatives along x
/// and y, osl-derivatives).
inline std::string dualRecipeOf(StringRef recipe) { return (recipe + " dual x y").str(); }

/// The library function `call` calls (one with a recipe), if it does.
func::FuncOp libraryCallee(func::CallOp call);

/// Copies `callee`'s single-block body, its terminator included, at `b`'s
/// insertion point with its arguments bound to `args`; returns the copied
/// terminator, whose operands are what the copy returns (and stay so when
/// a value is replaced).
func::ReturnOp cloneBody(OpBuilder &b, func::FuncOp callee, ValueRange args);

/// Replaces `call` by a copy of its callee's single-block body; returns
/// what replaces its results.
SmallVector<Value> inlineCall(func::CallOp call, func::FuncOp callee);

/// `available`, or when it is null and `assumeAll` is set, every routine
/// (the passes' assume-compiled option, for tests).
inline LibraryObjectAvailable orAssumedCompiled(LibraryObjectAvailable available,
                                                bool assumeAll) {
  if (!available && assumeAll)
    return [](StringRef) { return true; };
  return available;
}

/// Whether `v` is a constant, or lanes of one: a copy of a routine it is
/// passed to would fold it.
bool isConstantOperand(Value v);

} // namespace mlir::osl

#endif // OSLLANES_LIBRARYFUNCTIONS_H
