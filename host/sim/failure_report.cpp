// The neighbourhood of a failing node, for SimulationError messages; see failure_report.hpp.
#include "sim/failure_report.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <fmt/format.h>

namespace pdmesh {

std::string describe_neighbourhood(const NodeSet& nodes, std::size_t node, double radius, std::size_t max_listed) {
  if (node >= nodes.size()) return fmt::format("node {} (not in the node set of {})", node, nodes.size());
  const Vec2 p = nodes.x[node];
  std::string out = fmt::format("node {} ({}) at ({:.17g}, {:.17g}), spacing {:.6g}", node, to_string(nodes.kind[node]),
                                p.x, p.y, nodes.q[node]);
  std::vector<std::pair<double, std::size_t>> near;
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    if (j == node) continue;
    const double d = std::hypot(nodes.x[j].x - p.x, nodes.x[j].y - p.y);
    if (d <= radius) near.emplace_back(d, j);
  }
  if (near.empty()) return out + fmt::format("; no other node within {:.6g}", radius);
  std::sort(near.begin(), near.end());
  out += fmt::format("; within {:.6g}:", radius);
  for (std::size_t k = 0; k < near.size() && k < max_listed; ++k) {
    const std::size_t j = near[k].second;
    out += fmt::format("{} node {} ({}) at ({:.17g}, {:.17g}) distance {:.6g}", k ? "," : "", j,
                       to_string(nodes.kind[j]), nodes.x[j].x, nodes.x[j].y, near[k].first);
  }
  if (near.size() > max_listed) out += fmt::format(" ({} more)", near.size() - max_listed);
  return out;
}

}  // namespace pdmesh
