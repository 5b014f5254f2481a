// SU2 native mesh format (ASCII) reader: type 5 triangles, NMARK markers as curves.
#pragma once
#include <filesystem>
#include <string>

#include "io/mesh_io_common.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// Reads NDIME= 2 files; markers become curves (named by MARKER_TAG), their type 3 lines boundary
// edges; other element types are skipped and counted. Throws InputError naming FILE:LINE.
Mesh parse_su2(const std::string& file_label, std::string content, MeshReadReport& report);
Mesh read_su2(const std::filesystem::path& path, MeshReadReport& report);

}  // namespace pdmesh
