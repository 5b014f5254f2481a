// Reader for Triangle's .poly PSLG files: vertices, segments with boundary markers, hole points.
#pragma once
#include <string>
#include <vector>

#include "geometry/geometry.hpp"

namespace pdmesh {

struct PolyFile {
  std::vector<RawCurve> curves;
  std::vector<RawHolePoint> holes;
};

// Segments become curves: a curve is a maximal chain of segments with one boundary marker, broken
// at vertices where that marker's segments meet in other than two; a cycle is a closed curve.
// Throws InputError naming FILE:LINE and the offending text (see docs/geometry-input.md).
PolyFile read_poly_file(const std::string& path);

}  // namespace pdmesh
