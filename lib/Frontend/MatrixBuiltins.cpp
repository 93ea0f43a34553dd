//===- MatrixBuiltins.cpp - matrix(...), determinant, transpose, getmatrix -===//
//
// The matrix library on top of IRGen's matrix arithmetic (IRGenMatrix.cpp).
// Space names are compile-time strings; testshade's spaces are fixed (and
// its camera's follow the image size), so named matrices are constants.
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

using namespace osl::frontend;
using namespace mlir;
using namespace mlir::osl;

namespace {

std::string typesText(const std::vector<RValue> &args) {
  std::string t;
  for (size_t k = 0; k < args.size(); ++k)
    t += (k ? ", " : "") + args[k].type.str();
  return t;
}

/// A space name known when the shader is compiled.
bool spaceNames(IRGen &g, const RValue &v, const Expr &e, llvm::StringRef fn) {
  auto names = g.compileTimeStrings(v, e.loc, "the space names of '" + fn.str() + "'");
  if (!names)
    return false;
  for (const std::string &name : *names)
    if (name.empty())
      return g.valueError(e.loc, "empty space name");
  return true;
}

/// matrix(f), matrix(m), matrix(16 floats), matrix(from, to), and
/// matrix(space, f | 16 floats): the matrix given in `space`, i.e.
/// space->common * M (OSL's prepend).
std::optional<RValue> emitMatrixConstructor(IRGen &g, const Expr &call) {
  std::vector<RValue> args;
  OslType floatType(BaseType::Float), matrixType(BaseType::Matrix);
  for (const ExprPtr &a : call.args) {
    auto v = g.emitExpr(*a, &floatType);
    if (!v)
      return std::nullopt;
    args.push_back(*v);
  }
  auto wrong = [&]() -> std::optional<RValue> {
    g.error(call.loc, "wrong arguments to 'matrix(" + typesText(args) +
                          ")'; candidates: matrix(float); matrix(matrix); matrix(16 floats); "
                          "matrix(string from, string to); matrix(string space, float); "
                          "matrix(string space, 16 floats)");
    return std::nullopt;
  };
  size_t first = !args.empty() && args[0].type.isString() ? 1 : 0;
  if (first && !spaceNames(g, args[0], *call.args[0], "matrix"))
    return std::nullopt;
  RValue m;
  size_t count = args.size() - first;
  // Space names may be chosen per point: each choice runs on its lanes.
  auto named = [&](const RValue &from, const RValue &to) {
    return g.forEachStringChoice(from, call.loc, [&](const std::string &f) {
      return g.forEachStringChoice(to, call.loc, [&](const std::string &t) {
        bool known = true;
        return std::optional<RValue>(g.namedMatrix(f, t, call.loc, known));
      });
    });
  };
  if (first && count == 1 && args[1].type.isString()) {
    if (!spaceNames(g, args[1], *call.args[1], "matrix"))
      return std::nullopt;
    return named(args[0], args[1]);
  }
  if (count == 1 && (args[first].type.isScalar() || (!first && args[0].type.isMatrix()))) {
    auto c = g.coerce(args[first], matrixType, call.args[first]->begin, "in 'matrix(...)'");
    if (!c)
      return std::nullopt;
    m = *c;
  } else if (count == 16) {
    IRGen::MatrixElems elems;
    for (size_t k = first; k < args.size(); ++k) {
      if (!args[k].type.isScalar())
        return wrong();
      elems.push_back(
          g.convert(args[k].value, g.builder().getF32Type(), call.args[k]->loc));
    }
    m = IRGen::matrixValue(elems);
  } else {
    return wrong();
  }
  if (!first || (!args[0].isStringChoice() && args[0].str == "common"))
    return m;
  // An unknown space leaves the matrix as it is (OSL reports it at run time).
  auto toCommon = named(args[0], RValue::string("common"));
  if (!toCommon)
    return std::nullopt;
  return IRGen::matrixValue(g.matrixMultiply(toCommon->elems, m.elems, call.loc));
}

/// getmatrix(from, to, output M) and getmatrix(from, output M) (to
/// "common"): 1, or 0 when a space is unknown (M then holds the known half).
std::optional<RValue> emitGetMatrix(IRGen &g, const Expr &call) {
  size_t n = call.args.size();
  if (n != 2 && n != 3) {
    g.error(call.loc, "wrong arguments to 'getmatrix'; candidates: int getmatrix(string from, "
                      "string to, output matrix); int getmatrix(string from, output matrix)");
    return std::nullopt;
  }
  RValue names[2] = {RValue::string(""), RValue::string("common")};
  for (size_t k = 0; k + 1 < n; ++k) {
    auto v = g.emitExpr(*call.args[k]);
    if (!v)
      return std::nullopt;
    if (!v->type.isString()) {
      g.error(call.args[k]->loc, "'getmatrix' expects a space name (a string) here, got '" +
                                     v->type.str() + "'");
      return std::nullopt;
    }
    if (!spaceNames(g, *v, *call.args[k], "getmatrix"))
      return std::nullopt;
    names[k] = *v;
  }
  auto lv = g.emitLValue(*call.args[n - 1]);
  if (!lv)
    return std::nullopt;
  // Names may be chosen per point: each pair runs on its lanes and gives
  // the matrix and whether both spaces are known.
  auto perNames = [&](bool wantMatrix) {
    return g.forEachStringChoice(names[0], call.loc, [&](const std::string &f) {
      return g.forEachStringChoice(names[1], call.loc, [&](const std::string &t) {
        if (wantMatrix) {
          bool known = true;
          return std::optional<RValue>(g.namedMatrix(f, t, call.loc, known));
        }
        bool known = bool(namedSpaceTransform(f, t, g.cameraImage()));
        return std::optional<RValue>(
            RValue::num(OslType(BaseType::Int), g.constInt(known ? 1 : 0, call.loc)));
      });
    });
  };
  auto m = perNames(/*wantMatrix=*/true);
  if (!m)
    return std::nullopt;
  auto v = g.coerce(*m, lv->type, call.args[n - 1]->begin,
                    "in output argument " + llvm::Twine(n) + " of 'getmatrix'");
  if (!v)
    return std::nullopt;
  g.storeLValue(*lv, *v, call.loc);
  return perNames(/*wantMatrix=*/false);
}

/// determinant(M) and transpose(M).
std::optional<RValue> emitMatrixFunction(IRGen &g, const Expr &call) {
  bool isDet = call.name == "determinant";
  auto evaluated = emitArgs(g, call);
  if (!evaluated)
    return std::nullopt;
  std::vector<RValue> &args = *evaluated;
  if (args.size() != 1 || !args[0].type.isMatrix()) {
    g.error(call.loc, "wrong arguments to '" + call.name + "(" + typesText(args) +
                          ")'; candidates: " +
                          (isDet ? "float determinant(matrix)" : "matrix transpose(matrix)"));
    return std::nullopt;
  }
  if (isDet)
    return RValue::num(OslType(BaseType::Float),
                       g.matrixDeterminant(args[0].elems, call.loc));
  return IRGen::matrixValue(g.matrixTranspose(args[0].elems));
}

} // namespace

namespace osl::frontend {

std::optional<RValue> emitMatrixBuiltin(IRGen &g, const Expr &call, bool &known) {
  known = true;
  if (call.isCtor) {
    if (call.castType.base == BaseType::Matrix)
      return emitMatrixConstructor(g, call);
  } else if (call.name == "getmatrix") {
    return emitGetMatrix(g, call);
  } else if (call.name == "determinant" || call.name == "transpose") {
    return emitMatrixFunction(g, call);
  }
  known = false;
  return std::nullopt;
}

} // namespace osl::frontend
