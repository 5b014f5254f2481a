// The faces of a planar straight line graph (vertices joined by non-crossing segments): the
// connected regions the segments cut the plane into. Triangle's .poly semantics rest on them: a
// face is a hole when a hole point lies in it, outside when it is the unbounded face, and a
// segment bounds the domain when exactly one of its sides is in it (geometry/poly_reader.cpp).
#pragma once
#include <array>
#include <vector>

#include "core/vec2.hpp"

namespace pdmesh {

struct PlanarFaces {
  // Per edge: the face on the left of a -> b (side 0) and on its right (side 1); -1 is the
  // unbounded face. Both sides are the same face for an edge no cycle passes through (a dangling
  // chain or a tree).
  std::vector<std::array<int, 2>> sides;
  // Per bounded face: the vertex indices of its outer boundary, counter-clockwise, and the area it
  // encloses (the face's own area plus that of whatever lies inside it).
  std::vector<std::vector<int>> outer;
  std::vector<double> outer_area;
  std::vector<Box> outer_box;  // bounding box of each outer boundary, to skip the tests of far faces
};

// The faces of the graph. Edges are vertex index pairs (a != b); the caller guarantees that no two
// edges cross or overlap and no vertex lies inside an edge, and that vertices are distinct points.
PlanarFaces planar_faces(const std::vector<Vec2>& vertices, const std::vector<std::array<int, 2>>& edges);

// The bounded face containing p (the innermost outer boundary around it), -1 for the unbounded
// face, -2 when p lies on an edge (exact tests).
int locate_face(const PlanarFaces& faces, const std::vector<Vec2>& vertices,
                const std::vector<std::array<int, 2>>& edges, Vec2 p);

}  // namespace pdmesh
