// The boundary of a mesh as node strings, one per curve, for the formats that describe boundaries by
// node lists (ADCIRC fort.14, SMS .2dm): each string runs with the domain on its left, a closed curve
// repeats its first node last, and each string knows whether it lies on the outer boundary or around
// a hole (an island).
#pragma once
#include <vector>

#include "mesh/mesh.hpp"

namespace pdmesh {

struct BoundaryString {
  int curve = 0;           // index into Mesh::curve_names
  std::vector<int> nodes;  // point indices, the domain on the left
  bool closed = false;     // first node == last node
  bool internal = false;   // around a hole: the boundary loop it lies on runs clockwise
};

// The strings of every curve's boundary edges, in curve order (a curve whose edges do not form one
// chain gives one string per chain). Edges with a triangle on both sides (an embedded constraint) are
// not boundary and are left out; so is a curve with no boundary edge.
std::vector<BoundaryString> boundary_strings(const Mesh& mesh);

}  // namespace pdmesh
