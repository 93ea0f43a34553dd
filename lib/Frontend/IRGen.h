//===- IRGen.h - Syntax tree to the osl dialect -----------------*- C++ -*-===//
//
// Variables are SSA: each variable's current value lives in the emitter
// (Var::val) and is replaced on assignment. Structured control flow
// (osl.if, osl.while) carries the variables its regions assign, found by a
// syntactic scan (scanAssigned). User functions are inlined at each call.
// Strings are compile-time constants, strings chosen per point among
// them, or strings computed at run time (i32 handles, see RValue). A string
// variable an `if` changes leaves it as a choice or a handle (the if yields
// an i32); loops cannot change strings yet.
//
// break, continue, return and exit() set hidden boolean flags ("$break",
// "$continue", "$returned", "$exit"); the statements after one that may
// have set a flag run under `if (!flags)`, and loops also test them. A flag
// set under a uniform condition stays uniform, so only divergent jumps cost
// masking, and a flag that is never set folds away.
//
//===----------------------------------------------------------------------===//
#ifndef OSLFRONTEND_IRGEN_H
#define OSLFRONTEND_IRGEN_H

#include "Ast.h"
#include "OslDialect/OslDialect.h"
#include "OslFrontend/Frontend.h"

#include "mlir/Dialect/Func/IR/FuncOps.h"
#include "mlir/IR/Builders.h"
#include "llvm/ADT/DenseMap.h"
#include "llvm/ADT/DenseSet.h"
#include "llvm/ADT/StringMap.h"
#include "llvm/ADT/StringSet.h"

#include <deque>
#include <optional>
#include <map>
#include <set>

namespace osl::frontend {

/// A value of some OSL type: one IR value for numbers and triples, a
/// compile-time string, or the elements of an array (or the 16 f32 values
/// of a matrix, row-major).
///
/// A string chosen per point (from a string array with a run-time index,
/// or by `c ? "a" : "b"`) is one of `choices`, selected by the i32 `value`;
/// uses such as noise names then run once per choice, under masks.
struct RValue {
  OslType type;
  mlir::Value value;
  std::string str;
  std::vector<std::string> choices;
  std::vector<mlir::Value> elems;
  /// Structs: one value per field; arrays of structs: one array per field;
  /// string arrays: one string per element.
  std::vector<RValue> fields;

  /// A string chosen per point (see above).
  bool isStringChoice() const { return type.isString() && !choices.empty(); }
  /// A string computed at run time (format, concat, substr...): `value` is
  /// its i32 handle in the runtime's intern table (OslAbi/Strings.h).
  bool isRuntimeString() const { return type.isString() && value && choices.empty(); }
  /// A string known when the shader is compiled (one string, no choice).
  bool isKnownString() const { return type.isString() && !value; }

  static RValue num(OslType t, mlir::Value v) {
    RValue r;
    r.type = t;
    r.value = v;
    return r;
  }
  static RValue string(std::string s) {
    RValue r;
    r.type = OslType(BaseType::String);
    r.str = std::move(s);
    return r;
  }
  static RValue runtimeString(mlir::Value handle) {
    RValue r;
    r.type = OslType(BaseType::String);
    r.value = handle;
    return r;
  }
  static RValue voidValue() { return RValue(); }
};

/// A shader parameter as isconnected() names it: its name, with ".field"
/// for a struct's field; an empty path for a variable that is none.
struct ParamRef {
  std::string path;
  bool geometryData = false; // a lockgeom=0 parameter
};

struct Var {
  std::string name;
  OslType type;
  SrcLoc loc;
  unsigned id = 0;       // creation order: carried values are sorted by it
  RValue val;            // the current value
  bool isGlobal = false; // a shader global, read lazily (see readVar)
  bool isOutputParam = false;
  /// A function's non-output parameter: oslc warns when a function writes
  /// one (an error under -Werror). Parameters are references in OSL, so the
  /// write reaches the caller's variable (`writtenThrough`). (Globals, u
  /// and v too, are writable, as testshade's lazyglobals test shows.)
  bool readOnly = false;
  bool writtenThrough = false;
  /// A shader's input parameter: oslc refuses writes to it ("cannot write
  /// to non-output parameter"); and a global oslc declares read-only (u, v,
  /// Ng, dPdu, time...): it warns of writes, which take effect.
  bool isShaderInput = false;
  bool isReadOnlyGlobal = false;
  /// The shader parameter this variable is, or a function's parameter
  /// refers to (isconnected() answers for it).
  ParamRef param;
};

/// Same return and parameter types (and outputs).
bool sameSignature(const FunctionDecl &a, const FunctionDecl &b);
/// A function's signature as oslc's warnings write it: "int f (float,
/// output color)", "struct S" for a struct.
std::string oslcSignatureText(const FunctionDecl &fn);

struct Scope;
/// A function and the scope it was defined in (its free names resolve
/// there: globals for top-level functions, the enclosing body for nested
/// ones).
struct FunctionRef {
  const FunctionDecl *decl;
  Scope *scope;
};

struct Scope {
  Scope *parent = nullptr;
  llvm::StringMap<Var *> vars;
  llvm::StringMap<std::vector<FunctionRef>> funcs;
};

/// One step of an lvalue: an array element or a triple component, with
/// its index (a constant when `constIndex >= 0`).
struct Access {
  int field = -1; // a struct field
  bool component = false;
  mlir::Value index; // i32
  int64_t constIndex = -1;
  int length = 0; // number of elements or 3
  SrcLoc loc;
};

struct LValue {
  Var *var = nullptr;
  std::vector<Access> path;
  OslType type; // of the designated element
};

class IRGen {
public:
  IRGen(mlir::MLIRContext &ctx, Diagnostics &diags,
        llvm::ArrayRef<ParamOverride> overrides, const FrontendOptions &options);

