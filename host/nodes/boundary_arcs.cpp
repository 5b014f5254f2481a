// Arc positions of the boundary nodes (see boundary_arcs.hpp).
#include "nodes/boundary_arcs.hpp"

#include <fmt/format.h>

#include "core/errors.hpp"
#include "geometry/curve_projection.hpp"

namespace pdmesh {

std::vector<std::vector<double>> boundary_arcs(const Geometry& geometry, const NodeSet& nodes,
                                               std::vector<Vec2>* tangents) {
  if (nodes.curve_nodes.size() != geometry.curves.size())
    throw SimulationError(fmt::format("the node set has boundary node lists for {} curves, the geometry has {}",
                                      nodes.curve_nodes.size(), geometry.curves.size()));
  std::vector<std::vector<double>> all(geometry.curves.size());
  for (std::size_t c = 0; c < geometry.curves.size(); ++c) {
    const Curve& curve = geometry.curves[c];
    const std::vector<int>& list = nodes.curve_nodes[c];
    if (list.size() < 2)
      throw SimulationError(fmt::format("curve {} ('{}') has {} boundary nodes; it needs its two end points", c,
                                        curve.name, list.size()));
    std::vector<double>& arcs = all[c];
    arcs.assign(list.size(), 0.0);
    arcs.back() = curve.length();
    for (std::size_t k = 1; k + 1 < list.size(); ++k) {
      const auto node = static_cast<std::size_t>(list[k]);
      const CurvePoint cp = closest_on_curve_range(curve, nodes.x[node], arcs[k - 1], curve.length());
      arcs[k] = cp.arc;
      if (tangents && nodes.kind[node] == NodeKind::Boundary) (*tangents)[node] = cp.tangent;
    }
  }
  return all;
}

}  // namespace pdmesh
