//===- OslOps.td - osl dialect operations ------------------*- tablegen -*-===//
#ifndef OSL_OPS_TD
#define OSL_OPS_TD

include "OslDialect/OslDialect.td"
include "OslDialect/OslTypes.td"
include "OslDialect/OslEnums.td"
include "mlir/Interfaces/SideEffectInterfaces.td"
include "mlir/Interfaces/ControlFlowInterfaces.td"

//===----------------------------------------------------------------------===//
// Shader interface: globals, parameters, outputs
//===----------------------------------------------------------------------===//

def Osl_GlobalOp : Osl_Op<"global", [Pure]> {
  let summary = "a shader global (P, N, u, v, time...), varying per point";
  let arguments = (ins StrAttr:$name);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = "$name attr-dict `:` type($result)";
  let hasVerifier = 1;
}

def Osl_ParamOp : Osl_Op<"param", [Pure, AllTypesMatch<["defaultValue", "result"]>]> {
  let summary = "a shader parameter: its instance value, or its default";
  let description = [{
    The default is computed by the shader (it may read globals). Binding an
    instance value replaces the op by that constant; otherwise by the default.
    `index`: the element of an array (or matrix) parameter this op holds.
    `userdata`: per-geometry data the renderer supplies (lockgeom=0), set
    by the group's linking. `not_connectable`: its metadata forbids
    connections ([[int allowconnect = 0]]).
  }];
  let arguments = (ins StrAttr:$name, Osl_Value:$defaultValue, OptionalAttr<I64Attr>:$index,
                       UnitAttr:$userdata, UnitAttr:$not_connectable);
  let results = (outs Osl_Value:$result);
  let builders = [OpBuilder<(ins "::mlir::Type":$result, "::llvm::StringRef":$name,
                                "::mlir::Value":$defaultValue), [{
    build($_builder, $_state, result, name, defaultValue, nullptr, false, false);
  }]>];
  let assemblyFormat = "$name `(` $defaultValue `)` attr-dict `:` type($result)";
}

def Osl_OutputOp : Osl_Op<"output"> {
  let summary = "the final value of an output parameter";
  let description = [{
    Written once per shader invocation, in declaration order. Lanes that are
    not active in the batch are never written.
  }];
  // `index`: the element of an array (or matrix) output this op writes.
  let arguments = (ins StrAttr:$name, Osl_Value:$value, OptionalAttr<I64Attr>:$index);
  let builders = [OpBuilder<(ins "::llvm::StringRef":$name, "::mlir::Value":$value), [{
    build($_builder, $_state, name, value, nullptr);
  }]>];
  let assemblyFormat = "$name `=` $value attr-dict `:` type($value)";
}

def Osl_SetGlobalOp : Osl_Op<"set_global"> {
  let summary = "the value a group's layer leaves in a writable global";
  let description = [{
    Where a layer of a group ends, what it assigned to a global (P, N...):
    in OSL the layers share their globals, so the layers that run after it
    read this value. osl-link-group replaces those reads and erases the op.
    Not pure: the canonicalizer must keep it until then.
  }];
  let arguments = (ins StrAttr:$name, Osl_Value:$value);
  let assemblyFormat = "$name `=` $value attr-dict `:` type($value)";
}

//===----------------------------------------------------------------------===//
// Uniformity: masks and broadcasts
//===----------------------------------------------------------------------===//

def Osl_BroadcastOp : Osl_Op<"broadcast", [Pure]> {
  let summary = "a uniform value used where a varying one is required";
  let description = [{
    The value may be varying already (a pass made it so after the
    broadcast was placed): the broadcast is then the identity and folds.
  }];
  let arguments = (ins Osl_Value:$value);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = "$value attr-dict `:` type($value) `->` type($result)";
  let hasVerifier = 1;
  let hasFolder = 1;
}

def Osl_BatchMaskOp : Osl_Op<"batch_mask", [Pure]> {
  let summary = "the lanes of this batch that hold a shading point";
  let results = (outs Osl_Bool:$result);
  let assemblyFormat = "attr-dict `:` type($result)";
  let hasVerifier = 1;
}

def Osl_AnyOp : Osl_Op<"any", [Pure]> {
  let summary = "true if any lane of a varying boolean is true";
  let arguments = (ins Osl_Bool:$mask);
  let results = (outs I1:$result);
  let assemblyFormat = "$mask attr-dict `:` type($mask)";
}

def Osl_CountLanesOp : Osl_Op<"count_lanes", [MemoryEffects<[MemWrite]>]> {
  let summary = "adds a masked block's active lanes to the run's lane statistics";
  let description = [{
    osl-insert-mask-stack with `count-lanes` puts one at the start of each
    masked block it makes (an arm of a varying if, an iteration of a
    varying loop): every execution adds one block and the number of lanes
    of `mask` that are set, so `osl-run --lane-stats` can report the mean
    fraction of active lanes per executed block. The mask is already
    restricted to the batch's shading points.
  }];
  let arguments = (ins Osl_Bool:$mask);
  let assemblyFormat = "$mask attr-dict `:` type($mask)";
}

//===----------------------------------------------------------------------===//
// Structured control flow (before osl-insert-mask-stack)
//===----------------------------------------------------------------------===//

def Osl_IfOp : Osl_Op<"if", [RecursiveMemoryEffects, NoRegionArguments,
    DeclareOpInterfaceMethods<RegionBranchOpInterface,
                              ["areTypesCompatible", "getRegionInvocationBounds"]>]> {
  let summary = "if/else; the condition may be varying";
  let arguments = (ins Osl_Bool:$condition);
  let results = (outs Variadic<Osl_Value>:$results);
  let regions = (region SizedRegion<1>:$thenRegion, SizedRegion<1>:$elseRegion);
  let assemblyFormat = [{
    $condition `:` type($condition) (`->` type($results)^)? $thenRegion `else` $elseRegion attr-dict
  }];
  let hasRegionVerifier = 1; // after the ops inside verify
  let hasCanonicalizer = 1;
}

def Osl_WhileOp : Osl_Op<"while", [RecursiveMemoryEffects,
    DeclareOpInterfaceMethods<RegionBranchOpInterface,
                              ["areTypesCompatible", "getEntrySuccessorOperands"]>]> {
  let summary = "a loop; its condition may be varying";
  let description = [{
    Like scf.while: `cond` receives the loop-carried values and ends in
    osl.condition; `do` receives what the condition forwards and yields the
    next values. A varying condition makes lanes leave at different times.
  }];
  let arguments = (ins Variadic<Osl_Value>:$inits);
  let results = (outs Variadic<Osl_Value>:$results);
  let regions = (region SizedRegion<1>:$before, SizedRegion<1>:$after);
  let assemblyFormat = [{
    (`(` $inits^ `:` type($inits) `)`)? (`->` type($results)^)? `cond` $before `do` $after attr-dict
  }];
  let hasRegionVerifier = 1; // after the ops inside verify
}

