// A mesh file with point data (.vtu or .msh) read with the names of its point arrays: the solution
// that pdmesh transfer carries over and pdmesh adapt (and pdmesh.adapt) adapts to.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "io/mesh_io_common.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// The mesh of a .vtu or .msh file with point array `data.wanted` (when the file has it) and the names
// of all; with `cells`, its quads too. InputError for another file type.
Mesh read_mesh_with_point_data(const std::filesystem::path& path, MeshPointData& data, SurfaceCells* cells = nullptr);

// The names of the point arrays of `path` (a .vtu or .msh; InputError for another file).
std::vector<std::string> point_array_names(const std::string& path);

}  // namespace pdmesh
