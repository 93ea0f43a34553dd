//===- LinkShaderGroup.cpp - One function for a whole shader group -------===//
//
// A group compiles to one function so that specialisation (constant
// parameters, folding, dead code) works across layers, as OSL's runtime
// optimizer does. Upstream layers are inlined where their outputs are first
// read rather than up front: that keeps them lazy (a read under a varying
// if runs the layer only on the lanes that take the arm) and lets an unread
// layer vanish before any pass sees it.
//
//===----------------------------------------------------------------------===//
#include "OslDialect/OslDialect.h"
#include "OslDialect/GroupNames.h"
#include "OslLanes/LaneMath.h"
#include "OslTransforms/Passes.h"
#include "SharedGlobals.h"
#include "VaryingTypes.h"

#include "mlir/IR/Builders.h"
#include "mlir/IR/IRMapping.h"
#include "mlir/Pass/PassManager.h"
#include "mlir/Transforms/Passes.h"
#include "llvm/ADT/StringMap.h"
#include "llvm/ADT/StringSet.h"

namespace mlir::osl {
#define GEN_PASS_DEF_LINKSHADERGROUP
#include "OslTransforms/Passes.h.inc"
} // namespace mlir::osl

using namespace mlir;
using namespace mlir::osl;

namespace {

constexpr const char *kLayerAttr = "osl.layer";
constexpr const char *kEntryAttr = "osl.entry";
constexpr const char *kConnectAttr = "osl.connect";
constexpr const char *kFromLayerAttr = "osl.from_layer";
constexpr const char *kGroupOutputsAttr = "osl.group_outputs";

/// OSL's name for a base type, for messages.
std::string typeName(Type t) {
  t = getUniformType(t);
  if (t.isF32())
    return "float";
  if (t.isInteger(32))
    return "int";
  if (isTriple(t))
    return "color/point/vector/normal";
  std::string s;
  llvm::raw_string_ostream(s) << t;
  return s;
}

/// The (layer, output) an osl.param reads, if it is connected.
std::optional<std::pair<StringRef, StringRef>> connection(ParamOp param) {
  auto names = param->getAttrOfType<ArrayAttr>(kConnectAttr);
  if (!names || names.size() != 2)
    return std::nullopt;
  return std::make_pair(cast<StringAttr>(names[0]).getValue(),
                        cast<StringAttr>(names[1]).getValue());
}

/// What a layer does once its unconnected parameters take their values
/// and it is folded, as OSL's optimizer sees it before it decides what runs.
struct FoldedLayer {
  /// Its outputs (by outputKey) that are constants: OSL folds such a
  /// connection into the reading layer, and then never runs this layer for
  /// it (its printf and all).
  llvm::StringMap<TypedAttr> constantOutputs;
  /// Assigns Ci (a Ci under a parameter that turns it off does not count):
  /// with lazy-globals=false such a layer is not lazy (it runs in group
  /// order, as entries do) and the later layers see its Ci.
  bool writesCi = false;
  /// Calls error(): with lazy-error=false such a layer is not lazy either.
  bool callsError = false;
};

struct Layer {
  func::FuncOp func;
  StringRef name;
  bool entry = false;
  /// Where an explicitly named entry comes in the order the entries were
  /// given (a unit osl.entry: its place in the group).
  int64_t entryOrder = 0;
  /// Made when first asked for (LinkShaderGroupPass::folded).
  std::optional<FoldedLayer> folded;
};

struct LinkShaderGroupPass
    : public mlir::osl::impl::LinkShaderGroupBase<LinkShaderGroupPass> {
  using mlir::osl::impl::LinkShaderGroupBase<LinkShaderGroupPass>::LinkShaderGroupBase;

  void runOnOperation() override {
    ModuleOp module = getOperation();
    for (auto f : module.getOps<func::FuncOp>())
      if (auto name = f->getAttrOfType<StringAttr>(kLayerAttr)) {
        layerIndex[name.getValue()] = layers.size();
        layers.push_back({f, name.getValue()});
      }
    if (layers.empty()) {
      // A single shader: nothing to link, and no later layer reads its globals.
      module.walk([](SetGlobalOp write) { write.erase(); });
      return;
    }
    // The root layer's outputs keep their own names in the group: asked for
    // as ROOT.NAME (and not also as NAME), they are NAME, and only the root
    // runs for them.
    llvm::StringSet<> rootOnly, plain;
    if (auto requested = module->getAttrOfType<ArrayAttr>(kGroupOutputsAttr)) {
      keepAllOutputs = false;
      for (Attribute a : requested) {
        StringRef name = cast<StringAttr>(a).getValue();
        auto [layer, output] = name.rsplit('.');
        if (!output.empty() && layer == layers.back().name)
          rootOnly.insert(name = output);
        else
          plain.insert(name);
        requestedOutputs.insert(name);
      }
    }
    bool anyEntry = false;
    for (auto [index, l] : llvm::enumerate(layers)) {
      Attribute entry = l.func->getAttr(kEntryAttr);
      anyEntry |= l.entry = bool(entry);
      auto order = dyn_cast_or_null<IntegerAttr>(entry);
      l.entryOrder = order ? order.getInt() : int64_t(index);
    }
    // (osl.no_entries: entries were named, but none of them runs.)
    bool noEntries = module->hasAttr("osl.no_entries");
    if (!anyEntry && !noEntries)
      layers.back().entry = true;
    explicitEntries = anyEntry || noEntries;
    // Named entries run alone at every optimization level: OSL's
    // execute_layer runs the layer and pulls what it reads where it reads
    // it; only a whole group's run runs every layer unoptimized.
    lazyLayers = lazy || explicitEntries;
    // Asking for "layer.name" makes that layer run for it; asking for
    // "name", every layer with an output of that name (testshade makes each
    // a renderer output, which OSL never skips). Entries named explicitly
    // run alone: OSL's execute_layer runs no other layer for an output.
    for (auto &name : requestedOutputs) {
      if (explicitEntries)
        break;
      if (rootOnly.contains(name.getKey()) && !plain.contains(name.getKey())) {
        layers.back().entry = true;
        continue;
      }
      auto [layer, output] = name.getKey().rsplit('.');
      auto it = layerIndex.find(layer);
      if (!output.empty() && it != layerIndex.end()) {
        layers[it->second].entry = true;
        continue;
      }
      for (Layer &l : layers)
        l.func.walk([&](OutputOp out) {
          if (out.getName() == name.getKey())
            l.entry = true;
        });
    }
    if (failed(checkConnections()))
      return signalPassFailure();

    OpBuilder b(module.getContext());
    b.setInsertionPointToEnd(module.getBody());
    func::FuncOp root = layers.back().func;
    group = b.create<func::FuncOp>(root.getLoc(), "osl_group", b.getFunctionType({}, {}));
    if (Attribute type = root->getAttr("osl.shader_type"))
      group->setAttr("osl.shader_type", type);
    b.setInsertionPointToStart(group.addEntryBlock());
    Operation *ret = b.create<func::ReturnOp>(root.getLoc());

    // Entries and, without lazy globals, layers that assign Ci and, without
    // lazy errors, layers that call error() (every layer when not lazy) run
    // unconditionally, in order. Entry layers named explicitly run alone
    // (with what they read), as OSL's execute_layer runs them.
    llvm::StringSet<> pulledByEntries = entriesRunInside();
    auto eager = [&](Layer &l) {
      return (l.entry && !pulledByEntries.contains(l.name)) || !lazyLayers ||
             (!explicitEntries && ((!lazyGlobals && folded(l).writesCi) ||
                                   (!lazyError && folded(l).callsError)));
    };
    SmallVector<Layer *> order;
    for (Layer &l : layers)
      order.push_back(&l);
    if (explicitEntries && lazyLayers)
      sortByEntryOrder(order);
    if (!explicitEntries) {
      b.setInsertionPointToStart(&group.front());
      trace(b, layers.back(), "enter");
    }
    for (Layer *l : order) {
      b.setInsertionPoint(ret);
      if (eager(*l)) {
        placed[l->name] = inlineLayer(*l, b, /*inOrder=*/true);
        ranInOrder.push_back(l);
      } else if (l->entry && pulledByEntries.contains(l->name) && l != &layers.back()) {
        // Its turn, after the entry that ran it.
        trace(b, *l, "checking for already-run");
        trace(b, *l, "  taking early exit, already executed");
      }
    }
    // The others, last first: by then every layer that reads one is placed.
    // Dead code goes first, as OSL optimizes a layer before it decides what
    // upstream layers run: a read nothing uses (isconnected() aside) runs
    // no layer.
    OpPassManager cleanup(func::FuncOp::getOperationName());
    cleanup.addPass(createCanonicalizerPass());
    if (lazyLayers)
      for (Layer &l : llvm::reverse(layers))
        if (!eager(l)) {
          if (failed(runPipeline(cleanup, group)))
            return signalPassFailure();
          placeLazily(l);
        }

    // The layers now run in OSL's order: each global's reads see what the
    // layers before them assigned.
    forwardWrittenGlobals(group);
    if (failed(checkRequestedOutputs()))
      return signalPassFailure();
    makeParamsOpaque();
    std::string rootName = layers.back().name.str();
    for (Layer &l : layers)
      l.func.erase();
    group.setSymName(rootName);
  }

  /// Orders layers as their entries were named (-entry); others keep theirs.
  static void sortByEntryOrder(SmallVectorImpl<Layer *> &order) {
    llvm::stable_sort(order, [](Layer *a, Layer *b) { return a->entryOrder < b->entryOrder; });
  }

  /// `layer`'s outputs called `name` (one per element written by index).
  static SmallVector<OutputOp> outputsNamed(func::FuncOp layer, StringRef name) {
    SmallVector<OutputOp> outs;
    layer.walk([&](OutputOp out) {
      if (out.getName() == name)
        outs.push_back(out);
    });
    return outs;
  }

  /// Writes `value` to the group's output `name` in place of `out`'s element.
  void writeGroupOutput(OutputOp out, StringRef name, Value value) {
    OpBuilder b(group.front().getTerminator());
    auto copy = b.create<OutputOp>(out.getLoc(), name, value);
    if (auto index = out.getIndexAttr())
      copy.setIndexAttr(index);
  }

  /// Entry layers that an entry given before them reads, directly or
  /// through other layers: OSL runs such a layer inside its reader, where
  /// the reader first needs it, and then skips it as already run. (Only
  /// named entries are ordered; without them this is empty.)
  llvm::StringSet<> entriesRunInside() {
    llvm::StringSet<> inside, reached;
    if (!explicitEntries || !lazyLayers)
      return inside;
    SmallVector<Layer *> entries;
    for (Layer &l : layers)
      if (l.entry)
        entries.push_back(&l);
    sortByEntryOrder(entries);
    for (Layer *entry : entries) {
      if (reached.contains(entry->name)) {
        inside.insert(entry->name);
        continue;
      }
      SmallVector<Layer *> work{entry};
      while (!work.empty()) {
        Layer *l = work.pop_back_val();
        l->func.walk([&](ParamOp param) {
          if (auto from = connection(param); from && reached.insert(from->first).second)
            if (auto it = layerIndex.find(from->first); it != layerIndex.end())
              work.push_back(&layers[it->second]);
        });
      }
    }
    return inside;
  }

  LogicalResult checkConnections() {
    bool ok = true;
    // (Named variables, not structured bindings: C++17 lambdas cannot
    // capture those.)
    for (auto entry : llvm::enumerate(layers)) {
      size_t index = entry.index();
      auto &l = entry.value();
      l.func.walk([&](ParamOp param) {
        auto from = connection(param);
        if (!from)
          return;
        auto [fromLayer, fromOutput] = *from;
        auto it = layerIndex.find(fromLayer);
        if (it == layerIndex.end()) {
          param.emitError("input '") << param.getName() << "' of layer '" << l.name
                                     << "' is connected to unknown layer '" << fromLayer
                                     << "'";
          ok = false;
          return;
        }
        if (it->second >= index) {
          param.emitError("connecting layer '")
              << fromLayer << "' to layer '" << l.name
              << "' would make a cycle: a layer may only read layers declared before it";
          ok = false;
          return;
        }
        std::pair<StringRef, int> split = splitComponentName(fromOutput);
        StringRef outputName = split.first;
        int component = split.second;
        func::FuncOp fromFunc = layers[it->second].func;
        std::optional<int64_t> element = elementIndex(param);
        bool exists = false;
        fromFunc.walk([&](OutputOp o) { exists |= o.getName() == outputName; });
        int64_t inputLength = arrayLength(l.func, param.getName(), /*outputs=*/false);
        int64_t outputLength = arrayLength(fromFunc, outputName, /*outputs=*/true);
        if (exists && component < 0 && inputLength != outputLength) {
          // One message for the array, not one per element.
          if (reportedArrays.insert((l.name + "." + param.getName()).str()).second)
            param.emitError("cannot connect output '")
                << fromLayer << "." << fromOutput << "' (" << describeLength(outputLength)
                << ") to input '" << l.name << "." << param.getName() << "' ("
                << describeLength(inputLength) << ")";
          ok = false;
          return;
        }
        OutputOp out = findOutput(fromFunc, outputName, element);
        if (!out && component >= 0 && arrayLength(fromFunc, outputName, true) > 0) {
          // OSL's testshade asserts on these too ("no support for
          // individual array element connections").
          param.emitError("connecting one element of array output '")
              << fromLayer << "." << outputName << "' (to input '" << param.getName()
              << "' of layer '" << l.name
              << "') is not supported: connect the whole array to an array input";
          ok = false;
          return;
        }
        if (!out) {
          param.emitError("layer '") << fromLayer << "' has no output '" << fromOutput
                                     << "' (connected to input '" << param.getName()
                                     << "' of layer '" << l.name << "')";
          ok = false;
          return;
        }
        Type outType = out.getValue().getType();
        if (component >= 0 && isTriple(getUniformType(outType)))
          outType = withUniformity(Float32Type::get(param.getContext()), isVarying(outType));
        else if (component >= 0)
          outType = Type(); // a component of a non-triple: not connectable
        if (!outType || !connectable(outType, param.getType())) {
          param.emitError("cannot connect output '")
              << fromLayer << "." << fromOutput << "' ("
              << typeName(out.getValue().getType()) << ") to input '" << l.name << "."
              << param.getName() << "' (" << typeName(param.getType()) << ")";
          ok = false;
        }
      });
    }
    return success(ok);
  }

  LogicalResult checkRequestedOutputs() {
    if (explicitEntries)
      for (auto &name : requestedOutputs)
        if (!name.getKey().contains('.'))
          lastWriterOutput(name.getKey());
    llvm::StringSet<> written;
    std::string names;
    for (const std::string &name : available)
      if (written.insert(name).second)
        names += " " + name;
    for (auto &name : requestedOutputs)
      if (!written.contains(name.getKey()) && !zeroUnrunOutput(name.getKey()))
        return group.emitError("the group has no output '")
               << name.getKey() << "' (for another layer's, write LAYER.NAME); outputs:"
               << names;
    return success();
  }

  /// With entries named, an output asked for by its name alone is what the
  /// last entry that writes an output of that name left (testshade's
  /// renderer output takes every layer's, the last run last), the root's
  /// only where it is that entry.
  void lastWriterOutput(StringRef name) {
    for (Layer *l : llvm::reverse(ranInOrder)) {
      SmallVector<OutputOp> outs = outputsNamed(l->func, name);
      if (outs.empty())
        continue;
      if (l == &layers.back())
        return; // the root's outputs keep the name
      for (OutputOp out : outputsNamed(group, name))
        out.erase();
      for (OutputOp out : outs)
        writeGroupOutput(out, name, placed[l->name].lookup(outputKey(name, elementIndex(out))));
      available.push_back(name.str());
      return;
    }
  }

  /// Prints OSL's llvm_debug_layers line `what` for layer `l` at `b`:
  /// "(SHADER LAYER) WHAT layer INDEX LAYER SHADER".
  void trace(OpBuilder &b, Layer &l, StringRef what) {
    if (!traceLayers)
      return;
    auto shaderAttr = l.func->getAttrOfType<StringAttr>("osl.layer_shader");
    std::string shader = shaderAttr ? shaderAttr.getValue().str() : l.name.str();
    std::string text = "(" + shader + " " + l.name.str() + ") " + what.str() + " layer " +
                       std::to_string(layerIndex.lookup(l.name)) + " " + l.name.str() + " " +
                       shader + "\n";
    std::string format;
    for (char c : text)
      format += c == '%' ? std::string("%%") : std::string(1, c);
    Location loc = l.func.getLoc();
    // Tagged as the layer's code: lazily placed layers find their place
    // among the layers placed before them by these tags.
    StringAttr tag = b.getStringAttr(l.name);
    Value handle = b.create<StringConstantOp>(loc, b.getI32Type(), format);
    handle.getDefiningOp()->setAttr(kFromLayerAttr, tag);
    b.create<PrintOp>(loc, "printf", "s", ValueRange{handle}, Value())
        ->setAttr(kFromLayerAttr, tag);
  }

  /// Whether the group asks for one of `l`'s outputs as "layer.output".
  bool keepsAskedOutput(Layer &l) {
    bool asked = false;
    l.func.walk([&](OutputOp out) {
      asked |= requestedOutputs.contains((l.name + "." + out.getName()).str());
    });
    return asked;
  }

  /// With entries named, a layer none of them runs leaves its outputs as
  /// OSL leaves them: zeros (testshade writes 0 for such a layer's output,
  /// not its default). False when `name` is no such numeric output.
  bool zeroUnrunOutput(StringRef name) {
    if (!explicitEntries)
      return false;
    auto [layerName, output] = name.rsplit('.');
    if (output.empty()) // the root's own name
      std::tie(layerName, output) = std::make_pair(layers.back().name, name);
    auto it = layerIndex.find(layerName);
    if (it == layerIndex.end())
      return false;
    SmallVector<OutputOp> outs = outputsNamed(layers[it->second].func, output);
    OpBuilder b(group.front().getTerminator());
    for (OutputOp out : outs) {
      Type type = getUniformType(out.getValue().getType());
      if (!isa<FloatType, IntegerType, VectorType>(type))
        return false;
      writeGroupOutput(out, name,
                       b.create<arith::ConstantOp>(out.getLoc(),
                                                   cast<TypedAttr>(b.getZeroAttr(type))));
    }
    return !outs.empty();
  }

  /// As OSL: an output connects to an input of its type, an int output to a
  /// float input, and a float to a triple (converted).
  static bool connectable(Type output, Type input) {
    Type from = getUniformType(output), to = getUniformType(input);
    return from == to || (from.isInteger(32) && to.isF32()) ||
           ((from.isF32() || from.isInteger(32)) && isTriple(to));
  }

  /// The connected param reads `output` of a layer's `outputs` (OUT[k]: its
  /// component k), converted to the param's type.
  static void replaceConnected(ParamOp param, const llvm::StringMap<Value> &outputs,
                               StringRef output) {
    auto [name, component] = splitComponentName(output);
    Value value = outputs.lookup(outputKey(name, elementIndex(param)));
    OpBuilder b(param.getContext());
    b.setInsertionPointAfterValue(value);
    if (component >= 0)
      value = b.create<ExtractOp>(
          param.getLoc(), withUniformity(b.getF32Type(), isVarying(value.getType())), value,
          b.getI64IntegerAttr(component));
    Type to = getUniformType(param.getType());
    if (getUniformType(value.getType()) != to)
      value = b.create<ConvertOp>(param.getLoc(),
                                  withUniformity(to, isVarying(value.getType())), value);
    SmallVector<Operation *> users(param->getUsers());
    param.replaceAllUsesWith(value);
    param.erase();
    for (Operation *user : users)
      retypeParamDefault(user);
    // A varying output feeding a parameter typed uniform: the ops reading
    // it follow (osl.deriv's type is its value's).
    makeDataUsersVarying(value);
  }

  /// A parameter whose default is another parameter (`output S b = a`)
  /// takes the type of what now feeds it (a varying output, say).
  static void retypeParamDefault(Operation *op) {
    auto param = dyn_cast<ParamOp>(op);
    if (!param || param.getType() == param.getDefaultValue().getType())
      return;
    param.getResult().setType(param.getDefaultValue().getType());
    for (Operation *user : param->getUsers())
      retypeParamDefault(user);
  }

  static OutputOp findOutput(func::FuncOp f, StringRef name,
                             std::optional<int64_t> element = std::nullopt) {
    OutputOp found;
    f.walk([&](OutputOp out) {
      if (out.getName() == name && elementIndex(out) == element)
        found = out;
    });
    return found;
  }

  /// An array parameter or output is one op per element, each with its
  /// `index`.
  static std::optional<int64_t> elementIndex(Operation *op) {
    if (auto param = dyn_cast<ParamOp>(op))
      return param.getIndex();
    if (auto output = dyn_cast<OutputOp>(op))
      return output.getIndex();
    return std::nullopt;
  }

  /// The element count of the array input or output `name` of `f`; 0 when
  /// it is not an array.
  static int64_t arrayLength(func::FuncOp f, StringRef name, bool outputs) {
    int64_t length = 0;
    f.walk([&](Operation *op) {
      StringRef opName;
      if (auto out = dyn_cast<OutputOp>(op); out && outputs)
        opName = out.getName();
      else if (auto param = dyn_cast<ParamOp>(op); param && !outputs)
        opName = param.getName();
      if (opName == name && elementIndex(op))
        length = std::max(length, *elementIndex(op) + 1);
    });
    return length;
  }

  static std::string describeLength(int64_t length) {
    return length ? "an array of " + std::to_string(length) : "not an array";
  }

  /// How an inlined layer's outputs are found: by name, and an array's
  /// elements by name and index.
  static std::string outputKey(StringRef name, std::optional<int64_t> element) {
    return element ? (name + "#" + std::to_string(*element)).str() : name.str();
  }

  /// Clones layer `l` at `b`; returns its outputs' final values. Entry
  /// layers keep the outputs the group asks for. Without lazy globals, a
  /// layer placed at the top level (`inOrder`) starts from the Ci the
  /// layers before it left and leaves its own to those after it; a layer
  /// placed where it is read writes no Ci (else it would not be lazy).
  llvm::StringMap<Value> inlineLayer(Layer &l, OpBuilder &b, bool inOrder) {
    // The group's root, run as the whole group, is entered before the
    // layers it runs first (its enter line is placed at the group's start).
    bool rootOfGroup = !explicitEntries && &l == &layers.back();
    // OSL checks whether a named entry layer ran already (the root, the
    // group's own entry, excepted); other layers run where first read.
    if (explicitEntries && l.func->hasAttr("osl.entry_named") && &l != &layers.back())
      trace(b, l, "checking for already-run");
    if (!rootOfGroup)
      trace(b, l, "enter");
    IRMapping map;
    llvm::StringMap<Value> outputs;
    SmallVector<ParamOp> reads;
    StringAttr tag = b.getStringAttr(l.name);
    for (Operation &op : l.func.front().without_terminator()) {
      // Ci as the layers placed before left it (the front end marks the
      // value a shader's Ci starts with).
      auto empty = dyn_cast<ClosureEmptyOp>(op);
      if (empty && empty.getInitialCi() && currentCi && !lazyGlobals && inOrder) {
        map.map(op.getResult(0), currentCi);
        continue;
      }
      Operation *copy = b.clone(op, map);
      copy->walk([&](Operation *inner) { inner->setAttr(kFromLayerAttr, tag); });
      if (auto param = dyn_cast<ParamOp>(copy); param && connection(param))
        reads.push_back(param);
      auto out = dyn_cast<OutputOp>(copy);
      if (!out)
        continue;
      outputs[outputKey(out.getName(), elementIndex(out))] = out.getValue();
      if (out.getName() == "Ci" && inOrder)
        currentCi = out.getValue();
      std::string groupName = &l == &layers.back()
                                  ? out.getName().str()
                                  : (l.name + "." + out.getName()).str();
      // Unspecialised (not lazy), every output is written, so every layer
      // really runs, as in OSL at -O0. With entries named, an output asked
      // for is what its layer left, wherever it ran.
      bool asked = requestedOutputs.contains(groupName);
      if (l.entry || !lazyLayers || (explicitEntries && asked))
        available.push_back(groupName);
      bool keep = !lazyLayers || (l.entry && (keepAllOutputs || asked)) || (explicitEntries && asked);
      if (!keep)
        out.erase();
      else
        out.setName(groupName);
    }
    trace(b, l, "exit");
    // Reads of layers already at the top level are resolved now; the rest
    // wait until their layer is placed.
    for (ParamOp param : reads) {
      auto [fromLayer, fromOutput] = *connection(param);
      auto it = placed.find(fromLayer);
      if (it == placed.end())
        continue;
      replaceConnected(param, it->second, fromOutput);
    }
    return outputs;
  }

  /// `l` as OSL's optimizer sees it (FoldedLayer): a copy with its
  /// unconnected parameters bound to their values (per-geometry ones
  /// excepted: they may change per point), folded once and kept.
  const FoldedLayer &folded(Layer &l) {
    if (l.folded)
      return *l.folded;
    OpBuilder b(l.func);
    auto copy = cast<func::FuncOp>(b.clone(*l.func));
    copy.setSymName((l.func.getSymName() + ".folded").str());
    copy.walk([&](ParamOp param) {
      // (Unspecialised, -O0: nothing is known of a parameter's value.)
      if (connection(param) || param.getUserdata() || opaqueParams)
        return;
      param.replaceAllUsesWith(param.getDefaultValue());
      param.erase();
    });
    OpPassManager fold(func::FuncOp::getOperationName());
    fold.addPass(createFoldConstants());
    fold.addPass(createCanonicalizerPass());
    // Not folded: the layer as written, in which nothing counts as constant.
    bool foldedOk = succeeded(runPipeline(fold, copy));
    func::FuncOp seen = foldedOk ? copy : l.func;
    FoldedLayer facts;
    for (Operation &op : seen.front().without_terminator())
      if (auto out = dyn_cast<OutputOp>(op)) {
        std::string key = outputKey(out.getName(), elementIndex(out));
        auto constant = out.getValue().getDefiningOp<arith::ConstantOp>();
        if (constant && foldedOk)
          facts.constantOutputs[key] = constant.getValue();
        else
          facts.constantOutputs.erase(key);
      }
    seen.walk([&](OutputOp out) {
      auto initial = out.getValue().getDefiningOp<ClosureEmptyOp>();
      facts.writesCi |= out.getName() == "Ci" && !(initial && initial.getInitialCi());
    });
    seen.walk([&](PrintOp print) { facts.callsError |= print.isErrorCall(); });
    copy.erase();
    l.folded = std::move(facts);
    return *l.folded;
  }

  /// Where the code of a layer `first` reads at `readAt` goes: before
  /// `first`, but before the layers placed there earlier (the op tagged with
  /// their names just before it) that `first` reads later.
  Operation *insertionPoint(Operation *first, std::pair<int64_t, int64_t> readAt) {
    // The earlier layers' code, grouped by layer, in order.
    SmallVector<std::pair<StringAttr, SmallVector<Operation *>>> run;
    for (Operation *p = first->getPrevNode(); p; p = p->getPrevNode()) {
      auto tag = p->getAttrOfType<StringAttr>(kFromLayerAttr);
      if (!tag || !placedLazily.contains(tag.getValue()))
        break;
      if (run.empty() || run.back().first != tag)
        run.push_back({tag, {}});
      run.back().second.push_back(p);
    }
    Operation *insertAt = first;
    for (auto &[tag, ops] : run) { // nearest first
      SmallVector<Value> values;
      for (Operation *op : ops)
        llvm::append_range(values, op->getResults());
      if (firstReadWithin(first, values) <= readAt)
        break; // read before this layer: its code, and the earlier, stay first
      insertAt = ops.back(); // the layer's first op
    }
    return insertAt;
  }

  /// Where `op` (with what it holds, in order) first reads one of `values`:
  /// (the reading op's place in a pre-order walk, the operand).
  static std::pair<int64_t, int64_t> firstReadWithin(Operation *op, ArrayRef<Value> read) {
    llvm::SmallPtrSet<Value, 8> values(read.begin(), read.end());
    std::pair<int64_t, int64_t> found{INT64_MAX, INT64_MAX};
    int64_t index = 0;
    op->walk<WalkOrder::PreOrder>([&](Operation *inner) {
      for (OpOperand &use : inner->getOpOperands())
        if (values.contains(use.get())) {
          found = {index, int64_t(use.getOperandNumber())};
          return WalkResult::interrupt();
        }
      ++index;
      return WalkResult::advance();
    });
    return found;
  }

  /// Inlines `l` before the first op that needs one of its outputs, outside
  /// any loop, or nowhere if nothing reads it. A read of a constant output
  /// takes the constant instead.
  void placeLazily(Layer &l) {
    SmallVector<ParamOp> connected, reads;
    group.walk([&](ParamOp param) {
      if (auto from = connection(param); from && from->first == l.name)
        connected.push_back(param);
    });
    for (ParamOp param : connected) {
      StringRef output = connection(param)->second;
      std::string key = outputKey(splitComponentName(output).first, elementIndex(param));
      // (Folded only when something reads the layer.)
      const llvm::StringMap<TypedAttr> &constants = folded(l).constantOutputs;
      auto constant = constants.find(key);
      if (constant == constants.end()) {
        reads.push_back(param);
        continue;
      }
      OpBuilder b(param);
      llvm::StringMap<Value> constantValue;
      constantValue[key] = b.create<arith::ConstantOp>(param.getLoc(), constant->second);
      replaceConnected(param, constantValue, output);
    }
    SmallVector<Operation *> users;
    for (ParamOp param : reads)
      users.append(param->user_begin(), param->user_end());
    if (users.empty()) {
      for (ParamOp param : reads)
        param.erase();
      // An entry no earlier entry needed after all still runs, as OSL's
      // execute_layer runs it, after them.
      if (l.entry) {
        OpBuilder b(group.front().getTerminator());
        placed[l.name] = inlineLayer(l, b, /*inOrder=*/true);
      }
      return;
    }
    // The innermost block enclosing every read, and the first read in it.
    Block *block = users.front()->getBlock();
    for (Operation *user : users)
      while (!block->findAncestorOpInBlock(*user))
        block = block->getParentOp()->getBlock();
    Operation *first = nullptr;
    for (Operation *user : users) {
      Operation *ancestor = block->findAncestorOpInBlock(*user);
      if (!first || ancestor->isBeforeInBlock(first))
        first = ancestor;
    }
    // Inside a loop the layer would run once per iteration: hoist it out.
    // An entry runs for every point (where a reader does not run it, OSL's
    // execute_layer does): it goes out of ifs too, and so does a layer whose
    // output is asked for beside named entries (the output is kept).
    bool everyPoint = l.entry || (explicitEntries && keepsAskedOutput(l));
    for (Operation *p = first->getParentOp(); p != group; p = p->getParentOp())
      if (!isa<IfOp>(p) || everyPoint)
        first = p;
    // Layers placed before the same op run in the order the op reads them
    // (`a + b` runs a's layer, then b's), as OSL runs a layer at the first
    // read of its output; they are placed last first, so a later-placed
    // layer may belong before an earlier one.
    SmallVector<Value> mine;
    for (ParamOp param : reads)
      mine.push_back(param.getResult());
    OpBuilder b(insertionPoint(first, firstReadWithin(first, mine)));
    llvm::StringMap<Value> outputs = inlineLayer(l, b, /*inOrder=*/false);
    placedLazily.insert(l.name);
    for (ParamOp param : reads)
      replaceConnected(param, outputs, connection(param)->second);
  }

  /// Unspecialised parameters: the value lives in a writable global that
  /// the optimizer cannot see through, as a renderer's instance data would.
  void makeParamsOpaque() {
    ModuleOp module = getOperation();
    SmallVector<ParamOp> params;
    group.walk([&](ParamOp p) {
      if (opaqueParams || p.getUserdata())
        params.push_back(p);
    });
    for (ParamOp param : params) {
      auto constant = param.getDefaultValue().getDefiningOp<arith::ConstantOp>();
      if (!constant)
        continue; // a default computed per point is no instance value
      std::string symbol = "osl_param." +
                           param->getAttrOfType<StringAttr>(kFromLayerAttr).getValue().str() +
                           "." + param.getName().str();
      if (std::optional<int64_t> index = param.getIndex())
        symbol += "." + std::to_string(*index);
      OpBuilder b(module.getContext());
      b.setInsertionPointToStart(module.getBody());
      Type type = getUniformType(param.getType());
      auto global = b.create<LLVM::GlobalOp>(param.getLoc(), type, /*isConstant=*/false,
                                             LLVM::Linkage::External, symbol,
                                             constant.getValue(), /*alignment=*/16);
      b.setInsertionPoint(param);
      Value address = b.create<LLVM::AddressOfOp>(param.getLoc(), global);
      Operation *load = b.create<LLVM::LoadOp>(param.getLoc(), type, address);
      load->setAttr(kNoDerivativeAttr, b.getUnitAttr());
      Value value = load->getResult(0);
      if (isVarying(param.getType()))
        value = b.create<BroadcastOp>(param.getLoc(), param.getType(), value);
      param.replaceAllUsesWith(value);
      param.erase();
    }
  }

  SmallVector<Layer> layers;
  llvm::StringMap<size_t> layerIndex;
  llvm::StringMap<llvm::StringMap<Value>> placed;
  /// The layers placed where they are first read (their ops are tagged).
  llvm::StringSet<> placedLazily;
  /// Whether upstream layers are placed where they are read: the `lazy`
  /// option, or named entries (at every level).
  bool lazyLayers = true;
  /// The layers placed at the top level, in the order they run.
  SmallVector<Layer *> ranInOrder;
  /// Ci as the last layer placed that assigns it left it.
  Value currentCi;
  /// The group names its entry layers (else the root is its one entry).
  bool explicitEntries = false;
  llvm::StringSet<> requestedOutputs;
  llvm::StringSet<> reportedArrays;
  /// Outputs of the layers that run unconditionally, as the group names them.
  std::vector<std::string> available;
  bool keepAllOutputs = true;
  func::FuncOp group;
};

} // namespace
