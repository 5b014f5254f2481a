// SU2 native mesh format (ASCII) reader: type 5 triangles (and on request type 9 quadrilaterals),
// NMARK markers as curves.
#pragma once
#include <filesystem>
#include <string>

#include "io/mesh_io_common.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// Reads NDIME= 2 files; markers become curves (named by MARKER_TAG), their type 3 lines boundary
// edges; other element types are skipped and counted. With `cells`, quadrilaterals (type 9) are read
// too instead of skipped (io/mesh_io_common.hpp SurfaceCells); SU2 has no volume markers, so no cell
// is in cells->region and region_found stays false. Throws InputError naming FILE:LINE.
Mesh parse_su2(const std::string& file_label, std::string content, MeshReadReport& report,
               SurfaceCells* cells = nullptr);
Mesh read_su2(const std::filesystem::path& path, MeshReadReport& report, SurfaceCells* cells = nullptr);

}  // namespace pdmesh
