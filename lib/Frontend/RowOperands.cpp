//===- RowOperands.cpp - Values as the runtime's rows of 32-bit words
//------===//
//
// The runtime calls that take values of any type (messages, point clouds)
// take them as operands one per number, string handle, triple or closure
// (an array's elements, a matrix's 16 floats), each with a kind letter, as
// osl.print's operands.
//
//===----------------------------------------------------------------------===//
#include "IRGen.h"

using namespace mlir;

namespace osl::frontend {

char rowKindOf(const OslType &t) {
  return t.isTriple() ? 't' : t.isFloat() ? 'f' : t.isString() ? 's' : t.isClosure() ? 'k' : 'i';
}

std::optional<RowOperands> rowOperands(IRGen &g, const RValue &v, SrcLoc l,
                                       llvm::StringRef function) {
  RowOperands ops;
  const OslType &t = v.type;
  if (t.isStructLike() || t.base == BaseType::Bool) {
    g.error(l, "'" + function + "' cannot pass a value of type '" + t.str() + "' yet");
    return std::nullopt;
  }
  if (t.isArray() && t.base == BaseType::String) {
    for (const RValue &s : v.fields)
      ops.values.push_back(g.stringHandle(s, l)), ops.kinds += 's';
    return ops;
  }
  if (t.hasElems()) {
    OslType element = t.base == BaseType::Matrix ? OslType(BaseType::Float) : t.element();
    for (Value e : v.elems)
      ops.values.push_back(e), ops.kinds += rowKindOf(element);
    return ops;
  }
  ops.values.push_back(t.isString() ? g.stringHandle(v, l) : v.value);
  ops.kinds += rowKindOf(t);
  return ops;
}

RValue fromRowOperands(const RValue &like, ValueRange values) {
  RValue r = like;
  const OslType &t = like.type;
  if (t.isArray() && t.base == BaseType::String) {
    for (size_t k = 0; k < r.fields.size(); ++k)
      r.fields[k] = RValue::runtimeString(values[k]);
    return r;
  }
  if (t.hasElems()) {
    for (size_t k = 0; k < r.elems.size(); ++k)
      r.elems[k] = values[k];
    return r;
  }
  if (t.isString())
    return RValue::runtimeString(values[0]);
  return RValue::num(t, values[0]);
}

} // namespace osl::frontend