def Osl_ConditionOp : Osl_Op<"condition", [Pure, Terminator, HasParent<"WhileOp">,
    DeclareOpInterfaceMethods<RegionBranchTerminatorOpInterface>]> {
  let summary = "ends the condition region of osl.while";
  let arguments = (ins Osl_Bool:$condition, Variadic<Osl_Value>:$args);
  let assemblyFormat = "$condition `:` type($condition) (`,` $args^ `:` type($args))? attr-dict";
}

def Osl_YieldOp : Osl_Op<"yield", [Pure, Terminator, ReturnLike,
                                  ParentOneOf<["IfOp", "WhileOp"]>]> {
  let summary = "ends a region of osl.if or the body of osl.while";
  let arguments = (ins Variadic<Osl_Value>:$values);
  let builders = [OpBuilder<(ins), [{ build($_builder, $_state, ::mlir::ValueRange()); }]>];
  let assemblyFormat = "($values^ `:` type($values))? attr-dict";
}

//===----------------------------------------------------------------------===//
// Lane-wise operations: each lane computes on its own values. The result is
// varying exactly when some operand is.
//===----------------------------------------------------------------------===//

class Osl_LaneOp<string mnemonic, string kind, list<Trait> traits = []>
    : Osl_Op<mnemonic, !listconcat(traits, [Pure])> {
  let hasVerifier = 1;
  let extraClassDeclaration = [{
    static constexpr ::mlir::osl::LaneKind kLaneKind = ::mlir::osl::LaneKind::}] # kind # [{;
  }];
  let extraClassDefinition = [{
    ::llvm::LogicalResult $cppClass::verify() {
      return ::mlir::osl::verifyLaneOp(getOperation(), kLaneKind);
    }
  }];
}

class Osl_UnaryOp<string mnemonic, string kind, string summ>
    : Osl_LaneOp<mnemonic, kind> {
  let summary = summ;
  let arguments = (ins Osl_Value:$operand);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = "$operand attr-dict `:` type($operand) `->` type($result)";
  let builders = [OpBuilder<(ins "::mlir::Value":$operand), [{
    build($_builder, $_state, ::mlir::osl::inferLaneResultType(kLaneKind, operand), operand);
  }]>];
}

class Osl_BinaryOp<string mnemonic, string kind, string summ>
    : Osl_LaneOp<mnemonic, kind> {
  let summary = summ;
  let arguments = (ins Osl_Value:$lhs, Osl_Value:$rhs);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = "$lhs `,` $rhs attr-dict `:` type($lhs) `,` type($rhs) `->` type($result)";
  let builders = [OpBuilder<(ins "::mlir::Value":$lhs, "::mlir::Value":$rhs), [{
    build($_builder, $_state, ::mlir::osl::inferLaneResultType(kLaneKind, {lhs, rhs}), lhs, rhs);
  }]>];
}

class Osl_TernaryOp<string mnemonic, string kind, string summ>
    : Osl_LaneOp<mnemonic, kind> {
  let summary = summ;
  let arguments = (ins Osl_Value:$a, Osl_Value:$b, Osl_Value:$c);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = [{
    $a `,` $b `,` $c attr-dict `:` type($a) `,` type($b) `,` type($c) `->` type($result)
  }];
  let builders = [OpBuilder<(ins "::mlir::Value":$a, "::mlir::Value":$b, "::mlir::Value":$c), [{
    build($_builder, $_state, ::mlir::osl::inferLaneResultType(kLaneKind, {a, b, c}), a, b, c);
  }]>];
}

// Arithmetic on int, float and triples (componentwise). Division and modulo
// are OSL's safe versions: x/0 = 0 (see osl.div), int x%0 = 0.
def Osl_AddOp : Osl_BinaryOp<"add", "Numeric", "addition">;
def Osl_SubOp : Osl_BinaryOp<"sub", "Numeric", "subtraction"> {
  // x - x -> 0 as OSL's optimizer folds it (also for inf and NaN).
  let hasCanonicalizer = 1;
}
def Osl_MulOp : Osl_BinaryOp<"mul", "Numeric", "multiplication"> {
  // x * 0 -> 0 as OSL's optimizer folds it (also for inf and NaN).
  let hasCanonicalizer = 1;
}
def Osl_DivOp : Osl_BinaryOp<"div", "Numeric", "safe division: a float quotient that is not finite is 0 unless the divisor is a non-zero constant; int x/0 = 0">;
def Osl_ModOp : Osl_BinaryOp<"mod", "Int", "int remainder, truncating, x%0 = 0">;
def Osl_NegOp : Osl_UnaryOp<"neg", "Numeric", "negation">;
def Osl_MinOp : Osl_BinaryOp<"min", "Numeric", "minimum">;
def Osl_MaxOp : Osl_BinaryOp<"max", "Numeric", "maximum">;
def Osl_AbsOp : Osl_UnaryOp<"abs", "Numeric", "absolute value">;

// Booleans and bits.
def Osl_AndOp : Osl_BinaryOp<"and", "Bool", "logical and">;
def Osl_OrOp : Osl_BinaryOp<"or", "Bool", "logical or">;
def Osl_NotOp : Osl_UnaryOp<"not", "Bool", "logical not">;
def Osl_BitAndOp : Osl_BinaryOp<"bitand", "Int", "bitwise and">;
def Osl_BitOrOp : Osl_BinaryOp<"bitor", "Int", "bitwise or">;
def Osl_BitXorOp : Osl_BinaryOp<"bitxor", "Int", "bitwise xor">;
def Osl_BitNotOp : Osl_UnaryOp<"bitnot", "Int", "bitwise complement">;
def Osl_ShlOp : Osl_BinaryOp<"shl", "Int", "shift left">;
def Osl_ShrOp : Osl_BinaryOp<"shr", "Int", "arithmetic shift right">;