  mlir::OwningOpRef<mlir::ModuleOp> emitProgram(const Program &program);

  // --- building blocks shared with Builtins.cpp -------------------------------
  /// The image testshade's camera sees (the grid's size).
  const mlir::osl::CameraImage &cameraImage() const { return options.camera; }
  /// The --userdata datum called `name`, or null.
  const UserDatum *userDatum(llvm::StringRef name) const {
    for (const UserDatum &d : options.userData)
      if (d.name == name)
        return &d;
    return nullptr;
  }
  mlir::OpBuilder &builder() { return b; }
  const FrontendOptions &frontendOptions() const { return options; }
  /// The length of the array output connected to input `name`, or 0.
  int connectedArrayLength(llvm::StringRef name) const;
  /// The shader parameter `e` names: a variable, a struct field of one, or
  /// an element of one (the whole parameter) (ConnectionBuiltins.cpp).
  ParamRef parameterOf(const Expr &e);
  /// The working RGB space of the color functions (a compile option).
  llvm::StringRef workingColorSpace() const { return options.colorSpace; }
  /// The ray being shaded: raytype() is 1 for it.
  llvm::StringRef rayType() const { return options.rayType; }
  /// The name of the shader being emitted.
  llvm::StringRef shaderName() const { return shader; }
  /// Its layer's and group's names as testshade gives them (--layer,
  /// --groupname; unnamed, SHADER_0 and unnamed_group_1).
  std::string layerName() const {
    return options.layerName.empty() ? shader + "_0" : options.layerName;
  }
  std::string groupName() const {
    return groupNameOrDefault(options.groupName);
  }
  /// "file:line" of `l`, as OSL's run-time reports name places.
  std::string fileLine(SrcLoc l) const {
    return diags.fileName(l.file).str() + ":" + std::to_string(l.line);
  }
  Diagnostics &diagnostics() { return diags; }
  /// --debugnan (DebugNan.cpp): reports the points where `v`, stored into
  /// variable `name` from `source` by `assignOp` ("=", "*=", ...; "" for an
  /// initializer), has a NaN or infinite component.
  bool checkNotNan(const std::string &name, const RValue &v, const Expr &source,
                   llvm::StringRef assignOp, SrcLoc l);
  mlir::Location loc(SrcLoc l);
  bool error(SrcLoc l, const llvm::Twine &msg) {
    diags.error(l, msg);
    return false;
  }
  /// An error that depends on a value (a name that must be known when the
  /// shader is compiled, a valid noise or space name...): not reported
  /// while checkUncalledFunctions emits a function on made-up arguments,
  /// where it abandons that function's check instead.
  bool valueError(SrcLoc l, const llvm::Twine &msg) {
    if (checkingUncalled)
      return false;
    return error(l, msg);
  }

  /// Arrays from this length on are read by a non-constant index through
  /// osl.table_read when every element is a compile-time constant, else
  /// osl.pick: one gather instead of a compare and a select per element.
  static constexpr int kTableMinLength = 8;

  mlir::Value constInt(int32_t v, SrcLoc l);
  mlir::Value constFloat(float v, SrcLoc l);
  mlir::Value constBool(bool v, SrcLoc l);
  mlir::Value constTriple(float x, float y, float z, SrcLoc l);
  /// Zero of a non-array numeric type, a zeroed array, or "" for strings.
  RValue zeroValue(OslType t, SrcLoc l);
  /// Appends `element` to array `array`'s elems: its value, or a matrix's
  /// 16 (an array of matrices holds them one matrix after another).
  static void appendElement(RValue &array, const RValue &element);
  static std::optional<int64_t> getConstInt(mlir::Value v);
  static std::optional<bool> getConstBool(mlir::Value v);
  /// An int, float or bool constant as a double.
  static std::optional<double> getConstScalar(mlir::Value v);

  /// osl.convert to another base type (uniformity kept), folding constants.
  mlir::Value convert(mlir::Value v, mlir::Type toBase, SrcLoc l);
  /// Implicit conversion (assignment rules): int->float, scalars->triples,
  /// triple<->triple, bool->int/float; arrays element by element.
  /// Reports "cannot convert 'A' to 'B' <context>".
  std::optional<RValue> coerce(RValue v, OslType to, SrcLoc l,
                               const llvm::Twine &context);
  /// Explicit cast: coerce plus float->int truncation.
  std::optional<RValue> cast(RValue v, OslType to, SrcLoc l);
  /// What `=` and initializers convert: coerce, plus float->int, which
  /// oslc accepts there (truncating, with a warning of lost precision).
  std::optional<RValue> coerceForAssignment(RValue v, OslType to, SrcLoc l,
                                            const llvm::Twine &context);
  /// Is `from` implicitly convertible to `to`; cost for overload ranking
  /// (0 exact, larger is worse), or -1.
  static int conversionCost(OslType from, OslType to);
  /// A condition as i1: numbers and triples compare != 0.
  std::optional<mlir::Value> toBool(const RValue &v, SrcLoc l);

