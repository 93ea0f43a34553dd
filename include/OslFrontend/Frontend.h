//===- Frontend.h - OSL source to the osl dialect ---------------*- C++ -*-===//
//
// The front end parses one OSL source file (functions and one shader) and
// emits a module holding `func.func @<shader>()` in the osl dialect.
// Variables become SSA values, user functions are inlined, and string
// values are compile-time constants.
//
//===----------------------------------------------------------------------===//
#ifndef OSLFRONTEND_FRONTEND_H
#define OSLFRONTEND_FRONTEND_H

#include "OslLanes/NamedSpaces.h"

#include "mlir/IR/BuiltinOps.h"
#include "mlir/IR/MLIRContext.h"
#include "mlir/IR/OwningOpRef.h"
#include "llvm/ADT/ArrayRef.h"
#include "llvm/ADT/StringRef.h"
#include "llvm/Support/raw_ostream.h"

#include <optional>
#include <string>
#include <vector>

namespace osl {

/// The OSL release whose behaviour the project reproduces (1.13.12): the
/// preprocessor's OSL_VERSION_* and getattribute("osl:version").
constexpr int kOslVersionMajor = 1, kOslVersionMinor = 13, kOslVersionPatch = 12;
constexpr int kOslVersion = kOslVersionMajor * 10000 + kOslVersionMinor * 100 + kOslVersionPatch;

/// An instance value for a shader parameter, testshade style: "0.5", "3",
/// "0.1,0.2,0.3" for a triple (one number is repeated), comma-separated
/// lists for arrays, or the text itself for a string parameter.
struct ParamOverride {
  std::string name;
  std::string value;
};

/// Per-geometry data the renderer has on every point (testshade's
/// --userdata:type=TYPE NAME VALUE): getattribute(NAME) finds it and a
/// lockgeom=0 parameter NAME of a matching type takes it. `value` is the
/// text as given: comma-separated numbers, or the string.
struct UserDatum {
  std::string name;
  std::string type; // int, float, color, point, vector, normal or string
  std::string value;
};

/// What the front end takes besides the source: where #include looks, the
/// renderer it compiles for, and how warnings are reported.
struct FrontendOptions {
  /// Searched by #include after the including file's directory.
  std::vector<std::string> includePaths;
  /// The image size that fixes the "screen", "NDC" and "raster" spaces.
  mlir::osl::CameraImage camera;
  /// The working RGB space of the color functions (OSL's "colorspace").
  std::string colorSpace = "Rec709";
  /// oslc's -D and -U, in order (see preprocess()).
  std::vector<std::string> defines;
  /// The ray being shaded: raytype() is 1 for it.
  std::string rayType = "camera";
  std::vector<UserDatum> userData;
  /// The names getattribute("shader:layername") and "shader:groupname"
  /// answer (testshade's --layer and --groupname).
  std::string layerName;
  std::string groupName;
  /// The layer's position in its group (in OSL's index-range reports).
  int layerIndex = 0;
  /// Warnings as oslc prints them (`filename:line: warning: message`),
  /// hidden, or errors (oslc's -Werror).
  bool warningsAsErrors = false;
  bool showWarnings = true;
  /// testshade's --debugnan: report where a value stored into a variable
  /// has a NaN or infinite component (DebugNan.cpp).
  bool debugNan = false;
  /// A layer of a group: what it leaves in the globals it assigns is marked
  /// (osl.set_global), as the layers that run after it read those values.
  bool groupLayer = false;
  /// What isconnected() answers: this layer's inputs an upstream layer's
  /// output feeds, and its outputs a downstream layer or the renderer reads
  /// (names, with ".field" for a struct's field); with
  /// userdataIsConnected (testshade's --userdata_isconnected), a lockgeom=0
  /// parameter counts as connected, to the geometry.
  std::vector<std::string> connectedInputs;
  std::vector<std::string> connectedOutputs;
  bool userdataIsConnected = false;
  /// Inputs connected to an array output, with its length: an unsized
  /// array input (`float a[]`) takes it.
  std::vector<std::pair<std::string, int>> connectedArrayLengths;
  /// Parameters given lockgeom=0 on the command line (testshade's
  /// --param:lockgeom=0): per-geometry data as [[int lockgeom = 0]] makes
  /// them (testshade's renderer data, such as "t", comes first).
  std::vector<std::string> perGeometryParams;
};

/// A group's name as testshade gives it: `given` (--groupname), or
/// unnamed_group_1 when it has none.
inline std::string groupNameOrDefault(const std::string &given) {
  return given.empty() ? "unnamed_group_1" : given;
}

/// Parses `source` (named `filename` in diagnostics) and returns a module
/// with the shader, or null after printing diagnostics to `errs` as
/// `filename:line:col: error: message`. Loads the osl, func and arith
/// dialects into `context` if they are not loaded yet.
mlir::OwningOpRef<mlir::ModuleOp>
parseOslShader(llvm::StringRef source, llvm::StringRef filename,
               mlir::MLIRContext &context,
               llvm::ArrayRef<ParamOverride> overrides, llvm::raw_ostream &errs,
               const FrontendOptions &options = {});

/// Everything the front end reads of a shader as one string: its tokens
/// after preprocessing (#includes expanded, macros applied), each with its
/// file name and position (positions end up in run-time error messages).
/// Sources with equal fingerprints compile alike under equal options, so
/// this keys the kernel cache. Empty if the source does not preprocess;
/// compiling it then reports why.
std::string preprocessedFingerprint(llvm::StringRef source, llvm::StringRef filename,
                                    llvm::ArrayRef<std::string> includePaths = {},
                                    llvm::ArrayRef<std::string> defines = {});

/// The shader's interface as `oslinfo -v` prints it: its type and name,
/// each parameter's name, type and default value, and the metadata of
/// both. Null after printing diagnostics to `errs`.
std::optional<std::string> shaderInfoText(llvm::StringRef source, llvm::StringRef filename,
                                          llvm::raw_ostream &errs,
                                          llvm::ArrayRef<std::string> includePaths = {},
                                          llvm::ArrayRef<std::string> defines = {});

/// The shader's interface as JSON, for tools that query it as OSL's
/// OSLQuery does (python/oslquery.py): {"shadertype", "shadername",
/// "metadata", "params"}, each parameter with its name, type, flags, value
/// and metadata, and a struct parameter followed by its fields. Null after
/// printing diagnostics to `errs`.
std::optional<std::string> shaderQueryJson(llvm::StringRef source, llvm::StringRef filename,
                                           llvm::raw_ostream &errs,
                                           llvm::ArrayRef<std::string> includePaths = {},
                                           llvm::ArrayRef<std::string> defines = {});

/// A shader parameter as a renderer's query lists it: its name, its type as
/// OSL writes it ("color", "float[3]") and whether it is an output.
struct ShaderParamInfo {
  std::string name, type;
  bool isOutput = false;
  /// False with [[int allowconnect = 0]].
  bool connectable = true;
};

/// A string as OSL writes it in source and in serialized groups: quoted,
/// with its escapes.
std::string quotedOslString(llvm::StringRef s);

/// The parameters of the shader `source` declares, in order, read without
/// compiling it. Null after printing diagnostics to `errs`.
std::optional<std::vector<ShaderParamInfo>>
shaderParams(llvm::StringRef source, llvm::StringRef filename, llvm::raw_ostream &errs,
             llvm::ArrayRef<std::string> includePaths = {},
             llvm::ArrayRef<std::string> defines = {});

/// The parameters of a shader that refuse connections
/// ([[int allowconnect = 0]]), read from its source without compiling it,
/// so that a group builder can refuse a connection when it is made. Null
/// after printing diagnostics to `errs`.
std::optional<std::vector<std::string>>
unconnectableParams(llvm::StringRef source, llvm::StringRef filename, llvm::raw_ostream &errs,
                    llvm::ArrayRef<std::string> includePaths = {},
                    llvm::ArrayRef<std::string> defines = {});

/// A file a shader's source #includes (`standard`: one of osl-mlir's own
/// standard headers, oslutil.h and the like).
struct IncludedFile {
  std::string path;
  bool standard = false;
};

/// The files `source` #includes, directly or not, each once in the order
/// first included, as make's dependencies (oslc -M) list them. Null after
/// printing diagnostics to `errs`.
std::optional<std::vector<IncludedFile>>
includedFiles(llvm::StringRef source, llvm::StringRef filename, llvm::raw_ostream &errs,
              llvm::ArrayRef<std::string> includePaths = {},
              llvm::ArrayRef<std::string> defines = {});

/// The source of shader `name` among `dirs`: NAME.osl, else the first .osl
/// file (in name order) that declares a shader of that name, as oslc names
/// its output after the shader (ShaderSearch.cpp). Empty if there is none.
std::string findShaderSource(llvm::StringRef name, llvm::ArrayRef<std::string> dirs);

} // namespace osl

#endif // OSLFRONTEND_FRONTEND_H