// Float math, componentwise on triples, with OSL's edge rules.
def Osl_SinOp : Osl_UnaryOp<"sin", "Float", "sine">;
def Osl_CosOp : Osl_UnaryOp<"cos", "Float", "cosine">;
def Osl_TanOp : Osl_UnaryOp<"tan", "Float", "tangent">;
def Osl_AsinOp : Osl_UnaryOp<"asin", "Float", "arc sine (input clamped to [-1,1])">;
def Osl_AcosOp : Osl_UnaryOp<"acos", "Float", "arc cosine (input clamped to [-1,1])">;
def Osl_AtanOp : Osl_UnaryOp<"atan", "Float", "arc tangent">;
def Osl_ExpOp : Osl_UnaryOp<"exp", "Float", "e^x">;
def Osl_Exp2Op : Osl_UnaryOp<"exp2", "Float", "2^x">;
def Osl_LogOp : Osl_UnaryOp<"log", "Float", "natural log; log(x<=0) = log(FLT_MIN)">;
def Osl_Log2Op : Osl_UnaryOp<"log2", "Float", "base-2 log">;
def Osl_Log10Op : Osl_UnaryOp<"log10", "Float", "base-10 log">;
def Osl_SqrtOp : Osl_UnaryOp<"sqrt", "Float", "square root; sqrt(x<0) = 0">;
def Osl_InverseSqrtOp : Osl_UnaryOp<"inversesqrt", "Float", "1/sqrt(x); 0 for x<=0">;
def Osl_SinhOp : Osl_UnaryOp<"sinh", "Float", "hyperbolic sine">;
def Osl_CoshOp : Osl_UnaryOp<"cosh", "Float", "hyperbolic cosine">;
def Osl_TanhOp : Osl_UnaryOp<"tanh", "Float", "hyperbolic tangent">;
def Osl_Expm1Op : Osl_UnaryOp<"expm1", "Float", "e^x - 1, accurate near 0">;
def Osl_CbrtOp : Osl_UnaryOp<"cbrt", "Float", "cube root, odd in x">;
def Osl_ErfOp : Osl_UnaryOp<"erf", "Float", "error function">;
def Osl_ErfcOp : Osl_UnaryOp<"erfc", "Float", "1 - erf(x)">;
def Osl_LogbOp : Osl_UnaryOp<"logb", "Float", "exponent of x as a float; logb(0) = -126">;
def Osl_FloorOp : Osl_UnaryOp<"floor", "Float", "round down">;
def Osl_CeilOp : Osl_UnaryOp<"ceil", "Float", "round up">;
def Osl_RoundOp : Osl_UnaryOp<"round", "Float", "round half away from zero">;
def Osl_TruncOp : Osl_UnaryOp<"trunc", "Float", "round toward zero">;
def Osl_SignOp : Osl_UnaryOp<"sign", "Float", "-1, 0 or 1">;
def Osl_PowOp : Osl_BinaryOp<"pow", "Float", "x^y; 0 for x<0 with non-integer y"> {
  // 0^y -> 0 as OSL's optimizer folds it.
  let hasCanonicalizer = 1;
}
def Osl_FmodOp : Osl_BinaryOp<"fmod", "Float", "C fmod; fmod(x, 0) = 0">;
def Osl_Atan2Op : Osl_BinaryOp<"atan2", "Float", "atan2(y, x)">;
def Osl_StepOp : Osl_BinaryOp<"step", "Float", "step(edge, x): 0 if x < edge else 1">;
def Osl_MixOp : Osl_TernaryOp<"mix", "Float", "mix(a, b, t) = a*(1-t) + b*t">;
def Osl_ClampOp : Osl_TernaryOp<"clamp", "Numeric", "clamp(x, lo, hi)">;
def Osl_SmoothStepOp : Osl_TernaryOp<"smoothstep", "Float", "smoothstep(e0, e1, x)">;
def Osl_LinearStepOp : Osl_TernaryOp<"linearstep", "Float", "linearstep(e0, e1, x): clamped (x-e0)/(e1-e0)">;

// Geometry on triples.
def Osl_DotOp : Osl_BinaryOp<"dot", "TripleToFloat", "dot product">;
def Osl_DistanceOp : Osl_BinaryOp<"distance", "TripleToFloat", "distance between points">;
def Osl_LengthOp : Osl_UnaryOp<"length", "TripleToFloat", "length of a vector">;
def Osl_CrossOp : Osl_BinaryOp<"cross", "Triple", "cross product">;
def Osl_NormalizeOp : Osl_UnaryOp<"normalize", "Triple", "unit vector (0 stays 0)">;

def Osl_CmpOp : Osl_LaneOp<"cmp", "Compare"> {
  let summary = "comparison: eq, ne, lt, le, gt, ge, same";
  let description = [{
    Floats compare ordered (false with a NaN) except `ne`, which is true with
    a NaN; with `unordered`, every predicate is true when either side is a
    NaN, as OSL's JIT compares a shader's own operands. The front end's
    library code (isinf, smoothstep, ...) needs ordered comparisons.
    `same` compares bit patterns (a NaN equals a NaN of the same payload,
    0.0 differs from -0.0): the lane-group filter groups lanes by it.
    Triples and matrices: `ne` is or-ed over the components, the others
    and-ed.
  }];
  let arguments = (ins Osl_CmpPredicate:$predicate, Osl_Value:$lhs, Osl_Value:$rhs,
                       UnitAttr:$unordered);
  let results = (outs Osl_Bool:$result);
  let assemblyFormat = "$predicate `,` $lhs `,` $rhs attr-dict `:` type($lhs) `,` type($rhs) `->` type($result)";
  let builders = [OpBuilder<(ins "::llvm::StringRef":$predicate, "::mlir::Value":$lhs,
                                "::mlir::Value":$rhs, CArg<"bool", "false">:$unordered), [{
    std::optional<::mlir::osl::CmpPredicate> p = ::mlir::osl::symbolizeCmpPredicate(predicate);
    assert(p && "osl.cmp predicates are eq, ne, lt, le, gt, ge, same");
    build($_builder, $_state, ::mlir::osl::inferLaneResultType(kLaneKind, {lhs, rhs}), *p, lhs,
          rhs, unordered);
  }]>];
}

def Osl_SelectOp : Osl_LaneOp<"select", "Select"> {
  let summary = "cond ? a : b, per lane";
  let arguments = (ins Osl_Bool:$condition, Osl_Value:$trueValue, Osl_Value:$falseValue);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = [{
    $condition `,` $trueValue `,` $falseValue attr-dict `:` type($condition) `,`
    type($trueValue) `,` type($falseValue) `->` type($result)
  }];
  let builders = [OpBuilder<(ins "::mlir::Value":$c, "::mlir::Value":$a, "::mlir::Value":$b), [{
    build($_builder, $_state, ::mlir::osl::inferLaneResultType(kLaneKind, {c, a, b}), c, a, b);
  }]>];
}

