//===- GroupInputs.cpp - Mark a layer's connected inputs ------------------===//
#include "GroupInputs.h"

#include "OslDialect/OslDialect.h"
#include "OslDialect/GroupNames.h"

#include "mlir/IR/Builders.h"
#include "llvm/ADT/StringMap.h"

using namespace mlir;

namespace osl {
namespace {

class InputMarker {
public:
  InputMarker(func::FuncOp func, const GroupLayer &layer, const std::string &shaderName,
              llvm::raw_ostream &errs)
      : func(func), layer(layer), shaderName(shaderName), errs(errs), b(func.getContext()) {}

  bool connect(const GroupConnection &c) {
    if (!connectable(c))
      return false;
    Attribute from = b.getStrArrayAttr({c.fromLayer, c.fromOutput});
    auto [base, component] = mlir::osl::splitComponentName(c.toInput);
    if (component >= 0)
      return connectComponent(base, component, from);
    // A struct input: each field from the output's field of the same name.
    std::string prefix = c.toInput + ".";
    bool structInput = false;
    func.walk([&](mlir::osl::ParamOp p) {
      if (!p.getName().starts_with(prefix))
        return;
      std::string field = p.getName().drop_front(prefix.size()).str();
      p->setAttr(kConnect, b.getStrArrayAttr({c.fromLayer, c.fromOutput + "." + field}));
      structInput = true;
    });
    return structInput || mark(c.toInput, kConnect, from);
  }

  bool mark(llvm::StringRef name, llvm::StringRef attr, Attribute value) {
    bool found = markIfPresent(name, attr, value);
    if (!found)
      noParameter(name);
    return found;
  }

  /// Sets `attr` on the parameter `name` (each of its ops); false if the
  /// layer has none.
  bool markIfPresent(llvm::StringRef name, llvm::StringRef attr, Attribute value) {
    bool found = false;
    func.walk([&](mlir::osl::ParamOp p) {
      if (p.getName() == name) {
        p->setAttr(attr, value);
        found = true;
      }
    });
    return found;
  }

private:
  /// IN[k]: the triple IN gets component k from a float parameter "IN[k]"
  /// (its default IN's own component) that the connection reads.
  bool connectComponent(llvm::StringRef base, int k, Attribute from) {
    Value &tip = tips[base];
    if (!tip)
      func.walk([&](mlir::osl::ParamOp p) {
        if (p.getName() == base && !p.getIndex() &&
            mlir::osl::isTriple(mlir::osl::getUniformType(p.getType())))
          tip = p.getResult();
      });
    if (!tip) {
      bool array = false;
      func.walk([&](mlir::osl::ParamOp p) { array |= p.getName() == base && p.getIndex(); });
      // (OSL's testshade asserts on these: "no support for individual array
      // element connections".)
      if (array)
        errs << "error: connecting to one element of array input '" << layer.name << "."
             << base << "[" << k << "]' is not supported: connect a whole array output to the "
             << "whole array input\n";
      else
        noParameter((base + "[" + llvm::Twine(k) + "]").str());
      return false;
    }
    b.setInsertionPointAfterValue(tip);
    Location loc = tip.getLoc();
    Type component = mlir::osl::withUniformity(b.getF32Type(), mlir::osl::isVarying(tip.getType()));
    Value old = b.create<mlir::osl::ExtractOp>(loc, component, tip, b.getI64IntegerAttr(k));
    auto param = b.create<mlir::osl::ParamOp>(loc, component,
                                        (base + "[" + llvm::Twine(k) + "]").str(), old);
    param->setAttr(kConnect, from);
    Value inserted = b.create<mlir::osl::InsertOp>(loc, tip.getType(), param, tip,
                                             b.getI64IntegerAttr(k));
    tip.replaceAllUsesExcept(inserted, old.getDefiningOp());
    inserted.getDefiningOp()->setOperand(1, tip);
    tip = inserted;
    return true;
  }

  /// OSL's words when metadata forbids the connection.
  bool connectable(const GroupConnection &c) {
    llvm::StringRef input = mlir::osl::splitComponentName(c.toInput).first;
    bool forbidden = false;
    func.walk([&](mlir::osl::ParamOp p) {
      llvm::StringRef name = p.getName();
      if ((name == input || name.starts_with(input.str() + ".")) &&
          p.getNotConnectable())
        forbidden = true;
    });
    if (forbidden)
      errs << "error: cannot connect to " << layer.name << "." << c.toInput
           << " because it has metadata allowconnect=0\n";
    return !forbidden;
  }

  void noParameter(llvm::StringRef name) {
    errs << "error: layer '" << layer.name << "' (shader '" << shaderName
         << "') has no parameter '" << name << "'\n";
  }

  static constexpr const char *kConnect = "osl.connect";
  func::FuncOp func;
  const GroupLayer &layer;
  const std::string &shaderName;
  llvm::raw_ostream &errs;
  OpBuilder b;
  /// A triple input's value after the components connected so far.
  llvm::StringMap<Value> tips;
};

} // namespace

bool markGroupInputs(func::FuncOp func, const GroupLayer &layer, const ShaderGroup &group,
                     const std::string &shaderName, llvm::raw_ostream &errs) {
  InputMarker marker(func, layer, shaderName, errs);
  for (const GroupConnection &c : group.connections)
    if (c.toLayer == layer.name && !marker.connect(c))
      return false;
  Builder b(func.getContext());
  // Per-geometry data for a parameter the layer lacks is ignored: the front
  // end warns of its value, as of any other (and as testshade does).
  for (const std::string &name : layer.userdata)
    marker.markIfPresent(name, "userdata", b.getUnitAttr()); // osl.param's own attribute
  return true;
}

} // namespace osl