  std::optional<RValue> emitExpr(const Expr &e, const OslType *expected = nullptr);

  /// Arithmetic/comparison/bitwise operators on two values.
  std::optional<RValue> emitBinaryOp(llvm::StringRef op, RValue lhs, RValue rhs,
                                     SrcLoc l);

  /// Assignable places: a variable, an array element, a component.
  std::optional<LValue> emitLValue(const Expr &e);
  RValue loadLValue(const LValue &lv, SrcLoc l);
  bool storeLValue(const LValue &lv, RValue v, SrcLoc l);

  /// Calls `emitOne` with the string `s` names: once if it is known, else
  /// once per choice under `if (choice == k)`, so lanes run only the
  /// choices they made (lane-group filtering); the results merge per lane,
  /// as do the variables in `assigned` (which `emitOne` may write). With
  /// `wantValue` false the calls' results are void.
  std::optional<RValue>
  forEachStringChoice(const RValue &s, SrcLoc l,
                      llvm::function_ref<std::optional<RValue>(const std::string &)> emitOne,
                      const llvm::StringSet<> &assigned = {}, bool wantValue = true);
  /// A string chosen by `index` (i32) among `strings`.
  RValue stringChoice(std::vector<RValue> strings, mlir::Value index, SrcLoc l);
  /// The run-time handle (i32) of any string: compile-time strings are
  /// interned (osl.string_constant), a choice selects among its handles.
  mlir::Value stringHandle(const RValue &s, SrcLoc l);
  /// What testshade's renderer reports when the point runs (an unknown
  /// space name, say): "ERROR: message", once per run.
  void reportAtRunTime(const std::string &message, SrcLoc l);
  /// The strings `s` may be when the shader is compiled (one, or its
  /// choices); reports that `what` must be known then for a string
  /// computed at run time.
  std::optional<std::vector<std::string>> compileTimeStrings(const RValue &s, SrcLoc l,
                                                             const llvm::Twine &what);

  /// The value of a shader global (emitted once, at the top of the shader).
  mlir::Value getGlobal(llvm::StringRef name, mlir::Type base, SrcLoc l);

  /// exit(): the shader stops for the lanes that reach it.
  void emitExit(SrcLoc l);

  // --- matrices (IRGenMatrix.cpp) ---------------------------------------------
  // 16 f32 values, row-major; points are row vectors (p' = p * M), as in
  // Imath. Operations on constants fold, computing in float as the ops
  // would, so named-space matrices and literals cost nothing at run time.
  using MatrixElems = std::vector<mlir::Value>;
  static RValue matrixValue(MatrixElems elems);
  /// f (any number) on the diagonal, 0 elsewhere.
  RValue scaledIdentity(mlir::Value f, SrcLoc l);
  RValue constMatrix(const mlir::osl::Matrix44 &m, SrcLoc l);
  /// The matrix from space `from` to space `to` (testshade's spaces and
  /// its camera's); a space it does not know contributes the identity, as
  /// in OSL, and clears `known`.
  RValue namedMatrix(llvm::StringRef from, llvm::StringRef to, SrcLoc l, bool &known);
  MatrixElems matrixMultiply(const MatrixElems &a, const MatrixElems &m, SrcLoc l);
  MatrixElems matrixScale(const MatrixElems &a, mlir::Value f, SrcLoc l);
  /// Imath's Matrix44::inverse: the affine shortcut when the last column is
  /// (0,0,0,1), else Gauss-Jordan with partial pivoting; singular -> identity.
  MatrixElems matrixInverse(const MatrixElems &a, SrcLoc l);
  MatrixElems matrixTranspose(const MatrixElems &a);
  mlir::Value matrixDeterminant(const MatrixElems &a, SrcLoc l);
  /// transform(M, x): points divide by w (0 where w = 0), vectors ignore
  /// the translation, normals use the inverse transpose.
  mlir::Value transformByMatrix(const MatrixElems &m, mlir::Value x, BaseType kind,
                                SrcLoc l);
  /// *, /, == and != with a matrix operand (emitBinaryOp).
  std::optional<RValue> emitMatrixBinaryOp(llvm::StringRef op, RValue lhs, RValue rhs,
                                           SrcLoc l);

