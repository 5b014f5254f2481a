// Boundary conformity: recovery of constrained edges by flips (Sloan's method), constrained
// Delaunay restoration, and removal of the triangles outside the domain by parity flood fill.
#pragma once
#include <array>
#include <cstdint>
#include <unordered_set>
#include <vector>

#include "mesh/delaunay.hpp"

namespace pdmesh {

struct ConstrainedEdge {
  int a = 0, b = 0;  // point indices
  int curve = -1;    // for messages only; -1 when not from a curve
};

// Makes every edge a-b an edge of the triangulation and marks it constrained, then flips the
// other edges until the triangulation is constrained Delaunay.
// Throws GeometryError when an edge has equal end points, when a point lies in the interior of
// an edge, or when two edges cross (messages name the edges, the points and their coordinates).
void recover_edges(Triangulation& tri, const std::vector<ConstrainedEdge>& edges);

// The triangles inside the domain bounded by the constrained edges: a triangle is inside when
// an odd number of constrained edges separates it from the super-triangle (even-odd rule,
// so holes and islands in holes come out right). Constrained edges whose key
// (Triangulation::edge_key of the input point indices) is in `open_edges` (embedded constraints)
// bound nothing: the fill passes them. Consumes the triangulation: its arrays are freed and its
// triangle list becomes the result.
std::vector<std::array<int, 3>> inside_triangles(Triangulation&& tri,
                                                 const std::unordered_set<std::uint64_t>& open_edges = {});

}  // namespace pdmesh
