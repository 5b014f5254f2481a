// The points of a warm start (case key init.file, Python's generate(initial=...)): the node positions
// of a pdmesh node file or the points of a mesh file, to become a run's initial interior nodes
// (init/metric_fill.hpp, warm_fill).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "core/vec2.hpp"

namespace pdmesh {

// The points of `path`: a node file (.nodes, docs/node-file.md) or a mesh read by extension (.msh,
// .vtu, .su2, .mesh, .ele/.node; io/mesh_formats.hpp). Throws InputError naming the file on a missing or
// malformed file, a file without points, or a non-finite coordinate (with its index and value).
std::vector<Vec2> read_warm_points(const std::filesystem::path& path);

// The extensions read_warm_points reads (lower case, with the dot).
bool is_warm_points_extension(const std::string& extension);

}  // namespace pdmesh