  // Lane arithmetic on f32 (and i1/i32 for cmp/select) that folds constants.
  mlir::Value fAdd(mlir::Value x, mlir::Value y, SrcLoc l);
  mlir::Value fSub(mlir::Value x, mlir::Value y, SrcLoc l);
  mlir::Value fMul(mlir::Value x, mlir::Value y, SrcLoc l);
  /// Safe division, as osl.div (folded when both sides are constants).
  mlir::Value fDiv(mlir::Value x, mlir::Value y, SrcLoc l);
  mlir::Value fNeg(mlir::Value x, SrcLoc l);
  mlir::Value fAbs(mlir::Value x, SrcLoc l);
  /// osl.cmp, folded when both sides are constant scalars; `unordered` for
  /// the shader's own comparisons (see osl.cmp).
  mlir::Value cmp(llvm::StringRef pred, mlir::Value x, mlir::Value y, SrcLoc l,
                  bool unordered = false);
  mlir::Value select(mlir::Value c, mlir::Value x, mlir::Value y, SrcLoc l);
  /// Per lane, `a` where `c` else `b`, field by field and element by
  /// element (same types; not strings).
  std::optional<RValue> selectFields(mlir::Value c, const RValue &a, const RValue &b,
                                     SrcLoc l);
  mlir::Value boolAnd(mlir::Value x, mlir::Value y, SrcLoc l);
  mlir::Value boolOr(mlir::Value x, mlir::Value y, SrcLoc l);
  mlir::Value boolNot(mlir::Value x, SrcLoc l);
  /// Whether `e` names a variable in scope (which OSL's ops read where
  /// they run, not where the operand is written).
  bool isVariableRead(const Expr &e) {
    return e.kind == ExprKind::Ident && lookupVar(e.name);
  }

private:
  // --- program structure -----------------------------------------------------
  bool emitShader(const ShaderDecl &shader, mlir::func::FuncOp func);
  /// Declares a shader parameter; with runDefault false (nothing reads it)
  /// a default with effects (exit, printf, a user function) is not run.
  bool emitParam(const Param &p, Scope *scope, bool runDefault);
  bool emitStructParam(const Param &p, Scope *scope);
  bool emitStringArrayParam(const Param &p, OslType t, const std::string &value, Scope *scope);
  std::optional<RValue> paramDefault(const Param &p, OslType &t, const ParamOverride *ov,
                                     bool runDefault);
  const ParamOverride *overrideOf(const std::string &name) const;
  void wrapInParamOps(RValue &v, const std::string &name, bool perGeometry, SrcLoc at);

  std::optional<RValue> overrideValue(const Param &p, const std::string &text);
  /// Calls fn on each leaf of a struct value (nested structs flattened),
  /// named NAME.FIELD as OSL names a struct parameter's fields; on the value
  /// itself when it is not a struct. An array of structs is one leaf.
  void forEachStructLeaf(const std::string &name, const OslType &type, RValue &value,
                         llvm::function_ref<void(const std::string &, RValue &)> fn);
  /// A declaration's initializer (an expression or `{...}`) as `type`;
  /// sets the length of unsized arrays.
  std::optional<RValue> emitInitializer(const Expr &init, OslType &type,
                                        llvm::StringRef name, SrcLoc l);
  void collectFunctions(const Stmt &s);

  // --- scopes and variables --------------------------------------------------
  Scope *newScope(Scope *parent);
  Var *declareVar(Scope *scope, const std::string &name, OslType type, SrcLoc l,
                  RValue init);
  Var *lookupVar(llvm::StringRef name);
  /// The current value of a variable (materializes a global).
  RValue readVar(Var *v, SrcLoc l);
  std::vector<FunctionRef> lookupFunctions(llvm::StringRef name);

  // --- statements ------------------------------------------------------------
  /// `tail`: the statement ends the function (or shader) on its path, so
  /// a `return` there is supported.
  bool emitStmt(const Stmt &s, bool tail);
  bool emitStmtList(const std::vector<StmtPtr> &stmts, size_t from, bool tail);
  /// Statements [from, end) of `stmts`, on the lanes where `jumped` (the
  /// or of `flags`, set by a break, continue, return or exit before them)
  /// is false.
  bool emitUnlessJumped(mlir::Value jumped, const std::vector<Var *> &flags, SrcLoc l,
                        const std::vector<StmtPtr> &stmts, size_t from, bool tail);
  bool emitScoped(const Stmt &s, bool tail);
  bool emitScoped(const std::vector<StmtPtr> &stmts, bool tail);
  bool emitDecl(const Stmt &s);
  bool emitIf(const Stmt &s, bool tail);
  bool emitLoop(const Stmt &s);
  bool emitWhile(const Expr *cond, const Stmt &body, const Expr *step,
                 const llvm::StringSet<> &names, SrcLoc l);
  bool emitJump(const Stmt &s, bool tail);

  // --- jumps (break, continue, return, exit) as flags ------------------------
  Var *declareFlag(Scope *scope, llvm::StringRef name, SrcLoc l);
  void setFlag(Var *flag, SrcLoc l);
  /// i1 that is true where a jump has left the current statement list (the
  /// innermost loop's break/continue when `withContinue`, the function's
  /// return, exit); null when no flag can be set (nothing to guard).
  mlir::Value jumpedCondition(SrcLoc l, bool withContinue,
                              std::vector<Var *> *flagsOut = nullptr);
  /// The loops of the function being emitted (outer ones are not its own).
  bool inLoop() const;

