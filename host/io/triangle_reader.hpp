// Triangle (Shewchuk) file reader: STEM.ele with STEM.node, and STEM.poly when present for the
// boundary segments (curves by segment marker, named from "# pdmesh curve" comments); the .ele's first
// triangle attribute is the triangle's region.
#pragma once
#include <filesystem>
#include <string>

#include "io/mesh_io_common.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// `ele_path` names the .ele file. Indices may start at 0 or 1 (the first node decides).
// 6-node triangles keep their corners. Throws InputError naming FILE:LINE.
Mesh read_triangle(const std::filesystem::path& ele_path, MeshReadReport& report);

// The same from file contents; `poly` may be empty (no boundary).
Mesh parse_triangle(const std::string& node_label, std::string node, const std::string& ele_label, std::string ele,
                    const std::string& poly_label, std::string poly, MeshReadReport& report);

}  // namespace pdmesh
