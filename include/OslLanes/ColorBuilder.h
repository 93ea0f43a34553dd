//===- ColorBuilder.h - OSL's color functions on lane values ----*- C++ -*-===//
//
// transformc, blackbody, wavelength_color and luminance as arith ops on
// lane values (see LaneMath.h), under a working RGB color space such as
// Rec709 or ACEScg: OSL's ColorSystem, with its constants, algorithms and
// edge behaviour.
//
//===----------------------------------------------------------------------===//
#ifndef OSLLANES_COLORBUILDER_H
#define OSLLANES_COLORBUILDER_H

#include "mlir/IR/Builders.h"
#include "mlir/Support/LogicalResult.h"

#include <array>
#include <mutex>
#include <string>
#include <vector>

namespace mlir::osl {

/// A working RGB space: its XYZ matrices (for row vectors, c' = c * M),
/// its luminance weights and blackbody's temperature table.
struct ColorSystem {
  std::string name;
  std::array<float, 9> xyzToRgb;
  std::array<float, 9> rgbToXyz;
  std::array<float, 3> luminance;
  /// blackbody's table, one list per channel: the color at temperature
  /// T_i = 2 i^1.5 + 800, clamped at 0 and raised to 1/5. Made on first use
  /// (about 1 ms, which every compile paid when the front end checked the
  /// working space's name).
  const std::array<std::vector<float>, 3> &blackbodyTable() const;

  /// The color system named `name` (OSL's: Rec709, sRGB, NTSC, EBU, PAL,
  /// SECAM, SMPTE, HDTV, CIE, AdobeRGB, XYZ, ACES2065-1, ACEScg), or null.
  static const ColorSystem *get(StringRef name);

private:
  mutable std::once_flag blackbodyOnce;
  mutable std::array<std::vector<float>, 3> blackbody;
};

/// The names transformc knows under the working space `working`.
bool isColorSpaceName(StringRef space, StringRef working);

using LaneColor = std::array<Value, 3>;

/// transformc(from, to, c); fails for a space name it does not know.
FailureOr<LaneColor> buildTransformc(OpBuilder &b, Location loc,
                                     const ColorSystem &cs, StringRef from,
                                     StringRef to, LaneColor c);
LaneColor buildBlackbody(OpBuilder &b, Location loc, const ColorSystem &cs,
                         Value kelvin);
LaneColor buildWavelengthColor(OpBuilder &b, Location loc,
                               const ColorSystem &cs, Value nanometers);
Value buildLuminance(OpBuilder &b, Location loc, const ColorSystem &cs,
                     LaneColor c);

} // namespace mlir::osl

#endif // OSLLANES_COLORBUILDER_H
