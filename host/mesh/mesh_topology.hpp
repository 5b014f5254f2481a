// The first place where a triangle mesh read from a file is not a mesh pdmesh can measure: two
// triangles folded over each other, or an edge shared by more than two triangles.
#pragma once
#include <optional>
#include <string>

#include "mesh/mesh.hpp"

namespace pdmesh {

// `mesh` has counter-clockwise triangles (the readers turn clockwise ones). Returns a message
// naming the triangles (0-based, in file order), the edge and its coordinates for the conflict
// whose later triangle comes first in the file:
//  - two triangles use an edge in the same direction, so they lie on the same side of it: one is
//    folded over the other (a triangle that was inverted in the file, or overlapping triangles);
//  - more than two triangles use an edge: the mesh is not a manifold there.
// Nothing when every edge has one triangle (a boundary edge) or two on opposite sides.
std::optional<std::string> find_fold_or_nonmanifold_edge(const Mesh& mesh);

}  // namespace pdmesh
