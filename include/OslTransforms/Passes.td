//===- Passes.td - osl-mlir passes -------------------------*- tablegen -*-===//
#ifndef OSL_TRANSFORMS_PASSES_TD
#define OSL_TRANSFORMS_PASSES_TD

include "mlir/Pass/PassBase.td"

def BindParams : Pass<"osl-bind-params", "::mlir::func::FuncOp"> {
  let summary = "Replace shader parameters by instance values or defaults";
  let description = [{
    Each osl.param becomes the value given for it (a constant) or its
    default expression. `values` is `name=v[,v,v];name=...`: one number
    for int/float, three for a triple. Unknown names are an error, as in
    testshade.
  }];
  let options = [Option<"values", "values", "std::string", "\"\"",
                        "name=value pairs separated by ';'">];
  let dependentDialects = ["::mlir::arith::ArithDialect"];
}

def LinkShaderGroup : Pass<"osl-link-group", "::mlir::ModuleOp"> {
  let summary = "Link the layers of a shader group into one shader function";
  let description = [{
    The module holds one func per layer, in group order, each marked
    `osl.layer = "name"`; a connected input is an osl.param marked
    `osl.connect = ["fromLayer", "fromOutput"]`. Layers marked `osl.entry`
    (default: the last layer, the root; an integer `osl.entry` is the place
    among the entries they were named in, which is the order they run in,
    an entry read by an earlier one running where that one reads it, once)
    run at the top level in order and
    keep their osl.output ops (the root's under their own names, the others'
    as "layer.output"); a module attribute `osl.group_outputs` (a list of
    such names) keeps only those (a layer named there runs unconditionally
    too; an unknown name is an error). Every other layer is inlined where its
    outputs are first needed: before the earliest op, in the innermost block
    enclosing all its reads, that is outside every loop. Reads inside one
    arm of a varying if therefore run the layer only on the lanes that take
    that arm (osl-insert-mask-stack masks it) and a layer runs at most once
    per point. A layer nobody reads is not inlined at all.

    With `lazy=false` (osl-run -O0/-O1) every layer is inlined at the top
    level in group order and keeps all its outputs (as "layer.output"), so
    that every layer runs. With `opaque-params` (-O0) each unconnected
    parameter whose value is a constant becomes a load from a writable
    external global, so nothing is specialised on it; parameters marked
    `userdata` (lockgeom=0) are always loaded that way.

    With `lazy-globals=false` (OSL's lazyglobals=0 option) a layer that
    assigns Ci is not lazy either: it runs at the top level in group order,
    and the layers after it read the Ci it left. With `lazy-error=false`
    (OSL's lazyerror=0) neither is a layer that calls error(), so that its
    errors are reported whether or not its outputs are read. Both are
    decided as OSL decides, on the layer folded with its parameters bound
    (`if (set_Ci) Ci = ...` with set_Ci 0 assigns nothing), and neither
    applies when the group names its entry layers: those run alone, with
    the layers they read, as OSL's execute_layer runs them.

    A parameter marked `userdata` (per-geometry data, lockgeom=0 in its
    declaration or on the command line) is never taken as constant: an
    upstream layer whose output would fold only through it still runs
    where that output is read (its printf and all), as in OSL.

    With `trace-layers` each layer prints OSL's llvm_debug_layers lines
    where it is entered and left ("(SHADER LAYER) enter layer INDEX LAYER
    SHADER"; a layer marked `osl.entry_named`, named as an entry, says
    "checking for already-run layer" first, and an entry that already ran
    takes its "early exit"); a layer's shader is its func's
    `osl.layer_shader`.

    Errors: an unknown layer or output, a connection to the same or an
    earlier layer (a cycle), and a type mismatch between output and input.
  }];
  let options = [Option<"lazy", "lazy", "bool", "true",
                        "inline upstream layers where their outputs are read "
                        "and drop unread layers">,
                 Option<"lazyGlobals", "lazy-globals", "bool", "true",
                        "let layers that assign Ci run lazily too">,
                 Option<"lazyError", "lazy-error", "bool", "true",
                        "let layers that call error() run lazily too">,
                 Option<"opaqueParams", "opaque-params", "bool", "false",
                        "load every unconnected constant parameter from memory">,
                 Option<"traceLayers", "trace-layers", "bool", "false",
                        "print where each layer is entered and left, as OSL's "
                        "llvm_debug_layers option does">];
  let dependentDialects = ["::mlir::LLVM::LLVMDialect", "::mlir::func::FuncDialect"];
}

def FoldConstants : Pass<"osl-fold-constants", "::mlir::func::FuncOp"> {
  let summary = "Evaluate osl operations on constants; decide constant control flow";
  let description = [{
    Render-time specialisation: once instance values are constants, an
    exactly defined lane operation (arithmetic, comparisons, logic, bit
    operations, conversions, building and taking apart triples) whose
    operands are all constants is replaced by the arith ops its lowering
    would emit (LaneMath), which fold; so the folded value has the bits the
    kernel would have computed. Transcendental functions are left alone:
    their folders would use the host's libm, not OSL's algorithms. A select
    or an osl.if on a constant condition becomes the chosen value or arm,
    which is how a value that looked varying becomes uniform before
    osl-varying-propagation runs.
  }];
  let dependentDialects = ["::mlir::arith::ArithDialect", "::mlir::math::MathDialect"];
}

def UnrollConstantLoops : Pass<"osl-unroll-constant-loops", "::mlir::func::FuncOp"> {
  let summary = "Unroll uniform loops whose trip count folds to a constant";
  let description = [{
    A loop over a small local array (`for (i = 0; i < n; ++i) a[i]`) reads
    and writes its elements through a chain of selects on the index, one per
    element, at every trip. Peeled one trip at a time, with
    osl-fold-constants' patterns applied to each, a loop whose condition
    folds to a constant at every trip becomes straight-line code whose
    indices are constants: the elements are plain values, and a count kept
    by an unrolled loop (`n += 1` under conditions that fold) becomes a
    constant the next loop is unrolled with. A loop is left as it is when a
    trip's condition does not fold, or when unrolling it would take more
    than `max-trips` trips or add more than `max-ops` operations, or when
    it indexes no array by a value it carries (unrolling it would only
    cost compile time). Reads of arrays of eight or more elements are
    osl.pick, which reads memory at any index: they do not count.
  }];
  let options = [
    Option<"maxTrips", "max-trips", "int64_t", "32", "most trips a loop is unrolled for">,
    Option<"maxOps", "max-ops", "int64_t", "1000",
           "most operations the unrolled trips of one loop may hold">,
  ];
  let dependentDialects = ["::mlir::arith::ArithDialect", "::mlir::math::MathDialect",
                           "::mlir::scf::SCFDialect"];
}

def VaryingPropagation : Pass<"osl-varying-propagation", "::mlir::func::FuncOp"> {
  let summary = "Infer which values are varying";
  let description = [{
    Shader globals are varying; a value computed from a varying value is
    varying (data dependence), and so is a value assigned under a varying
    condition and read after the join or in a later loop iteration (control
    dependence). Everything else stays uniform and scalar. Uniform values
    flowing into varying slots get an explicit osl.broadcast.
  }];
}

def InsertMaskStack : Pass<"osl-insert-mask-stack", "::mlir::func::FuncOp"> {
  let summary = "Turn varying control flow into masked straight-line code";
  let description = [{
    A varying osl.if runs both arms and selects per lane; a varying
    osl.while carries a lane mask, iterates while any lane is active and
    freezes the values of lanes that left. Loops are seeded with the mask of
    the enclosing context, so lanes that are off never keep a loop going
    (the outermost mask is the batch's active lanes). Uniform control flow
    stays ordinary scf.if/scf.while with no masking cost.

    An arm of a varying if that holds a loop, a noise call, or more than `skip-threshold`
    operations runs under `scf.if (osl.any(mask))`, so a batch in which no
    lane takes it skips it at run time; smaller arms run unconditionally
    because the test would cost more than the arm. When the other arm only
    passes values on (`if (c) { ... }` with no else), the merge happens
    inside the guard, and a skipped arm leaves the values as they were
    without waiting for its condition. In a loop such a one-sided arm is
    guarded from three operations of its own on (`if (d < r) { cover +=
    1 - d / r; if (cover > 1.25) break; }`): the values the loop carries
    then depend on the condition only when some lane takes the arm, as in
    OSL's batched code, which branches around every arm.
  }];
  let options = [Option<"skipThreshold", "skip-threshold", "int", "16",
                        "operations in an arm from which it is skipped when its "
                        "mask is empty">,
                 Option<"countLanes", "count-lanes", "bool", "false",
                        "start each masked block with osl.count_lanes (lane "
                        "statistics for osl-run --lane-stats)">];
  let dependentDialects = ["::mlir::scf::SCFDialect"];
}

def LaneGroupFilter : Pass<"osl-lane-group-filter", "::mlir::func::FuncOp"> {
  let summary = "Run lookups and Gabor noises whose per-call options vary once per group of agreeing lanes";
  let description = [{
    OpenImageIO takes a texture's file, wrap modes, interpolation and
    subimage once per call. An osl.texture whose choice of one of them is
    varying becomes a loop: the first pending lane leads, the lanes whose
    choices equal its own form a group, the lookup runs for that group
    (osl.texture with the lead's uniform choices and the group as mask),
    and the group leaves the pending lanes; the loop ends when none is
    left. Lookups whose choices are uniform stay one call, with no loop.
    Gabor noise's options (osl.noise gabor: anisotropic, direction,
    bandwidth, impulses, do_filter) split the same way; the noise, a pure
    op with no mask, is computed for every lane and kept for the group's.
    Lanes agree when their values have the same bits (osl.cmp same), so a
    lane always joins its own group and the loop ends, NaNs included.
    Runs after osl-insert-mask-stack; the loop's condition is uniform.
  }];
  let dependentDialects = ["::mlir::scf::SCFDialect", "::mlir::arith::ArithDialect"];
}

def UniformReference : Pass<"osl-uniform-reference", "::mlir::func::FuncOp"> {
  let summary = "Make every value uniform: run one point at a time (reference mode)";
  let description = [{
    Replaces every !osl.varying<T> by T and removes osl.broadcast, so that
    at width 1 the shader runs one point per call and osl.if/osl.while
    become ordinary branches and loops on that point's values: no masks,
    no selects. This is the reference the differential tester compares the
    vectorized kernels with (osl-run --interpret); it shares the math
    lowering, so results agree bit for bit when masking is right.
  }];
}

def Derivatives : Pass<"osl-derivatives", "::mlir::ModuleOp"> {
  let summary = "Resolve osl.lane_deriv by forward-mode differentiation";
  let description = [{
    Runs after osl-convert-to-vector. Each osl.lane_deriv becomes the
    derivative of its operand with respect to x, y or z, computed by the
    chain rule through the arith, math and vector operations that produce
    it, from the derivative rows of the shader globals (dPdx, dudx, ...).
    Only what a derivative is asked of is differentiated.

    A library routine that stays a call (`osl.keep_call`) is differentiated
    along x and y by a call of its dual routine: a function of the routine's
    arguments and their tangents returning its results and their
    derivatives along x and y, built once from the routine's code and keyed
    by its recipe (`recipe dual x y`), as OSL's batched library calls noise
    on dual numbers. A routine compiled before is declared instead of built
    (`assume-compiled` takes every one as compiled). Other routines, all of
    them in a shader asking for derivatives along z, and all in reference
    mode (`dual-routines=false`: every value uniform, the routines' options
    included) are copied in place and differentiated there.
  }];
  let options = [Option<"dualRoutines", "dual-routines", "bool", "true",
                        "differentiate library calls kept as calls through their dual "
                        "routines (false: in place, as reference mode does)">,
                 Option<"assumeCompiled", "assume-compiled", "bool", "false",
                        "take every dual routine as compiled already (the compiler "
                        "asks its library objects instead)">];
  let dependentDialects = ["::mlir::arith::ArithDialect", "::mlir::math::MathDialect",
                           "::mlir::vector::VectorDialect", "::mlir::LLVM::LLVMDialect",
                           "::mlir::func::FuncDialect"];
}

def InlineLibrary : Pass<"osl-inline-library", "::mlir::ModuleOp"> {
  let summary = "Put small library routines' code in place of their calls";
  let description = [{
    osl-convert-to-vector lowers library routines (noise of every kind,
    spline inversion) to calls of private functions built from a recipe
    (`osl.library_recipe`), one per routine and signature, which the JIT
    compiles once and keeps as objects across shaders
    (OslCompiler/LibraryObjects.h): a shader's compile time does not grow
    with each noise call it makes. A routine found compiled is a
    declaration. This pass chooses which calls of routines with code go
    back in place, and erases the routines no call is left to. Run after
    osl-derivatives (which copies in place the routines a derivative needs
    where no dual routine serves).

    A function without loops or branches whose ops times its calls is at
    most `inline-ops` (cell and hash noise called once or twice) goes back
    in place while the copies made, cheapest function first, fit in
    `inline-budget` for the kernel: a call clobbers every vector register,
    so the caller spills its live values around it, which costs more than
    such a body (and inlined constant arguments fold). A body of more than
    `inline-always-ops` ops goes back only where a call passes it a
    constant or runs in a loop: copies of it that do not fold cost codegen
    time and gain little over a call made once. The bounds keep unrolled
    loops of calls, or many different routines called once each (a noise
    name chosen per point), from growing the kernel. Calls their site
    marked `osl.keep_call` stay calls.

    With `keep-calls=false` (--math=double, whose f64 rewrite stays within
    the kernel, and osl-run --inline-library) every call of a routine with
    code is replaced by the code, calls in that code too.
  }];
  let options = [Option<"keepCalls", "keep-calls", "bool", "true",
                        "keep the calls it does not gain to inline; false: inline "
                        "every call of a routine with code">,
                 Option<"inlineOps", "inline-ops", "unsigned", "500",
                        "inline a straight-line function whose ops times its calls "
                        "is at most this">,
                 Option<"inlineBudget", "inline-budget", "unsigned", "1500",
                        "inline such functions while their copies' ops add up "
                        "to at most this">,
                 Option<"inlineAlwaysOps", "inline-always-ops", "unsigned", "100",
                        "a function of more ops is inlined only where a call "
                        "passes it a constant or runs in a loop">];
  let dependentDialects = ["::mlir::func::FuncDialect"];
}

def ApproximateMath : Pass<"osl-approximate-math", "::mlir::ModuleOp"> {
  let summary = "Expand math ops into the arithmetic that computes them, before folding";
  let description = [{
    `level` chooses how f32 math ops are computed (osl-run --math=):

    * `default`: sin, cos, tan, atan, atan2, exp, exp2, log, log2, log10
      and pow become OSL's own algorithms (OslMathApproximation.cpp), the
      other math ops MLIR's polynomial approximations. Reproduces OSL.
    * `fast`: per op, the faster of OSL's algorithm and MLIR's polynomial
      approximation as measured by bench/osl-mathbench: OSL's for tan,
      atan, atan2 and pow, MLIR's for the others (MathLevels.cpp);
      measured bounds in bench/MATH.md.
    * `precise`: each op evaluated in f64 by glibc's libm, one call per
      lane, then rounded to f32: within 1 ULP of the correctly rounded
      result.
    * `polynomial`: MLIR's polynomial approximations for every op; not an
      osl-run level, measured by bench/osl-mathbench as one implementation.
    * `double`: as precise here; the osl-to-llvm pipeline then runs
      osl-evaluate-in-double (the reference for whole-shader errors).

    It runs right after osl-derivatives and before any canonicalization,
    because the math dialect's folders evaluate constant operands with the
    host's libm: a value the optimizer proves constant would otherwise
    differ from the same value computed at run time (found by the
    differential tester, seed 7489). Every level builds the same ops for
    scalars and vectors of any width, so results are bit-identical across
    widths.
  }];
  let options = [Option<"level", "level", "::mlir::osl::MathLevel",
                        "::mlir::osl::MathLevel::Default",
                        "how math ops are computed: fast, default or precise",
                        [{::llvm::cl::values(
                          clEnumValN(::mlir::osl::MathLevel::Fast, "fast",
                                     "MLIR's polynomial approximations"),
                          clEnumValN(::mlir::osl::MathLevel::Default, "default",
                                     "OSL's (OIIO fast_*) algorithms"),
                          clEnumValN(::mlir::osl::MathLevel::Precise, "precise",
                                     "f64 libm per lane, rounded to f32"),
                          clEnumValN(::mlir::osl::MathLevel::Polynomial, "polynomial",
                                     "MLIR's polynomial approximations for every op"),
                          clEnumValN(::mlir::osl::MathLevel::Double, "double",
                                     "precise math; the pipeline evaluates in f64"))}]>];
  let dependentDialects = ["::mlir::arith::ArithDialect", "::mlir::vector::VectorDialect",
                           "::mlir::func::FuncDialect"];
}

def EvaluateInDouble : Pass<"osl-evaluate-in-double", "::mlir::ModuleOp"> {
  let summary = "Compute every float value of the kernel in f64 (--math=double)";
  let description = [{
    The double-precision reference for a whole shader's error: runs after
    osl-approximate-math at the precise level and turns every f32 value
    (arithmetic, comparisons, selects, vector ops, loop-carried values) into
    f64. Loads of globals and tables are extended (exactly), stores of
    outputs rounded once, and a float reinterpreted as bits is rounded to
    f32 first. Not a shading mode for images: a measuring instrument.
  }];
  let dependentDialects = ["::mlir::arith::ArithDialect"];
}

def ContractFma : Pass<"osl-contract-fma", "::mlir::ModuleOp"> {
  let summary = "Fuse a*b+c into one fused multiply-add (--math=fast)";
  let description = [{
    testshade computes a*b+c with two roundings, and the default levels
    reproduce it; OSL's batched backend fuses them. At --math=fast this
    pass does too, before LLVM sees the kernel: `addf(mulf(a, b), c)`
    (either order) becomes `math.fma(a, b, c)` and `subf(mulf(a, b), c)`
    `math.fma(a, b, -c)`, when the product has no other use. Deciding here,
    on the same ops at every width, keeps widths bit-identical (LLVM's own
    contraction may decide differently for scalars and vectors).
  }];
  let dependentDialects = ["::mlir::math::MathDialect", "::mlir::arith::ArithDialect"];
}

#endif // OSL_TRANSFORMS_PASSES_TD
