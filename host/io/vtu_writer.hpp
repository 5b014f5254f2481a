// VTK XML UnstructuredGrid (.vtu, ASCII) writer: triangles with per-triangle quality metrics as
// CellData, the node kind as PointData, and the boundary edges and curve names as FieldData.
#pragma once
#include <string>

#include "mesh/mesh.hpp"

namespace pdmesh {

// Non-finite metric values (degenerate triangles) are written as 1e300 because VTK's ASCII
// parser does not read "inf". Kind is -1 for every point when the mesh does not know it.
std::string vtu_string(const Mesh& mesh);

}  // namespace pdmesh
