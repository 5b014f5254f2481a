// Reader for Triangle's .poly PSLG files: vertices, segments with boundary markers, hole points and
// regional attributes, read with Triangle's semantics (docs/geometry-input.md, "Triangle .poly").
#pragma once
#include <string>
#include <vector>

#include "geometry/geometry.hpp"

namespace pdmesh {

struct PolyFile {
  // Boundary curves first (segments with the domain on one side, in the order of their markers'
  // first appearance; the convex hull's own edges last, named "hull"), then the constraints
  // (segments with the domain on both sides: RawCurve::constraint).
  std::vector<RawCurve> curves;
  std::vector<RawHolePoint> holes;
  std::vector<RawPoint> points;         // isolated vertices inside the domain
  std::vector<GeometryRegion> regions;  // regional attributes whose point lies in the domain
  std::vector<std::string> notes;       // what differs from the plain reading, one line each, for stderr
};

// The domain is what the segments enclose (with the convex hull when `hull` says so) less the faces
// that hold a hole point; a segment with the domain on one side is a boundary, on both sides a
// constraint, on neither side dropped (noted). Segments become curves: a curve is a maximal chain
// of segments of one kind and one boundary marker, broken at vertices where other than two of them
// meet or where any other segment meets them; a cycle is a closed curve. Isolated vertices inside
// the domain become points, others are dropped (noted). Throws InputError naming FILE:LINE and the
// offending text (see docs/geometry-input.md).
PolyFile read_poly_file(const std::string& path, PolyHull hull = PolyHull::Automatic);

}  // namespace pdmesh