//===----------------------------------------------------------------------===//
// Conversions and components
//===----------------------------------------------------------------------===//

def Osl_ConvertOp : Osl_Op<"convert", [Pure]> {
  let summary = "int/float/bool conversion, or a scalar promoted to a triple";
  let description = [{
    f32 -> i32 truncates toward zero (OSL's int(x)); numbers -> i1 test != 0;
    i1 -> numbers give 0 or 1; f32/i32 -> triple repeats the value.
  }];
  let arguments = (ins Osl_Value:$value);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = "$value attr-dict `:` type($value) `->` type($result)";
  let hasVerifier = 1;
}

def Osl_ConstructOp : Osl_LaneOp<"construct", "Construct"> {
  let summary = "a triple from three floats";
  let arguments = (ins Osl_Value:$x, Osl_Value:$y, Osl_Value:$z);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = "$x `,` $y `,` $z attr-dict `:` type($x) `,` type($y) `,` type($z) `->` type($result)";
  let builders = [OpBuilder<(ins "::mlir::Value":$x, "::mlir::Value":$y, "::mlir::Value":$z), [{
    build($_builder, $_state, ::mlir::osl::inferLaneResultType(kLaneKind, {x, y, z}), x, y, z);
  }]>];
}

def Osl_ExtractOp : Osl_Op<"extract", [Pure]> {
  let summary = "one component of a triple";
  let arguments = (ins Osl_Triple:$vector, ConfinedAttr<I64Attr, [IntMinValue<0>, IntMaxValue<2>]>:$index);
  let results = (outs Osl_Float:$result);
  let assemblyFormat = "$vector `[` $index `]` attr-dict `:` type($vector) `->` type($result)";
  let hasVerifier = 1;
}

def Osl_InsertOp : Osl_Op<"insert", [Pure]> {
  let summary = "a triple with one component replaced";
  let arguments = (ins Osl_Float:$value, Osl_Triple:$vector,
                       ConfinedAttr<I64Attr, [IntMinValue<0>, IntMaxValue<2>]>:$index);
  let results = (outs Osl_Triple:$result);
  let assemblyFormat = "$value `,` $vector `[` $index `]` attr-dict `:` type($value) `,` type($vector) `->` type($result)";
  let hasVerifier = 1;
}

def Osl_PickOp : Osl_Op<"pick", [Pure]> {
  let summary = "one of a local array's elements, by a uniform or per-point index";
  let description = [{
    `array[index]` for a local array of numbers or triples whose elements are
    values: the element `index` of `elements`. `index` (i32) must be within
    0..N-1: the front end clamps it, as OSL clamps an index out of range.
    One op instead of a chain of selects, so the elements are read from
    memory at the lane level (osl.lane_pick) rather than all kept live.
  }];
  let arguments = (ins Osl_Value:$index, Variadic<Osl_Value>:$elements);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = [{
    $index `,` `[` $elements `]` attr-dict `:` type($index) `,` `[` type($elements) `]`
    `->` type($result)
  }];
  let hasVerifier = 1;
  let hasFolder = 1;
}

def Osl_LanePickOp : Osl_Op<"lane_pick", [Pure]> {
  let summary = "one of N lane values, by a uniform or per-lane index";
  let description = [{
    The lane-level form of osl.pick, one per component: `elements` are all
    of the result's type (f32 or i32, as scalars or W lanes) and `index` is
    an i32 within 0..N-1, uniform (a scalar) or per lane (vector<W x i32>).
    osl-lower-to-llvm keeps each list of elements in a stack block, stored
    where each element is defined, and reads it with a load or a gather.
  }];
  let arguments = (ins AnyType:$index, Variadic<AnyType>:$elements);
  let results = (outs AnyType:$result);
  let assemblyFormat = [{
    $index `,` `[` $elements `]` attr-dict `:` type($index) `,` `[` type($elements) `]`
    `->` type($result)
  }];
  let hasVerifier = 1;
  let hasFolder = 1;
}

def Osl_CodegenFenceOp : Osl_Op<"codegen_fence", [Pure, AllTypesMatch<["value", "result"]>]> {
  let summary = "its operand unchanged, opaque to LLVM's instruction selection";
  let description = [{
    The lane value `value` (i32, scalar or W lanes) as it is. The noise
    builders put one after each subtraction of the lookup3 hash (bjmix,
    bjfinal). Without them, LLVM's DAG combiner asks for the known bits of
    each xor and sub of the hash chain six levels deep. Each value of the
    chain feeds two or three later steps, so one query visits hundreds of
    nodes: 18 inlined hashes cost llc 194M instructions on AVX2, 103M
    fenced. osl-lower-to-llvm lowers it to llvm.arithmetic.fence on the
    bits seen as f32, which emits no instruction. A constant operand folds
    through it.
  }];
  let arguments = (ins AnyTypeOf<[I32, VectorOfRankAndType<[1], [I32]>]>:$value);
  let results = (outs AnyTypeOf<[I32, VectorOfRankAndType<[1], [I32]>]>:$result);
  let assemblyFormat = "$value attr-dict `:` type($value)";
  let hasFolder = 1;
}

//===----------------------------------------------------------------------===//
// Library calls
//===----------------------------------------------------------------------===//

def Osl_DenseTableAttr : ElementsAttrBase<CPred<"::llvm::isa<::mlir::DenseElementsAttr>($_self)">,
                                          "dense constant table"> {
  let storageType = [{ ::mlir::DenseElementsAttr }];
  let returnType = [{ ::mlir::DenseElementsAttr }];
  let convertFromStorage = "$_self";
}

def Osl_TableReadOp : Osl_Op<"table_read", [Pure]> {
  let summary = "an element of a constant table, by a uniform or per-point index";
  let description = [{
    `table[index]` for an array whose elements are all known at compile
    time (a font, a palette, a list of primes): one load for a uniform
    index, one gather for a varying one, where a chain of selects costs a
    compare and a select per element. `index` (i32) must be within the
    table: the front end clamps it, as OSL clamps an index out of range.
  }];
  let arguments = (ins Osl_DenseTableAttr:$table, Osl_Value:$index);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = "$table `[` $index `]` attr-dict `:` type($index) `->` type($result)";
  let hasVerifier = 1;
}

def Osl_HashOp : Osl_Op<"hash", [Pure]> {
  let summary = "OSL's hash of numbers: an int from the keys' bits";
  let description = [{
    hash(int), hash(float), hash(float, float), hash(point) and
    hash(point, float): Bob Jenkins' lookup3 final mix (OSL's inthash) of
    the keys' 32-bit patterns, an int taken as it is and a float's bits,
    a triple's three components in order.
  }];
  let arguments = (ins Variadic<Osl_Value>:$keys);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = "`(` $keys `)` attr-dict `:` type($keys) `->` type($result)";
}

