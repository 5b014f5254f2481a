// VTK XML UnstructuredGrid (.vtu) reader: points, triangle cells, the node kind, the triangles'
// region (cell data "region") and the boundary edges / curve names that our writer stores as
// FieldData, and on request point-data arrays and the quads (SurfaceCells).
#pragma once
#include <filesystem>
#include <string>

#include "io/mesh_io_common.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// Cells other than triangles (type 5) are skipped and counted. Data arrays may be ascii, binary
// (base64) or appended (raw or base64), uncompressed or zlib-compressed. With `data`, the point-data
// array data->wanted is decoded into data->array, those data->decodes() into data->arrays, and every
// array's name is listed. With
// `cells`, quads (VTK_QUAD 9) are read too instead of skipped (io/mesh_io_common.hpp SurfaceCells:
// the region is the cell-data array of that name, as mixed_vtu_string writes it, 0 or 1 per cell).
// Throws InputError naming FILE:LINE on malformed or unsupported content.
Mesh parse_vtu(const std::string& file_label, const std::string& content, MeshReadReport& report,
               MeshPointData* data = nullptr, SurfaceCells* cells = nullptr);
Mesh read_vtu(const std::filesystem::path& path, MeshReadReport& report, MeshPointData* data = nullptr,
              SurfaceCells* cells = nullptr);

}  // namespace pdmesh
