// Checks that a parsed checkpoint describes a state the simulation can continue on this geometry:
// the same curves, node lists that start and end at Fixed nodes, every Boundary node in exactly its
// own curve's list, increasing arc positions, every node within the geometry's extents (checkpoint.hpp).
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "sim/checkpoint.hpp"

namespace pdmesh {

void check_checkpoint_fits(const Checkpoint& c, const GeometryTree& tree, const std::string& source) {
  const Geometry& geometry = tree.geometry();
  const NodeSet& nodes = c.nodes;
  const SimState& s = c.state;
  const auto fail = [&](const std::string& what) {
    throw InputError(fmt::format("{}: the checkpoint does not fit the case's geometry: {}", source, what));
  };
  const std::size_t n = nodes.size();
  if (nodes.curve_nodes.size() != geometry.curves.size())
    fail(fmt::format("it has node lists for {} curves, the geometry has {}", nodes.curve_nodes.size(),
                     geometry.curves.size()));
  if (!(s.dt_initial > 0.0) || !(s.time_step.dt > 0.0) || (s.time_step.previous && !(*s.time_step.previous >= 0.0)))
    fail(fmt::format("the time step state (dt_initial {}, dt {}) is not positive", s.dt_initial, s.time_step.dt));
  for (std::size_t r = 0; r < s.history.size(); ++r)
    if (s.history[r].iteration != static_cast<int>(r) + 1)
      fail(fmt::format("history row {} is iteration {}", r + 1, s.history[r].iteration));
  // Every node within the geometry's extents (a margin for the rounding of snapped positions), so
  // that a stray coordinate cannot blow up the neighbour grid.
  const Box& e = geometry.extents;
  const double margin = 1e-6 * std::hypot(e.hi.x - e.lo.x, e.hi.y - e.lo.y);
  std::vector<int> listed(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 p = nodes.x[i];
    if (!(nodes.q[i] > 0.0)) fail(fmt::format("node {} has spacing {}", i, nodes.q[i]));
    if (p.x < e.lo.x - margin || p.x > e.hi.x + margin || p.y < e.lo.y - margin || p.y > e.hi.y + margin)
      fail(fmt::format("node {} at ({}, {}) is outside the geometry's extents", i, p.x, p.y));
    const Vec2 t = s.tangents[i];
    if (std::hypot(t.x, t.y) > 1.0 + 1e-9)
      fail(fmt::format("node {} has a tangent ({}, {}) longer than 1", i, t.x, t.y));
    const int curve = nodes.curve[i];
    const bool interior = nodes.kind[i] == NodeKind::Interior;
    if (interior ? curve != -1 : (curve < 0 || static_cast<std::size_t>(curve) >= geometry.curves.size()))
      fail(fmt::format("node {} ({}) names curve {}", i, to_string(nodes.kind[i]), curve));
  }
  if (s.arcs.size() != geometry.curves.size()) fail(fmt::format("it has arc positions for {} curves", s.arcs.size()));
  for (std::size_t k = 0; k < geometry.curves.size(); ++k) {
    const Curve& curve = geometry.curves[k];
    const std::vector<int>& list = nodes.curve_nodes[k];
    const std::vector<double>& arcs = s.arcs[k];
    if (list.size() < 2 || arcs.size() != list.size())
      fail(fmt::format("curve {} ('{}') has {} nodes and {} arc positions", k, curve.name, list.size(), arcs.size()));
    for (std::size_t j = 0; j < list.size(); ++j) {
      const auto node = static_cast<std::size_t>(list[j]);
      const NodeKind kind = nodes.kind[node];
      const bool end = j == 0 || j + 1 == list.size();
      if (end ? kind != NodeKind::Fixed : kind == NodeKind::Interior)
        fail(fmt::format("curve {} ('{}') lists node {} ({}) at position {}", k, curve.name, node, to_string(kind), j));
      if (kind == NodeKind::Boundary) {
        if (nodes.curve[node] != static_cast<int>(k))
          fail(fmt::format("boundary node {} of curve {} is listed on curve {}", node, nodes.curve[node], k));
        ++listed[node];
      }
      // Arc positions run from 0 to the curve's length, strictly increasing: neighbours never meet.
      if (j == 0 ? arcs[j] != 0.0 : !(arcs[j] > arcs[j - 1]))
        fail(fmt::format("curve {} ('{}') arc position {} is {} after {}", k, curve.name, j, arcs[j],
                         j == 0 ? 0.0 : arcs[j - 1]));
    }
    if (arcs.back() != curve.length())
      fail(fmt::format("curve {} ('{}') ends at arc position {}, its length is {}", k, curve.name, arcs.back(),
                       curve.length()));
  }
  for (std::size_t i = 0; i < n; ++i)
    if (nodes.kind[i] == NodeKind::Boundary && listed[i] != 1)
      fail(fmt::format("boundary node {} is listed {} times on its curve {}", i, listed[i], nodes.curve[i]));
}

}  // namespace pdmesh