def Osl_NoiseOp : Osl_Op<"noise", [Pure, AttrSizedOperandSegments]> {
  let summary = "noise(name, p [, t]) with a float or triple result";
  let description = [{
    `kind` is the noise (OslEnums.td: the front end maps OSL's names and
    aliases to it).
    Domains: (f32), (f32, f32), (triple), (triple, f32). With `periodic`
    (OSL's pnoise) the coordinates are followed by one period of the same
    type per coordinate.

    Gabor noise ("gabor") also takes OSL's noise options as operands, each
    optional (OSL's default when absent; per-point options are split into
    lane groups by osl-lane-group-filter, the lowering needs them uniform): `anisotropic`
    (i32: 0 isotropic, 1 anisotropic, 2 hybrid), `direction` (triple),
    `bandwidth` and `impulses` (f32), `do_filter` (i32). `derivs` holds
    Dx then Dy of the lookup point's coordinates (the first one or two
    coordinates, not a 4th one or the periods), for the filter; without
    them the noise is not filtered.
  }];
  let arguments = (ins Osl_NoiseKind:$kind, Variadic<Osl_Value>:$coords, UnitAttr:$periodic,
                       Variadic<Osl_Value>:$derivs,
                       Optional<Osl_Value>:$anisotropic, Optional<Osl_Value>:$direction,
                       Optional<Osl_Value>:$bandwidth, Optional<Osl_Value>:$impulses,
                       Optional<Osl_Value>:$do_filter);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = [{
    $kind `(` $coords `)`
    (`derivs` `(` $derivs^ `:` type($derivs) `)`)?
    (`anisotropic` `(` $anisotropic^ `:` type($anisotropic) `)`)?
    (`direction` `(` $direction^ `:` type($direction) `)`)?
    (`bandwidth` `(` $bandwidth^ `:` type($bandwidth) `)`)?
    (`impulses` `(` $impulses^ `:` type($impulses) `)`)?
    (`do_filter` `(` $do_filter^ `:` type($do_filter) `)`)?
    attr-dict `:` functional-type($coords, $result)
  }];
  let builders = [
    OpBuilder<(ins "Type":$result, "::mlir::osl::NoiseKind":$kind, "ValueRange":$coords,
                   "bool":$periodic), [{
      build($_builder, $_state, result, kind, coords, periodic, ValueRange(),
            Value(), Value(), Value(), Value(), Value());
    }]>
  ];
  let extraClassDeclaration = [{
    /// Gabor's options that are present, in operand order.
    ::llvm::SmallVector<::mlir::Value> getOptions() {
      ::llvm::SmallVector<::mlir::Value> options;
      for (::mlir::Value v : {getAnisotropic(), getDirection(), getBandwidth(), getImpulses(),
                              getDoFilter()})
        if (v)
          options.push_back(v);
      return options;
    }
  }];
  let hasVerifier = 1;
}

def Osl_NoiseByKindOp : Osl_Op<"noise_by_kind", [Pure, AttrSizedOperandSegments]> {
  let summary = "noise(name, p [, t]) whose kind is a value: chosen per point or at run time";
  let description = [{
    The noise of `kind` (an i32 holding an `osl.noise` kind's number, uniform
    or per point) at `coords`, domains and `periodic` as in `osl.noise`; a
    kind outside the kinds the noise has (simplex kinds when periodic) gives
    0. The front end makes one for noise("name", ...) whose name is one of
    several strings the shader knows (an element of a constant array), so
    that the kernel makes one call, as OSL's batched backend calls one
    routine that switches on the name, instead of one call per name.

    Gabor noise is among the kinds with OSL's default options; `derivs`
    holds Dx then Dy of the lookup point (as `osl.noise`'s), for its
    filter: none for a 1D domain, zeros where the shader's names exclude
    "gabor".
  }];
  let arguments = (ins Osl_Value:$kind, Variadic<Osl_Value>:$coords, UnitAttr:$periodic,
                       Variadic<Osl_Value>:$derivs);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = [{
    $kind `:` type($kind) `(` $coords `)`
    (`derivs` `(` $derivs^ `:` type($derivs) `)`)?
    attr-dict `:` functional-type($coords, $result)
  }];
  let hasVerifier = 1;
  let hasCanonicalizer = 1;
}

def Osl_TransformOp : Osl_Op<"transform", [Pure]> {
  let summary = "transform a point, vector or normal between named spaces";
  let arguments = (ins StrAttr:$from, StrAttr:$to, Osl_TransformKind:$kind, Osl_Triple:$value);
  let results = (outs Osl_Triple:$result);
  let assemblyFormat = "$from `to` $to $kind $value attr-dict `:` type($value) `->` type($result)";
  let hasVerifier = 1;
}

//===----------------------------------------------------------------------===//
// Textures
//===----------------------------------------------------------------------===//

def Osl_TextureOp : Osl_Op<"texture", [AttrSizedOperandSegments]> {
  let summary = "texture(), texture3d() and environment() through OpenImageIO";
  let description = [{
    A filtered texture lookup of `nchannels` (1 or 3) channels plus alpha.
    `kind` is texture (coords s, t; derivs ds/dx, dt/dx, ds/dy, dt/dy),
    texture3d (coords P; derivs dP/dx, dP/dy, dP/dz, component by
    component) or environment (coords R; derivs dR/dx, dR/dy).

    `floatOptions` are the per-point options, in the order sblur, tblur,
    rblur, swidth, twidth, rwidth, fill, missingalpha, then missingcolor's
    three components; `firstchannel` (per point) and `subimage` (uniform)
    are ints.

    Options that OpenImageIO takes once per call are chosen among
    compile-time strings: `choices` holds, for file, swrap, twrap, rwrap,
    interp and subimagename in that order, an i32 index into the matching
    list of `candidates`. A varying index is split into lane groups that
    agree by osl-lane-group-filter; the lowering needs them uniform.

    `fileHandle` (optional), a string handle, is the file name where it is
    computed at run time (format, concat...): then each lane looks up the
    file it names, and the file's candidates are unused.

    `mask` (optional) limits the lookup to some lanes; the other lanes'
    results are undefined. Results are varying: a lookup reads per point.
    The lookup may report an error (a missing file) once per file, unless
    `wantsErrorMessage` (the "errormessage" option): then `errorMessage` is
    the handle of the error's text where a lookup failed ("unknown" when
    the texture system gave none) and of "" elsewhere.
  }];
  let arguments = (ins Osl_TextureKind:$kind, I32Attr:$nchannels,
                       UnitAttr:$hasMissingColor, UnitAttr:$hasMissingAlpha,
                       UnitAttr:$wantsErrorMessage, ArrayAttr:$candidates,
                       Variadic<Osl_Float>:$coords, Variadic<Osl_Float>:$derivs,
                       Variadic<Osl_Float>:$floatOptions,
                       Osl_Value:$firstchannel, Osl_Value:$subimage,
                       Variadic<Osl_Value>:$choices, Optional<Osl_Value>:$fileHandle,
                       Optional<Osl_Bool>:$mask);
  let results = (outs Osl_Value:$result, Osl_Float:$alpha, Osl_Value:$errorMessage);
  let assemblyFormat = [{
    $kind `(` $coords `)` `derivs` `(` $derivs `)` `options` `(` $floatOptions `)`
    `channel` $firstchannel `subimage` $subimage `choices` `(` $choices `)`
    (`file` $fileHandle^ `:` type($fileHandle))? (`mask` $mask^ `:` type($mask))? attr-dict `:` `(` type($coords) `)` `(` type($derivs) `)`
    `(` type($floatOptions) `)` type($firstchannel) `,` type($subimage) `(` type($choices) `)`
    `->` type($result) `,` type($alpha) `,` type($errorMessage)
  }];
  let hasVerifier = 1;
}

