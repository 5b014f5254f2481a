// The points of a warm start; see warm_points.hpp.
#include "init/warm_points.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <system_error>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "io/mesh_formats.hpp"
#include "nodes/node_file.hpp"

namespace pdmesh {

bool is_warm_points_extension(const std::string& extension) {
  // .meshb is taken so that read_mesh refuses it with the binary Medit file's own message.
  return extension == ".nodes" || extension == ".msh" || extension == ".vtu" || extension == ".su2" ||
         extension == ".mesh" || extension == ".meshb" || extension == ".ele" || extension == ".node";
}

std::vector<Vec2> read_warm_points(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(fmt::format("init.file '{}': no such file", path.string()));
  const std::string ext = lower_extension(path);
  std::vector<Vec2> points;
  if (ext == ".nodes") {
    points = read_node_file(path).nodes.x;
  } else if (is_warm_points_extension(ext)) {
    points = read_mesh(path).points;
  } else {
    throw InputError(fmt::format("init.file '{}': not a .nodes, .msh, .vtu, .su2, .mesh or .ele file", path.string()));
  }
  if (points.empty()) throw InputError(fmt::format("init.file '{}': the file has no points", path.string()));
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!std::isfinite(points[i].x) || !std::isfinite(points[i].y))
      throw InputError(
          fmt::format("init.file '{}': point {} is ({}, {}), not finite", path.string(), i, points[i].x, points[i].y));
  return points;
}

}  // namespace pdmesh
