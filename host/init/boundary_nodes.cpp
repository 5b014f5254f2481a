// Boundary nodes of the initial distribution (thesis ch. 4, "Boundary Nodes"): one Fixed node per
// critical location, the other stations of each curve (by default its geometry points, duplicated)
// as Boundary nodes, curve_nodes in order.
#include <map>
#include <utility>

#include "core/errors.hpp"
#include "fmt/format.h"
#include "init/boundary_placement.hpp"
#include "init/initial_distribution.hpp"

namespace pdmesh {

NodeSet assemble_boundary_nodes(const Geometry& geometry, const SpacingField& spacing, const CurveStations& stations) {
  NodeSet nodes;
  const std::size_t curve_count = geometry.curves.size();
  if (stations.size() != curve_count)
    throw GeometryError(fmt::format("boundary nodes: {} station lists for {} curves", stations.size(), curve_count));
  // node_of[c][i]: the node for point i of curve c, -1 until assigned.
  std::vector<std::vector<int>> node_of(curve_count);
  for (std::size_t c = 0; c < curve_count; ++c) node_of[c].assign(geometry.curves[c].points.size(), -1);
  // Fixed nodes by exact location, so that a location is never given two Fixed nodes.
  std::map<std::pair<double, double>, int> fixed_at;

  auto fixed_node = [&](Vec2 p, int curve) {
    const auto key = std::make_pair(p.x, p.y);
    const auto found = fixed_at.find(key);
    if (found != fixed_at.end()) return found->second;
    const int id = nodes.add(p, spacing.at(p), NodeKind::Fixed, curve);
    fixed_at.emplace(key, id);
    return id;
  };

  // 1. The critical points, in Geometry::critical order: each is one node shared by its curves.
  for (const CriticalPoint& cp : geometry.critical) {
    const int id = fixed_node(cp.p, cp.curves.empty() ? -1 : cp.curves.front());
    for (std::size_t k = 0; k < cp.curves.size() && k < cp.indices.size(); ++k) {
      const int c = cp.curves[k], i = cp.indices[k];
      if (c >= 0 && static_cast<std::size_t>(c) < curve_count && i >= 0 &&
          static_cast<std::size_t>(i) < node_of[c].size())
        node_of[c][i] = id;
    }
  }

  // 2. Walk each curve's stations from its first point to its last. Curve end points and points
  // flagged critical are Fixed even if Geometry::critical missed them (the curve_nodes contract needs
  // Fixed ends); a closed curve's last point is its first point's node.
  nodes.curve_nodes.resize(curve_count);
  for (std::size_t c = 0; c < curve_count; ++c) {
    const Curve& curve = geometry.curves[c];
    const std::size_t n = curve.points.size();
    const std::vector<BoundaryStation>& list_in = stations[c];
    if (list_in.size() < 2 || list_in.front().vertex != 0 || list_in.back().vertex != static_cast<int>(n) - 1)
      throw GeometryError(
          fmt::format("boundary nodes: curve {} ('{}') stations do not run from its first point to "
                      "its last",
                      c, curve.name));
    std::vector<int>& list = nodes.curve_nodes[c];
    list.reserve(list_in.size());
    for (const BoundaryStation& s : list_in) {
      if (s.vertex < 0) {
        list.push_back(nodes.add(s.p, spacing.at(s.p), NodeKind::Boundary, static_cast<int>(c)));
        continue;
      }
      const auto i = static_cast<std::size_t>(s.vertex);
      int& id = node_of[c][i];
      if (id < 0) {
        const Vec2 p = curve.points[i];
        const bool is_end = (i == 0 || i + 1 == n);
        const bool flagged = i < curve.critical.size() && curve.critical[i] != 0;
        if (is_end || flagged) {
          id = fixed_node(p, static_cast<int>(c));
        } else {
          id = nodes.add(p, spacing.at(p), NodeKind::Boundary, static_cast<int>(c));
        }
      }
      list.push_back(id);
    }
    if (curve.constraint) {
      nodes.constraint_curves.resize(curve_count, 0);
      nodes.constraint_curves[c] = 1;
    }
  }
  // 3. The embedded points (Geometry::embedded_points): Fixed nodes on no curve.
  for (const RawPoint& p : geometry.embedded_points) fixed_node(p.p, -1);
  return nodes;
}

CurveStations vertex_stations(const Geometry& geometry, const std::vector<std::vector<int>>* vertices) {
  CurveStations stations(geometry.curves.size());
  for (std::size_t c = 0; c < geometry.curves.size(); ++c) {
    const Curve& curve = geometry.curves[c];
    if (vertices == nullptr) {
      for (std::size_t i = 0; i < curve.points.size(); ++i)
        stations[c].push_back({curve.points[i], static_cast<int>(i), curve.arc[i]});
      continue;
    }
    for (const int i : (*vertices)[c])
      stations[c].push_back({curve.points[static_cast<std::size_t>(i)], i, curve.arc[static_cast<std::size_t>(i)]});
  }
  return stations;
}

NodeSet make_boundary_nodes(const Geometry& geometry, const SpacingField& spacing) {
  return assemble_boundary_nodes(geometry, spacing, vertex_stations(geometry));
}

}  // namespace pdmesh