def Osl_GetTextureInfoOp : Osl_Op<"gettextureinfo", [Pure]> {
  let summary = "gettextureinfo(): a fact about a texture file";
  let description = [{
    OpenImageIO's answer for `name` ("resolution", "channels", "exists",
    "averagecolor", "texturetype", metadata...) about `file`, as ints,
    floats (`floats` set) or i32 handles of run-time strings (`strings`
    set): `found` is 1 when the texture system knew the answer, else 0 and
    the values are undefined. The results are uniform, unless `fileHandle`
    (optional), a string handle, names the file (computed at run time,
    `file` is then unused) and is varying: each point asks about its own.
  }];
  let arguments = (ins StrAttr:$file, StrAttr:$name, UnitAttr:$floats, UnitAttr:$strings,
                       Optional<Osl_Value>:$fileHandle);
  let results = (outs Osl_Value:$found, Variadic<Osl_Value>:$values);
  let assemblyFormat = [{
    $file `,` $name (`file` $fileHandle^ `:` type($fileHandle))? attr-dict `:`
    type($found) `,` `(` type($values) `)`
  }];
  let hasVerifier = 1;
}

def Osl_UdimTileOp : Osl_Op<"udim_tile", [Pure]> {
  let summary = "the file of a UDIM pattern's tile at (s, t)";
  let description = [{
    `file` is a string handle (i32). The result is the handle of the file
    name of the pattern's tile at (s, t) ("file.<UDIM>.tx" at s = 1.5,
    t = 0.2 is "file.1002.tx", as OpenImageIO resolves it), of "" where the
    pattern has no tile there, or `file` itself where it is not a UDIM
    pattern. gettextureinfo(file, s, t, name, dest) asks about it.
  }];
  let arguments = (ins Osl_Value:$file, Osl_Value:$s, Osl_Value:$t);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = [{
    $file `at` `(` $s `,` $t `)` attr-dict `:` type($file) `,` type($s) `,` type($t) `->` type($result)
  }];
  let hasVerifier = 1;
}

def Osl_FirstLaneOp : Osl_Op<"first_lane", [Pure]> {
  let summary = "the value of the first lane of `mask` that is set";
  let description = [{
    Lane-group filtering's lead: the value of the lowest lane whose mask
    bit is set (undefined when none is). Uniform operands are their own
    lead.
  }];
  let arguments = (ins Osl_Value:$value, Osl_Bool:$mask);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = "$value `,` $mask attr-dict `:` type($value) `,` type($mask) `->` type($result)";
  let hasVerifier = 1;
}

def Osl_IsConstantOp : Osl_Op<"is_constant", [Pure]> {
  let summary = "isconstant(): 1 if the value is known before the shader runs";
  let description = [{
    OSL answers isconstant() after its runtime optimizer has bound the
    parameters and folded constants; this op is answered as late, when it
    is lowered: 1 if `value` is a constant by then, else 0.
  }];
  let arguments = (ins Osl_Value:$value);
  let results = (outs I32:$result);
  let assemblyFormat = "$value attr-dict `:` type($value)";
}

//===----------------------------------------------------------------------===//
// Strings computed at run time
//===----------------------------------------------------------------------===//

def Osl_StringConstantOp : Osl_Op<"string_constant", [Pure]> {
  let summary = "the run-time handle (i32) of a compile-time string";
  let description = [{
    Strings computed at run time are i32 handles into the runtime's intern
    table (OslAbi/Strings.h); equal strings have equal handles. This
    op interns a compile-time string where it meets such strings.
  }];
  let arguments = (ins StrAttr:$value);
  let results = (outs I32:$result);
  let assemblyFormat = "$value attr-dict `:` type($result)";
}

def Osl_StringCallOp : Osl_Op<"string_call", [Pure]> {
  let summary = "an OSL string function on run-time strings";
  let description = [{
    Calls string function `callee` (concat, format, strlen, hash,
    startswith, endswith, getchar, substr, stoi, stof, regex_search,
    regex_match; see kStringFunctions) lane by lane. `kinds` has one letter
    per operand: `s` a string handle (i32), `i` an int (i32), `f` a float,
    `t` a triple. String results are handles; int results i32; stof's f32.
    The result is varying when an operand is.
  }];
  let arguments = (ins StrAttr:$callee, StrAttr:$kinds, Variadic<Osl_Value>:$args);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = [{
    $callee $kinds `(` $args `)` attr-dict `:` functional-type($args, $result)
  }];
  let hasVerifier = 1;
}

