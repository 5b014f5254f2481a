// Gmsh MSH writers: version 4.1 ASCII (default) and legacy 2.2 ASCII, with one physical line
// group per boundary curve (named after the curve) and one physical surface "domain", or with
// regional attributes (Mesh::region) one physical surface "region_<attribute>" per attribute.
#pragma once
#include <string>

#include "mesh/mesh.hpp"

namespace pdmesh {

// Physical tags: curve c -> c + 1; "domain" -> number of curves + 1, or the j-th attribute in ascending
// order -> number of curves + 1 + j (surface entity j + 1). Node tags are point index + 1.
std::string msh41_string(const Mesh& mesh);
std::string msh22_string(const Mesh& mesh);

}  // namespace pdmesh