  /// Names assigned anywhere in a statement or expression (including
  /// through output arguments and the bodies of called user functions).
  void scanAssigned(const Stmt &s, llvm::StringSet<> &names);
  void scanAssigned(const Expr &e, llvm::StringSet<> &names);
  /// The arguments a library call writes (sincos's, split's results,
  /// getattribute's value...); none for a user function of that name.
  llvm::SmallVector<size_t> libraryOutputArgs(const Expr &e) const;
  bool hasSideEffects(const Expr &e);
  /// Whether `e` may only run on the lanes that evaluate it: it has side
  /// effects or an index checked at run time.
  bool mustRunMasked(const Expr &e);
  const llvm::StringSet<> &functionAssigned(const FunctionDecl *fn);
  /// Whether `fn` may write its parameter `name` (see Var::writtenThrough).
  bool writesParam(const FunctionDecl &fn, llvm::StringRef name) {
    return functionAssigned(&fn).count(name) > 0;
  }
  /// The outer variables a region must carry, sorted by creation.
  std::vector<Var *> carriedVars(const llvm::StringSet<> &names);
  std::vector<mlir::Value> flatten(const std::vector<Var *> &vars, SrcLoc l);
  void unflatten(const std::vector<Var *> &vars, mlir::ValueRange values);
  std::vector<std::pair<Var *, RValue>> stringSnapshot(const llvm::StringSet<> &names);
  /// The string variables among `names` that a loop (`scalarsToo`) or an
  /// if (string arrays only) assigns are carried from now on as run-time
  /// handles (i32 leaves), like numbers; an if keeps single strings known
  /// when it can (choices, see mergeStringArms).
  void carryStringsAsHandles(const llvm::StringSet<> &names, bool scalarsToo);
  /// Makes `v`'s string (or each string of its array) a run-time handle.
  void materializeStrings(Var *v, SrcLoc l);
  bool checkStrings(const std::vector<std::pair<Var *, RValue>> &snap, SrcLoc l,
                    llvm::StringRef what);
  /// The string fields of the carried struct variables (not carried like
  /// other leaves): an `if` merges them (takeStructStrings), a loop may not
  /// change them yet (checkStructStrings).
  std::vector<std::pair<Var *, std::vector<RValue>>>
  structStringSnapshot(const std::vector<Var *> &carried);
  bool checkStructStrings(const std::vector<std::pair<Var *, std::vector<RValue>>> &snap,
                          SrcLoc l, llvm::StringRef what);
  /// Each snapshot variable's string fields now; restores the snapshot's.
  std::vector<std::vector<RValue>>
  takeStructStrings(const std::vector<std::pair<Var *, std::vector<RValue>>> &snap);
  /// The snapshot's variables' current values; restores the snapshot.
  std::vector<RValue> takeStrings(const std::vector<std::pair<Var *, RValue>> &snap);
  /// A string variable the arms of an `if` leave different: what each arm
  /// yields (an index into `choices` when both arms' strings are known at
  /// compile time, else a run-time handle).
  struct StringArms {
    Var *var = nullptr;
    /// For a struct variable's string field: which of the if's struct
    /// snapshots it is in, and which of its string fields (collected in
    /// order); field -1 for a string variable.
    size_t structIndex = 0;
    int field = -1;
    mlir::Value thenValue, elseValue;
    std::vector<std::string> choices;
    /// The merged string, from the if's result for it.
    RValue merged(mlir::Value result) const;
  };
  /// The arms' yields for a string they leave different.
  StringArms mergeStringPair(const RValue &thenString, const RValue &elseString,
                             mlir::Block *thenBlock, mlir::Block *elseBlock, SrcLoc l);
  /// Sets the variables both arms leave equal; returns the others, whose
  /// yielded values it emits at the ends of the arms' blocks.
  std::vector<StringArms>
  mergeStringArms(const std::vector<std::pair<Var *, RValue>> &snap,
                  const std::vector<RValue> &thenStrings,
                  const std::vector<RValue> &elseStrings, mlir::Block *thenBlock,
                  mlir::Block *elseBlock, SrcLoc l);
  /// An osl.if on `cond` carrying the variables in `assigned`; with
  /// `wantValue`, the arms' values (unified) are an extra result.
  std::optional<RValue> emitIfRegion(mlir::Value cond, SrcLoc l,
                                     const llvm::StringSet<> &assigned,
                                     llvm::function_ref<std::optional<RValue>()> thenArm,
                                     llvm::function_ref<std::optional<RValue>()> elseArm,
                                     bool wantValue);