def Osl_PrintOp : Osl_Op<"print", [AttrSizedOperandSegments,
                                   MemoryEffects<[MemWrite]>]> {
  let summary = "printf, fprintf, warning or error, once per active point";
  let description = [{
    Formats `args` with OSL's format rules for every active point and sends
    the text to `stream` (kPrintStreams, OslAbi/Print.h): printf's
    standard output, fprintf's file (the first operand names it), or the
    run's warnings and errors. `kinds` has one letter per operand, as
    osl.string_call's (an array or matrix is passed element by element,
    its conversion repeated by the front end). The points' texts
    come out in point order whatever the width. `mask`, set by
    osl-insert-mask-stack inside varying control flow, names the points
    that print.
  }];
  let arguments = (ins StrAttr:$stream, StrAttr:$kinds, Variadic<Osl_Value>:$args,
                       Optional<Osl_Bool>:$mask);
  let assemblyFormat = [{
    $stream $kinds `(` $args `)` (`mask` $mask^ `:` type($mask))? attr-dict `:` type($args)
  }];
  let extraClassDeclaration = [{
    /// An error() call (OSL's lazyerror option and opt_warnings ask).
    bool isErrorCall() { return getStream() == "error"; }
  }];
  let hasVerifier = 1;
}

//===----------------------------------------------------------------------===//
// Messages between layers
//===----------------------------------------------------------------------===//

def Osl_SetMessageOp : Osl_Op<"set_message", [AttrSizedOperandSegments,
                                               MemoryEffects<[MemRead, MemWrite]>]> {
  let summary = "setmessage(): a named value for the later layers of each point";
  let description = [{
    Stores `values` (one operand per number, string handle, triple or
    closure of the value, in order; `kinds` has one letter per operand as
    osl.print's) as message `name` of OSL type `typeName` for each active
    point. Messages live for one batch. Setting a message twice, or after a
    getmessage of it found nothing, is reported as OSL reports it and keeps
    what was there. `mask`, set by osl-insert-mask-stack, names the points.
  }];
  let arguments = (ins StrAttr:$name, StrAttr:$typeName, StrAttr:$kinds,
                       Variadic<Osl_Value>:$values, Optional<Osl_Bool>:$mask);
  let assemblyFormat = [{
    $name $typeName $kinds `(` $values `)` (`mask` $mask^ `:` type($mask))? attr-dict
    `:` type($values)
  }];
  let hasVerifier = 1;
}

def Osl_GetMessageOp : Osl_Op<"get_message", [AttrSizedOperandSegments,
                                               MemoryEffects<[MemRead, MemWrite]>]> {
  let summary = "getmessage(): a message set earlier for the same point";
  let description = [{
    `found` is 1 on the points where message `name` was set with a type
    equivalent to `typeName` (triples match triples); there `values` are
    the message's, elsewhere `current` (the destination's values). A
    type mismatch is reported; a message not found is remembered, so that
    setting it later is reported. Results are varying.
  }];
  let arguments = (ins StrAttr:$name, StrAttr:$typeName, StrAttr:$kinds,
                       Variadic<Osl_Value>:$current, Optional<Osl_Bool>:$mask);
  let results = (outs Osl_Value:$found, Variadic<Osl_Value>:$values);
  let assemblyFormat = [{
    $name $typeName $kinds `(` $current `)` (`mask` $mask^ `:` type($mask))? attr-dict
    `:` functional-type($current, results)
  }];
  let hasVerifier = 1;
}

//===----------------------------------------------------------------------===//
// Point clouds
//===----------------------------------------------------------------------===//

def Osl_PointCloudOp : Osl_Op<"pointcloud", [AttrSizedOperandSegments,
                                             MemoryEffects<[MemRead, MemWrite]>]> {
  let summary = "pointcloud_search, pointcloud_get or pointcloud_write";
  let description = [{
    `function` is "search", "get" or "write". `inputs` are the function's
    inputs and `current` the output arrays' elements as they are, with
    `kinds` one letter per operand of both (OslAbi/PointCloud.h lists them
    and the `layout` of the arrays). `status` is the function's result
    (search: how many points were found; get and write: 1 on success),
    `written` how many leading elements of each output array were written;
    `values` are the arrays' elements after the call. All results are
    varying. `mask`, set by osl-insert-mask-stack, names the points.

    Example: `n = pointcloud_search("c.geo", P, 0.1, 4, 1, "index", idx)`:

    ```mlir
    %n, %w, %i0, %i1, %i2, %i3 = osl.pointcloud "search" "index:i:4" "stfiiiiii"
        (%file, %P, %r, %max, %sort) (%c0, %c1, %c2, %c3) : ...
    ```
  }];
  let arguments = (ins StrAttr:$function, StrAttr:$layout, StrAttr:$kinds,
                       Variadic<Osl_Value>:$inputs, Variadic<Osl_Value>:$current,
                       Optional<Osl_Bool>:$mask);
  let results = (outs Osl_Value:$status, Osl_Value:$written, Variadic<Osl_Value>:$values);
  let assemblyFormat = [{
    $function $layout $kinds `(` $inputs `)` `(` $current `)` (`mask` $mask^)? attr-dict `:` functional-type(operands, results)
  }];
  let hasVerifier = 1;
}

//===----------------------------------------------------------------------===//
// Closures
//===----------------------------------------------------------------------===//

def Osl_ClosureEmptyOp : Osl_Op<"closure_empty", [Pure]> {
  let summary = "the empty closure (what `Ci = 0` assigns)";
  let description = [{
    `initial_ci`: the value a shader's Ci starts with (the front end marks
    it), which osl-link-group replaces by an earlier layer's Ci when globals
    are not lazy.
  }];
  let arguments = (ins UnitAttr:$initial_ci);
  let results = (outs Osl_ClosureType:$result);
  let assemblyFormat = "attr-dict `:` type($result)";
}

def Osl_ClosureComponentOp : Osl_Op<"closure_component", [Pure]> {
  let summary = "a closure of OSL's standard library with weight 1";
  let description = [{
    `name` is one of the closures of kClosures (OslAbi/Closures.h).
    The operands are its positional parameters then every keyword parameter
    of its signature, in that order (the front end fills absent keywords
    with 0 or ""): triples for `n` and `c`, f32 for `f`, i32 for `i` and
    string handles (i32) for `s`, closures for `k`. The result is varying
    when an operand is.
  }];
  let arguments = (ins StrAttr:$name, Variadic<Osl_Value>:$args);
  let results = (outs Osl_AnyClosure:$result);
  let assemblyFormat = [{
    $name `(` $args `)` attr-dict `:` functional-type($args, $result)
  }];
  let hasVerifier = 1;
}

