// Reader for .crv/.dat curve files: blocks of a point-count line followed by that many `x y [z]` lines.
#pragma once
#include <string>
#include <vector>

#include "geometry/geometry.hpp"

namespace pdmesh {

// One RawCurve per block, unnamed, with the source line of every point. z is checked and ignored.
// Throws InputError naming FILE:LINE and the offending text (see docs/geometry-input.md).
std::vector<RawCurve> read_curve_file(const std::string& path);

}  // namespace pdmesh
