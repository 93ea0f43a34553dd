//===- GroupAssembly.cpp - Building a group as testshade reports it -------===//
#include "GroupAssembly.h"

#include "OslFrontend/Frontend.h"

#include "llvm/ADT/StringMap.h"
#include "llvm/ADT/StringSet.h"
#include "llvm/Support/FileSystem.h"
#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/Path.h"

using namespace osl;

namespace {

class GroupAssembler {
public:
  GroupAssembler(RunOptions &options, llvm::raw_ostream &out, llvm::raw_ostream &errs)
      : options(options), group(options.group), out(out), errs(errs),
        groupName(groupNameOrDefault(options.compile.groupName)) {}

  bool run() {
    // testshade reports a shader it cannot find and builds the group
    // without it; the parameter values given for it go to the next shader.
    std::vector<ParamOverride> carried;
    llvm::erase_if(group.layers, [&](GroupLayer &l) {
      if (llvm::sys::fs::is_regular_file(l.shaderPath)) {
        l.params.insert(l.params.begin(), carried.begin(), carried.end());
        carried.clear();
        return false;
      }
      carried.insert(carried.end(), l.params.begin(), l.params.end());
      std::string name =
          l.shaderName.empty() ? llvm::sys::path::stem(l.shaderPath).str() : l.shaderName;
      error("No .oso file could be found for shader \"" + name + "\"", false);
      error("Could not find shader \"" + name + "\"");
      missing.insert(l.name);
      return true;
    });
    llvm::erase_if(options.groupBeforeReparams.layers,
                   [&](const GroupLayer &l) { return missing.contains(l.name); });

    // testshade stops at the first connection it refuses.
    for (const GroupConnection &c : group.connections) {
      if (c.statement.empty())
        out << "Connect " << c.fromLayer << "." << c.fromOutput << " to " << c.toLayer << "."
            << c.toInput << "\n";
      if (!connectable(c)) {
        if (!c.statement.empty()) {
          error("ShaderGroupBegin: error parsing group description: ");
          errs << "        problem might be here: " << c.statement << ";\n\n";
          error("Invalid shader group. Exiting testshade.", false);
        }
        return false;
      }
    }
    if (!group.entries.empty()) {
      llvm::raw_string_ostream line(options.entryLayersLine);
      line << "Entry layers:";
      for (const std::string &e : group.entries)
        line << " " << e << "(" << layerIndex(e) << ")";
      line << "\n";
      // testshade's line comes after the group, or, when it reports images,
      // after its blank line, with them (osl-run.cpp).
      if (options.outputs.empty())
        out << options.entryLayersLine;
    }
    return !group.layers.empty();
  }

private:
  bool connectable(const GroupConnection &c) {
    const GroupLayer *from = findPresent(c.fromLayer), *to = findPresent(c.toLayer);
    if (!from) {
      error("ConnectShaders: source layer \"" + c.fromLayer + "\" not found");
      return false;
    }
    if (!to) {
      error("ConnectShaders: destination layer \"" + c.toLayer + "\" not found");
      return false;
    }
    // "c[1]" and "s.f" belong to parameters c and s.
    llvm::StringRef input = llvm::StringRef(c.toInput).split('[').first;
    for (const std::string &p : unconnectable(*to))
      if (input == p || input.starts_with(p + ".")) {
        error("ConnectShaders: cannot connect to " + c.toLayer + "." + c.toInput +
              " because it has metadata allowconnect=0");
        return false;
      }
    return true;
  }

  size_t layerIndex(const std::string &layer) const {
    const GroupLayer *l = group.findLayer(layer);
    return l ? size_t(l - group.layers.data()) : group.layers.size();
  }

  const GroupLayer *findPresent(const std::string &layer) const {
    return missing.count(layer) ? nullptr : group.findLayer(layer);
  }

  /// The layer's parameters with allowconnect=0; none when its source does
  /// not parse (compiling it reports why).
  const std::vector<std::string> &unconnectable(const GroupLayer &l) {
    auto [it, inserted] = refusing.try_emplace(l.name);
    if (!inserted)
      return it->second;
    auto source = llvm::MemoryBuffer::getFile(l.shaderPath, /*IsText=*/true);
    if (!source)
      return it->second;
    std::string ignored;
    llvm::raw_string_ostream quiet(ignored);
    if (auto names = unconnectableParams((*source)->getBuffer(), l.shaderPath, quiet,
                                         options.compile.includePaths,
                                         options.compile.defines))
      it->second = std::move(*names);
    return it->second;
  }

  /// testshade's error lines: "ERROR: what", then the group it was building.
  void error(const std::string &what, bool namesGroup = true) {
    out.flush();
    errs << "ERROR: " << what << "\n";
    if (namesGroup)
      errs << "        group: " << groupName << "\n";
    errs.flush();
  }

  RunOptions &options;
  ShaderGroup &group;
  llvm::raw_ostream &out, &errs;
  std::string groupName;
  llvm::StringSet<> missing;
  llvm::StringMap<std::vector<std::string>> refusing;
};

} // namespace

bool osl::assembleGroup(RunOptions &options, llvm::raw_ostream &out,
                        llvm::raw_ostream &errs) {
  bool ok = GroupAssembler(options, out, errs).run();
  out.flush();
  return ok;
}
