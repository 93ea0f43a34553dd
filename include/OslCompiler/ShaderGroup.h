//===- ShaderGroup.h - Layers of shader instances and their wiring -*- C++ -*-===//
//
// A shader group as testshade and renderers build it: layers (a shader with
// instance parameter values), connections from an upstream layer's output
// to a downstream layer's input, and the entry layers that run
// unconditionally (by default the last layer, the root). The whole group
// compiles to one kernel (ShaderCompiler::compileGroup).
//
//===----------------------------------------------------------------------===//
#ifndef OSLCOMPILER_SHADERGROUP_H
#define OSLCOMPILER_SHADERGROUP_H

#include "OslFrontend/Frontend.h"

#include <string>
#include <vector>

namespace osl {

struct GroupLayer {
  /// The shader's file (its source is read when the group compiles).
  std::string shaderPath;
  /// The shader as the user named it, for messages ("" if as shaderPath).
  std::string shaderName;
  std::string name;
  std::vector<ParamOverride> params;
  /// Parameters declared with lockgeom=0: per-geometry data, never folded.
  std::vector<std::string> userdata;
};

struct GroupConnection {
  std::string fromLayer, fromOutput, toLayer, toInput;
  /// The group statement that made it ("connect a.b c.d"); empty for
  /// testshade's --connect, whose connections are reported as made.
  std::string statement = "";
};

/// How much render-time specialisation a group gets (testshade's -O).
enum class GroupOptimization {
  O0, // parameters are loads, every layer runs
  O1, // parameters are constants, every layer runs
  O2, // also: upstream layers run lazily, unread layers and outputs vanish
};

struct ShaderGroup {
  std::vector<GroupLayer> layers;

  /// Makes the layers of `entryOutputs` the entries where testshade runs
  /// them instead of the entry layers; false (with `error`) for an output
  /// of no layer of the group.
  bool useEntryOutputs(std::string &error);
  std::vector<GroupConnection> connections;
  /// Layers that run unconditionally; empty: the last layer.
  std::vector<std::string> entries;
  /// testshade's --entryoutput: "layer.name" outputs whose layers run
  /// in this order in place of `entries` (useEntryOutputs says when).
  std::vector<std::string> entryOutputs;
  /// No layer runs (entry outputs of no entry layer): outputs stay 0.
  bool runsNoLayer = false;
  /// The entry layers as named, where entry outputs replaced them: OSL
  /// still checks whether these ran (llvm_debug_layers shows it).
  std::vector<std::string> namedEntries;
  /// The outputs the caller reads: "name" for the root layer's,
  /// "layer.name" for another layer's. Empty: every output of the entries.
  std::vector<std::string> outputs;
  GroupOptimization optimization = GroupOptimization::O2;
  /// OSL's lazyglobals option: false runs layers that assign Ci in order,
  /// and the later layers see that Ci.
  bool lazyGlobals = true;
  /// OSL's llvm_debug_layers option: each layer prints where it is
  /// entered and left.
  bool traceLayers = false;

  /// Parameter values waiting for the next `shader` statement.
  std::vector<ParamOverride> pendingParams;
  std::vector<std::string> pendingUserdata;

  /// testshade's statements, one call each: `--param` then `--shader`.
  void param(std::string name, std::string value, bool userdata = false);
  bool shader(std::string shaderPath, std::string layerName, std::string &error);
  /// Records a connection; its layers are checked when the group is
  /// assembled or validated.
  void connect(GroupConnection c) { connections.push_back(std::move(c)); }
  /// Changes an instance value of a built group (testshade's --reparam);
  /// compile again to re-specialise.
  bool reparam(const std::string &layer, const std::string &name, std::string value,
               std::string &error);

  /// testshade's group syntax (`--group`): `param TYPE NAME VALUE... ;`
  /// (optionally followed by `[[int lockgeom=0]]`), `shader NAME LAYER ;`,
  /// `connect FROMLAYER.OUTPUT TOLAYER.INPUT ;` (a comma may end a
  /// statement instead of `;`, as in OSL's group strings). Shader names without a
  /// directory or extension are looked up as `DIR/NAME.osl`.
  bool parseStatements(const std::string &text, const std::string &shaderDir,
                       std::string &error);

  /// Everything the group needs before it compiles: layers exist, params
  /// were all used, connections point backwards. Messages name the layer.
  bool validate(std::string &error) const;

  const GroupLayer *findLayer(const std::string &name) const;
};

/// "layer.name" -> (layer, name) at the last dot (layer names hold no
/// dots); false when either side is empty.
bool splitLayerDotName(const std::string &s, std::string &layer, std::string &name);

} // namespace osl

#endif // OSLCOMPILER_SHADERGROUP_H