  // --- expressions -----------------------------------------------------------
  std::optional<RValue> emitIdent(const Expr &e);
  std::optional<RValue> emitUnary(const Expr &e, const OslType *expected);
  std::optional<RValue> emitLogical(const Expr &e);
  std::optional<RValue> emitTernary(const Expr &e, const OslType *expected);
  std::optional<RValue> emitAssign(const Expr &e);
  std::optional<RValue> emitIncDec(const Expr &e);
  /// Warns of a write to a read-only variable (Var::readOnly) and marks it
  /// written through; false when warnings are errors. `how` says how it is
  /// written when not directly.
  bool checkWritable(const LValue &lv, SrcLoc l, const llvm::Twine &how = "");
  std::optional<RValue> emitIndexOrMember(const Expr &e);
  std::optional<RValue> emitCall(const Expr &e, const OslType *expected);
  std::optional<RValue> emitUserCall(const Expr &e,
                                     const std::vector<FunctionRef> &cands,
                                     const OslType *expected);
  /// A library function (Builtins.cpp), or an error if `e` names none.
  std::optional<RValue> emitBuiltin(const Expr &e, const OslType *expected);
  const StructDecl *lookupStruct(llvm::StringRef name) const;
  /// `S(a, b, ...)`: a struct from one value per field.
  std::optional<RValue> emitStructConstructor(const StructDecl &s, const Expr &e);
  /// The best-ranked candidate for these arguments, or null. Candidates
  /// the arguments rank equally are told apart by their return types
  /// (float, int, color, vector, point, normal, matrix, string, closure,
  /// struct, void, in that order), with oslc's "Ambiguous call" warning at
  /// `call`. An argument with `initListSizes[k] >= 0` is an initializer list of that many
  /// values, not evaluated yet: it fits a struct with as many fields, an
  /// array of that length (or unsized) or a triple of three.
  const FunctionRef *resolveOverload(const std::vector<FunctionRef> &cands,
                                     const std::vector<RValue> &args,
                                     const std::vector<std::optional<LValue>> &lvalues,
                                     const OslType *expected,
                                     const std::vector<int> *initListSizes = nullptr,
                                     const Expr *call = nullptr);
  /// oslc's "Ambiguous call" warning: the call, then the candidates best
  /// first, each as file:line<TAB>declaration.
  std::string ambiguityMessage(const Expr &call, const std::vector<RValue> &args,
                               const std::vector<const FunctionRef *> &ranked);
  /// An operator with a struct operand calls the user's `__operator__X__`
  /// overload when one takes the operands; returns false if none does.
  bool tryOverloadedOperator(llvm::StringRef op, const Expr &site,
                             std::vector<RValue> operands, std::optional<RValue> &result);
  std::optional<RValue> inlineCall(const FunctionRef &f, const Expr &call,
                                   std::vector<RValue> &args,
                                   std::vector<std::optional<LValue>> &lvalues);
  /// Common type of two branches (ternary) or nullopt.
  std::optional<OslType> unify(OslType a, OslType b);

  /// The access an Index or Member expression makes into `baseType`.
  std::optional<Access> makeAccess(OslType baseType, const Expr &e, OslType &elemType);
  RValue updatePath(const RValue &cur, const std::vector<Access> &path, size_t k,
                    const RValue &newValue, SrcLoc l);
  RValue elementAt(const RValue &cur, const Access &a, int j, SrcLoc l);
  /// OSL's report of an index out of range for `e` (an Index expression):
  /// `index` is the number, or "%d" for a format.
  std::string indexRangeMessage(const Expr &e, const std::string &index, int length);
  /// An element of an array of kTableMinLength or more numbers or triples
  /// by a non-constant index (clamped): osl.table_read when the elements
  /// are constants, else osl.pick (a stack block and a gather at the lane
  /// level instead of a select per element; shorter chains cost less than
  /// the stores).
  std::optional<RValue> readLongArray(const RValue &cur, const Access &a, SrcLoc l);
  /// Reads element `a` of an array (elems) or triple, index clamped, or a
  /// struct's field.
  RValue readAccess(const RValue &cur, const Access &a, SrcLoc l);
  /// The type of field j of a struct or (one array per field) of an array
  /// of structs.
  static OslType fieldType(const OslType &structType, size_t j);
  /// Reports struct types the IR cannot hold yet (string fields, array
  /// fields in arrays of structs).
  bool checkStructType(const OslType &t, SrcLoc l);
  /// An array of structs from its elements' values (held one array per
  /// field, nested structs likewise).
  RValue packStructArray(const OslType &arrayType, const std::vector<RValue> &elems);
  /// i1: does the (clamped) index select element k of n?
  mlir::Value selectsElement(mlir::Value index, int k, int n, SrcLoc l);

  mlir::MLIRContext &ctx;
  Diagnostics &diags;
  llvm::ArrayRef<ParamOverride> overrides;
  const FrontendOptions &options;
  std::string shader;
  /// String variables carried through control flow as handles (see
  /// carryStringsAsHandles).
  llvm::DenseSet<const Var *> stringsAsHandles;
  /// The Index expression whose base is being emitted: a matrix may be
  /// indexed there (its row, then the outer Index picks the column).
  const Expr *rowAccessOK = nullptr;
  mlir::OpBuilder b;
  struct OpCounter : mlir::OpBuilder::Listener {
    size_t count = 0;
    void notifyOperationInserted(mlir::Operation *, mlir::OpBuilder::InsertPoint) override {
      ++count;
    }
  } opCounter;
  /// False (after an error) once the shader has grown past kMaxOps.
  bool checkSize(SrcLoc l);
  mlir::Block *entryBlock = nullptr;
  mlir::Operation *lastGlobal = nullptr; // globals are emitted at the top
  /// Where the shader body's outermost statements are emitted.
  mlir::Block *bodyBlock = nullptr;

  std::deque<Scope> scopes;
  std::deque<Var> vars;
  /// A lockgeom=0 parameter: in its metadata or on the command line.
  bool isPerGeometry(const Param &p) const;
  Scope *root = nullptr;
  Scope *current = nullptr;
  /// The shader's parameters' scope and its body's outermost one: oslc
  /// declares the globals in the same scope, so their names are taken there.
  Scope *shaderParams = nullptr, *shaderBody = nullptr;
  unsigned nextVarId = 0;

  /// All user functions by name (for the assignment scan).
  llvm::StringMap<std::vector<const FunctionDecl *>> allFunctions;

