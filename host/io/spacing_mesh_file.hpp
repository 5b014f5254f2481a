// Reading a spacing field given on a background triangle mesh (spacing.field = "mesh"): the file's
// mesh and point-data array, handed to spacing/mesh_spacing's MeshSpacing, which checks and evaluates it.
#pragma once
#include <filesystem>
#include <memory>
#include <string>

#include "spacing/mesh_spacing.hpp"

namespace pdmesh {

// Reads FILE (.vtu or .msh by extension) and builds the field from its point-data array `array`
// (a VTU PointData array, or the MSH $NodeData view of that name). Throws InputError naming the file
// when it cannot be read, has no such array (listing the arrays it has), or the array is not one
// scalar per point; then every check of MeshSpacing.
std::unique_ptr<MeshSpacing> load_mesh_spacing(const std::filesystem::path& file, const std::string& array);

}  // namespace pdmesh