def Osl_ClosureMulOp : Osl_Op<"closure_mul", [Pure]> {
  let summary = "closure * color (a float weight is converted to a color first)";
  let arguments = (ins Osl_AnyClosure:$closure, Osl_Triple:$weight);
  let results = (outs Osl_AnyClosure:$result);
  let assemblyFormat = [{
    $closure `,` $weight attr-dict `:` type($closure) `,` type($weight) `->` type($result)
  }];
  let hasVerifier = 1;
}

def Osl_ClosureAddOp : Osl_Op<"closure_add", [Pure]> {
  let summary = "closure + closure";
  let arguments = (ins Osl_AnyClosure:$lhs, Osl_AnyClosure:$rhs);
  let results = (outs Osl_AnyClosure:$result);
  let assemblyFormat = [{
    $lhs `,` $rhs attr-dict `:` type($lhs) `,` type($rhs) `->` type($result)
  }];
  let hasVerifier = 1;
  let hasFolder = 1;
}

//===----------------------------------------------------------------------===//
// Color
//===----------------------------------------------------------------------===//

def Osl_TransformcOp : Osl_Op<"transformc", [Pure]> {
  let summary = "transformc: convert a color between color spaces";
  let description = [{
    OSL's transformc(from, to, C) and color(space, ...): "rgb" (also "RGB",
    "linear" and the working space's own name), "hsv", "hsl", "YIQ", "XYZ",
    "xyY" and "sRGB". `colorspace` is the renderer's working RGB space
    (Rec709, ACEScg...), which fixes the XYZ matrices.
  }];
  let arguments = (ins StrAttr:$from, StrAttr:$to, StrAttr:$colorspace, Osl_Triple:$value);
  let results = (outs Osl_Triple:$result);
  let assemblyFormat = [{
    $from `to` $to `in` $colorspace $value attr-dict `:` type($value) `->` type($result)
  }];
  let hasVerifier = 1;
}

def Osl_BlackbodyOp : Osl_Op<"blackbody", [Pure]> {
  let summary = "the color of a black body at a temperature in kelvin";
  let description = [{
    Planck's law integrated against the CIE 1931 observer, in the working
    space `colorspace`; from a table below 12000 K, as OSL does. It has no
    derivatives (as in OSL).
  }];
  let arguments = (ins StrAttr:$colorspace, Osl_Float:$temperature);
  let results = (outs Osl_Triple:$result);
  let assemblyFormat = "$colorspace $temperature attr-dict `:` type($temperature) `->` type($result)";
  let hasVerifier = 1;
}

def Osl_WavelengthColorOp : Osl_Op<"wavelength_color", [Pure]> {
  let summary = "the color of light of one wavelength in nanometers";
  let arguments = (ins StrAttr:$colorspace, Osl_Float:$wavelength);
  let results = (outs Osl_Triple:$result);
  let assemblyFormat = "$colorspace $wavelength attr-dict `:` type($wavelength) `->` type($result)";
  let hasVerifier = 1;
}

def Osl_LuminanceOp : Osl_Op<"luminance", [Pure]> {
  let summary = "the luminance (CIE Y) of a color of the working space";
  let arguments = (ins StrAttr:$colorspace, Osl_Triple:$color);
  let results = (outs Osl_Float:$result);
  let assemblyFormat = "$colorspace $color attr-dict `:` type($color) `->` type($result)";
  let hasVerifier = 1;
}

def Osl_SplineOp : Osl_Op<"spline", [Pure, AttrSizedOperandSegments]> {
  let summary = "spline(basis, x, [count,] knots...) for float or triple knots";
  let description = [{
    OSL's spline. With `count` (an i32, possibly varying), only the first
    `count` knots are used (at most as many as are given).
  }];
  let arguments = (ins Osl_SplineBasis:$basis, Osl_Value:$x, Optional<Osl_Value>:$count,
                       Variadic<Osl_Value>:$knots);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = [{
    $basis $x (`count` $count^ `:` type($count))? `[` $knots `]` attr-dict `:` type($x) `,` type($knots) `->` type($result)
  }];
  let hasVerifier = 1;
}

def Osl_SplineInverseOp : Osl_Op<"splineinverse", [Pure, AttrSizedOperandSegments]> {
  let summary = "splineinverse(basis, y, [count,] knots...) for float knots";
  let description = [{
    The x in [0,1] where spline(basis, x, knots) = y, for monotonic knots:
    0 or 1 outside the knots' range, else found segment by segment by
    regula falsi falling back to bisection (32 iterations, eps 1e-6).
  }];
  let arguments = (ins Osl_SplineBasis:$basis, Osl_Value:$y, Optional<Osl_Value>:$count,
                       Variadic<Osl_Value>:$knots);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = [{
    $basis $y (`count` $count^ `:` type($count))? `[` $knots `]` attr-dict `:` type($y) `,` type($knots) `->` type($result)
  }];
  let hasVerifier = 1;
}

//===----------------------------------------------------------------------===//
// Derivatives
//===----------------------------------------------------------------------===//

def Osl_DerivOp : Osl_Op<"deriv", [Pure, AllTypesMatch<["value", "result"]>]> {
  let summary = "Dx, Dy or Dz of a float or triple";
  let description = [{
    The derivative of `value` with respect to the screen x or y direction
    (or z, for volumes). Uniform values have none (0). osl-convert-to-vector
    turns it into osl.lane_deriv, which osl-derivatives resolves by
    differentiating the lane code that computes the value.
  }];
  let arguments = (ins Osl_Value:$value, Osl_DerivAxis:$axis);
  let results = (outs Osl_Value:$result);
  let assemblyFormat = "$axis $value attr-dict `:` type($value)";
  let hasVerifier = 1;
}

def Osl_LaneDerivOp : Osl_Op<"lane_deriv", [Pure, AllTypesMatch<["value", "result"]>]> {
  let summary = "the derivative of lane values, until osl-derivatives";
  let description = [{
    The vector-level form of osl.deriv: `value` is the f32 lanes
    (vector<W x f32>) or triple lanes (vector<3 x W x f32>) of a varying
    value (scalars in reference mode). osl-derivatives replaces it with forward-mode derivative code
    for exactly the operations `value` depends on, starting from the
    derivative rows of the shader globals.
  }];
  let arguments = (ins AnyType:$value, Osl_DerivAxis:$axis);
  let results = (outs AnyType:$result);
  let assemblyFormat = "$axis $value attr-dict `:` type($value)";
}

#endif // OSL_OPS_TD
