// Triangle's semantics for a parsed .poly file (internal to poly_reader.cpp): which faces of the
// segments' planar graph are the domain, which segments bound it and which are constraints inside
// it, which isolated vertices and regional attributes lie in it, and the convex hull (-c).
#pragma once
#include <string>
#include <vector>

#include "geometry/poly_reader.hpp"

namespace pdmesh::detail {

struct PolyVertex {
  Vec2 p;
  int line = 0;
};

struct PolySegment {
  int a = 0, b = 0;  // 0-based vertex indices
  long long marker = 0;
  int line = 0;
};

// Fills result.curves, .points, .regions and .notes from the parsed sections (result.holes and
// `regions` as read). `base` is the file's first index (0 or 1), for messages.
void apply_poly_semantics(const std::string& path, int base, const std::vector<PolyVertex>& vertices,
                          const std::vector<PolySegment>& segments, const std::vector<GeometryRegion>& regions,
                          PolyHull hull, PolyFile& result);

}  // namespace pdmesh::detail
