// Triangle (Shewchuk) file writer: .node (points), .ele (triangles) and .poly (boundary
// segments with marker = curve index + 1; curve names in "# pdmesh curve" comment lines).
#pragma once
#include <string>

#include "mesh/mesh.hpp"

namespace pdmesh {

struct TriangleFiles {
  std::string node, ele, poly;
};

// Indices are 1-based. When the mesh knows node kinds, the .node file carries them as its one
// attribute (announced by a "# pdmesh: attribute 1 = node kind" comment). The node boundary
// marker is 1 for points on a boundary edge, else 0. The .ele file carries Mesh::region, when set,
// as each triangle's one attribute.
TriangleFiles triangle_strings(const Mesh& mesh);

}  // namespace pdmesh
