// VTK XML UnstructuredGrid (.vtu) ASCII reader: points, triangle cells, the node kind and the
// boundary edges / curve names that our writer stores as FieldData.
#pragma once
#include <filesystem>
#include <string>

#include "io/mesh_io_common.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// Cells other than triangles (type 5) are skipped and counted. Binary, appended or compressed
// data arrays are rejected with an InputError naming FILE:LINE.
Mesh parse_vtu(const std::string& file_label, const std::string& content, MeshReadReport& report);
Mesh read_vtu(const std::filesystem::path& path, MeshReadReport& report);

}  // namespace pdmesh
