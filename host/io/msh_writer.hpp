// Gmsh MSH writers: version 4.1 ASCII (default) and legacy 2.2 ASCII, with one physical line
// group per boundary curve (named after the curve) and one physical surface "domain".
#pragma once
#include <string>

#include "mesh/mesh.hpp"

namespace pdmesh {

// Physical tags: curve c -> c + 1; "domain" -> number of curves + 1. Node tags are point index + 1.
std::string msh41_string(const Mesh& mesh);
std::string msh22_string(const Mesh& mesh);

}  // namespace pdmesh