  struct InlineFrame {
    const FunctionDecl *fn;
    Var *returnVar = nullptr;
    Var *returned = nullptr; // "$returned"
    size_t loopBase = 0;     // loopStack size at the call
  };
  struct LoopFrame {
    Var *broke = nullptr;     // "$break"
    Var *continued = nullptr; // "$continue"
  };
  std::vector<LoopFrame> loopStack;
  Var *shaderReturned = nullptr; // `return` in the shader body
  Var *exitFlag = nullptr;
  std::vector<InlineFrame> inlineStack;
  /// How many file-level functions precede the shader.
  int shaderPosition = 0;
  /// Where the code being emitted stands among the file-level functions:
  /// in the innermost one being inlined, else in the shader.
  int usePosition() const;
  bool redefinitionApplies(const FunctionDecl &later, const FunctionDecl &kept) const;
  /// The user functions some call inlined (the others are checked alone,
  /// see checkUncalledFunctions).
  llvm::DenseSet<const FunctionDecl *> inlinedFunctions;
  bool checkingUncalled = false;
  /// oslc checks every function, called or not: emits each top-level
  /// function no call reached once, with zero arguments, into a scratch
  /// function that is then erased. False after an error.
  bool checkUncalledFunctions(const Program &program, mlir::ModuleOp module);
  /// What each user function's body assigns (see scanAssigned).
  std::map<const FunctionDecl *, llvm::StringSet<>> functionAssignedCache;

  llvm::StringMap<mlir::Value> globalValues;
  /// The shader globals' variables, in their declaration order.
  llvm::SmallVector<Var *> globalVars;
  unsigned exprDepth = 0;
  llvm::StringMap<const StructDecl *> structsByName;

