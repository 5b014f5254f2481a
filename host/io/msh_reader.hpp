// Gmsh MSH reader (ASCII 4.1 and 2.2, detected from $MeshFormat): nodes, 2-node lines as
// boundary edges grouped into curves by physical group, and 3-node triangles.
#pragma once
#include <filesystem>
#include <string>

#include "io/mesh_io_common.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// Curves: the dimension-1 physical groups in tag order (named from $PhysicalNames, else
// "physical<tag>"), then lines without a physical group per elementary entity ("entity<tag>").
// Other element types are skipped and counted in `report`. Throws InputError "FILE:LINE: ..."
// on truncation, bad counts, unknown node tags, binary files and unsupported versions.
Mesh parse_msh(const std::string& file_label, std::string content, MeshReadReport& report);
Mesh read_msh(const std::filesystem::path& path, MeshReadReport& report);

}  // namespace pdmesh