  /// Arguments a call already evaluated before it fell back to the library
  /// function: emitExpr returns them instead of emitting them again.
  llvm::DenseMap<const Expr *, RValue> preEvaluated;
  struct PreEvaluated {
    IRGen &gen;
    std::vector<const Expr *> keys;
    PreEvaluated(IRGen &gen, const Expr &call, const std::vector<RValue> &args);
    ~PreEvaluated();
  };
};

/// Library functions (Builtins.cpp). Returns nullopt with an error
/// reported, or sets `known` to false (and reports nothing) when `name`
/// is not a builtin.
std::optional<RValue> emitBuiltinCall(IRGen &gen, const Expr &call,
                                      const OslType *expected, bool &known);
/// Is `name` a builtin function (supported or not)?
bool isBuiltinName(llvm::StringRef name);
/// matrix(...) constructors and the matrix library (determinant, transpose,
/// getmatrix, transform by a matrix or to the camera's spaces) (MatrixBuiltins.cpp);
/// `known` is false when `call` is none of them.
std::optional<RValue> emitMatrixBuiltin(IRGen &gen, const Expr &call, bool &known);
/// The string functions on strings computed at run time: format, concat,
/// strlen, hash, startswith, endswith, getchar, substr, stoi, stof,
/// regex_search, regex_match (StringBuiltins.cpp); `known` is false when
/// `call` is none of them.
std::optional<RValue> emitStringBuiltin(IRGen &gen, const Expr &call, bool &known);
/// `type(args...)` for int, float, string and the triples
/// (ConstructorBuiltins.cpp):
/// also what `{args...}` means for a value of such a type.
std::optional<RValue> emitTypeConstructor(IRGen &gen, OslType type,
                                          const std::vector<ExprPtr> &args, SrcLoc loc);
/// The closures of OSL's standard library (ClosureBuiltins.cpp); `known`
/// is false when `call` is none of them.
std::optional<RValue> emitClosureBuiltin(IRGen &gen, const Expr &call, bool &known);
/// closure + closure, closure * color or float, color or float * closure.
/// stdosl.h's mix(closure color x, closure color y, float a): x*(1-a) + y*a.
std::optional<RValue> emitClosureMix(IRGen &gen, RValue x, RValue y, RValue a, SrcLoc loc);
std::optional<RValue> emitClosureArith(IRGen &gen, llvm::StringRef op, RValue lhs,
                                       RValue rhs, SrcLoc l);
/// The empty closure (0 assigned to a closure).
RValue emptyClosure(IRGen &gen, SrcLoc l);
/// texture(), texture3d(), environment() and gettextureinfo()
/// (TextureBuiltins.cpp); `known`
/// is false when `call` is none of them.
std::optional<RValue> emitTextureBuiltin(IRGen &gen, const Expr &call,
                                         const OslType *expected, bool &known);

/// setmessage(), getmessage() and trace() (MessageBuiltins.cpp); `known`
/// is false when `call` is none of them.
std::optional<RValue> emitMessageBuiltin(IRGen &gen, const Expr &call, bool &known);

/// pointcloud_search(), pointcloud_get() and pointcloud_write()
/// (PointCloudBuiltins.cpp); `known` is false when `call` is none of them.
std::optional<RValue> emitPointCloudBuiltin(IRGen &gen, const Expr &call, bool &known);

/// A value as the runtime's row operands: one per number, string handle,
/// triple or closure, with one kind letter each (RowOperands.cpp).
struct RowOperands {
  std::vector<mlir::Value> values;
  std::string kinds;
};
/// The kind letter of a value of type `t` (s i f t k).
char rowKindOf(const OslType &t);
/// The operands of `v`, or nullopt after reporting that `function` cannot
/// pass its type.
std::optional<RowOperands> rowOperands(IRGen &gen, const RValue &v, SrcLoc l,
                                       llvm::StringRef function);
/// `like` with its operands replaced by `values` (rowOperands' order).
RValue fromRowOperands(const RValue &like, mlir::ValueRange values);

/// isconnected() (ConnectionBuiltins.cpp); `known` is false for any other
/// call.
std::optional<RValue> emitConnectionBuiltin(IRGen &gen, const Expr &call, bool &known);

/// noise, snoise, cellnoise, hashnoise, pnoise, psnoise and gabor by name
/// (NoiseBuiltins.cpp).
std::optional<RValue> emitNoise(IRGen &gen, const Expr &call, const OslType *expected);
/// transform() between named spaces and transformc() between color spaces
/// (SpaceBuiltins.cpp).
std::optional<RValue> emitTransform(IRGen &gen, const Expr &call);
std::optional<RValue> emitTransformc(IRGen &gen, const Expr &call);
/// Whether the renderer knows `from` as a source space and `to` as a
/// destination; each unknown one is reported when the point runs
/// (SpaceBuiltins.cpp).
bool knownSpaces(IRGen &gen, llvm::StringRef from, llvm::StringRef to, SrcLoc l);
/// Whether a color converts from space `from` to `to` (in a constructor,
/// color("space", ...), when OSL's own spaces name both); if not, the
/// renderer reports it when the point runs (SpaceBuiltins.cpp).
bool knownColorTransform(IRGen &gen, const std::string &from, const std::string &to, SrcLoc l,
                         bool constructor = false);
/// Dx, Dy or Dz of `v` (axis 'x', 'y' or 'z') (Builtins.cpp).
mlir::Value derivOf(IRGen &gen, SrcLoc l, mlir::Value v, char axis);
/// spline() and splineinverse() (SplineBuiltins.cpp).
std::optional<RValue> emitSpline(IRGen &gen, const Expr &call, bool inverse);
/// sincos() (SincosBuiltin.cpp).
std::optional<RValue> emitSincos(IRGen &gen, const Expr &call);
std::optional<RValue> emitArtisticIor(IRGen &gen, const Expr &call);
/// getattribute() (AttributeBuiltins.cpp).
std::optional<RValue> emitGetAttribute(IRGen &gen, const Expr &call);

/// The argument types of a call, for errors: "float, color" (Builtins.cpp).
std::string argTypesText(const std::vector<RValue> &args);
/// A string argument `what` of `fn` that must be known when the shader is
/// compiled, into `out`; false after reporting why not (Builtins.cpp).
bool stringArg(IRGen &gen, const RValue &v, const Expr &e, llvm::StringRef fn,
               llvm::StringRef what, std::string &out);
/// A string argument known when compiled, or chosen per point among such
/// strings; false after reporting why not (Builtins.cpp).
bool namesArg(IRGen &gen, const RValue &v, const Expr &e, llvm::StringRef fn,
              llvm::StringRef what);

/// Evaluates every argument of a call, in order, with no expected types
/// (Builtins.cpp); nullopt after an error.
std::optional<std::vector<RValue>> emitArgs(IRGen &gen, const Expr &call);
/// The same, each argument with the type its position expects (null: none),
/// so a type-polymorphic call there (noise) returns what the callee takes.
std::optional<std::vector<RValue>> emitArgs(IRGen &gen, const Expr &call,
                                            llvm::ArrayRef<const OslType *> expected);

/// testshade's user data for a lockgeom=0 parameter `name` of type `type`:
/// (where it exists per point, its value), or nullopt when testshade has
/// none by that name (Builtins.cpp).
std::optional<std::pair<mlir::Value, mlir::Value>>
testshadeUserdata(IRGen &gen, llvm::StringRef name, const OslType &type, SrcLoc l);

/// The string user data (--userdata:type=string) for a lockgeom=0 string
/// parameter `name`: the same on every point, so known now.
std::optional<std::string> testshadeStringUserdata(const IRGen &gen, llvm::StringRef name);

/// The name of the hidden variable holding a function's return value.
inline constexpr const char *kReturnVarName = "$return";
/// The hidden jump flags (see the file comment).
inline constexpr const char *kBreakFlag = "$break";
inline constexpr const char *kContinueFlag = "$continue";
inline constexpr const char *kReturnedFlag = "$returned";
inline constexpr const char *kExitFlag = "$exit";

/// The variable an lvalue-shaped expression designates, or "".
inline llvm::StringRef rootName(const Expr &e) {
  const Expr *cur = &e;
  while (cur->kind == ExprKind::Index || cur->kind == ExprKind::Member)
    cur = cur->args[0].get();
  return cur->kind == ExprKind::Ident ? llvm::StringRef(cur->name) : "";
}

/// Whether evaluating `e` may assign a variable (an assignment, ++/--, or
/// a call, which may write its output arguments).
bool mayHaveSideEffects(const Expr &e);

/// The stdosl.h constants (M_PI, M_E...), or nullopt.
std::optional<double> lookupFloatConstant(llvm::StringRef name);

} // namespace osl::frontend

#endif // OSLFRONTEND_IRGEN_H
