// Boundary handling after each move: re-snapping boundary nodes within their allowed arc range
// and snapping escaped interior nodes onto the closest curve (see boundary_handling.hpp).
#include "sim/boundary_handling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "nodes/boundary_arcs.hpp"

namespace pdmesh {
BoundaryHandler::BoundaryHandler(const GeometryTree& tree, const NodeSet& nodes) : tree_(tree) {
  tangent_.assign(nodes.size(), Vec2{});
  budget_.assign(nodes.size(), 0.0);
  arcs_ = boundary_arcs(tree.geometry(), nodes, &tangent_);
}

void BoundaryHandler::restore(const NodeSet& nodes, std::vector<std::vector<double>> arcs, std::vector<Vec2> tangents) {
  if (tangents.size() != nodes.size())
    throw InputError(fmt::format("saved boundary state has {} tangents for {} nodes", tangents.size(), nodes.size()));
  if (arcs.size() != nodes.curve_nodes.size())
    throw InputError(fmt::format("saved boundary state has arc positions for {} curves, the node set has {}",
                                 arcs.size(), nodes.curve_nodes.size()));
  for (std::size_t c = 0; c < arcs.size(); ++c)
    if (arcs[c].size() != nodes.curve_nodes[c].size())
      throw InputError(fmt::format("saved boundary state has {} arc positions on curve {}, the node set {} nodes",
                                   arcs[c].size(), c, nodes.curve_nodes[c].size()));
  arcs_ = std::move(arcs);
  tangent_ = std::move(tangents);
}

void BoundaryHandler::curve_neighbours(const NodeSet& nodes, std::vector<int>& prev, std::vector<int>& next) const {
  prev.assign(nodes.size(), -1);
  next.assign(nodes.size(), -1);
  for (const std::vector<int>& list : nodes.curve_nodes) {
    for (std::size_t k = 1; k + 1 < list.size(); ++k) {
      const auto node = static_cast<std::size_t>(list[k]);
      if (nodes.kind[node] != NodeKind::Boundary) continue;
      prev[node] = list[k - 1];
      next[node] = list[k + 1];
    }
  }
}

BoundaryCounts BoundaryHandler::apply(NodeSet& nodes, const std::vector<double>& dx, const std::vector<double>& dy) {
  BoundaryCounts counts;
  move_boundary_nodes(nodes, dx, dy, counts);
  // 2. Interior nodes, in index order (snapped nodes change curve_nodes for the ones after them).
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes.kind[i] == NodeKind::Interior) move_interior_node(nodes, i, {dx[i], dy[i]}, counts);
  return counts;
}

BoundaryCounts BoundaryHandler::apply_subset(NodeSet& nodes, const std::vector<double>& dx,
                                             const std::vector<double>& dy, const std::vector<int>& interior) {
  BoundaryCounts counts;
  move_boundary_nodes(nodes, dx, dy, counts);
  std::vector<Vec2> moves(interior.size());
  for (std::size_t k = 0; k < interior.size(); ++k) {
    const auto i = static_cast<std::size_t>(interior[k]);
    moves[k] = {dx[i], dy[i]};
  }
  const BoundaryCounts inner = apply_interior(nodes, interior, moves, {});
  counts.snapped = inner.snapped;
  return counts;
}

BoundaryCounts BoundaryHandler::apply_interior(NodeSet& nodes, const std::vector<int>& interior,
                                               const std::vector<Vec2>& moves,
                                               const std::function<void()>& before_snap) {
  BoundaryCounts counts;
  for (std::size_t k = 0; k < interior.size(); ++k) {
    const auto i = static_cast<std::size_t>(interior[k]);
    // The device moved this node since the host last saw it: the host's budget no longer holds.
    budget_[i] = 0.0;
    if (nodes.kind[i] == NodeKind::Interior) move_interior_node(nodes, i, moves[k], counts, &before_snap);
  }
  return counts;
}

void BoundaryHandler::move_boundary_nodes(NodeSet& nodes, const std::vector<double>& dx, const std::vector<double>& dy,
                                          BoundaryCounts& counts) {
  const Geometry& geometry = tree_.geometry();
  tangent_.resize(nodes.size());
  // 1. Boundary nodes: every new arc position from the old ones (Jacobi), then commit.
  for (std::size_t c = 0; c < geometry.curves.size(); ++c) {
    const Curve& curve = geometry.curves[c];
    const std::vector<int>& list = nodes.curve_nodes[c];
    std::vector<double>& arcs = arcs_[c];
    const std::vector<double> old_arcs = arcs;
    for (std::size_t k = 1; k + 1 < list.size(); ++k) {
      const auto node = static_cast<std::size_t>(list[k]);
      if (nodes.kind[node] != NodeKind::Boundary) continue;
      const double lo = old_arcs[k] - kMaxGapFraction * (old_arcs[k] - old_arcs[k - 1]);
      const double hi = old_arcs[k] + kMaxGapFraction * (old_arcs[k + 1] - old_arcs[k]);
      const Vec2 target{nodes.x[node].x + dx[node], nodes.x[node].y + dy[node]};
      // The drivers check the moves before calling apply(); this keeps a NaN out of the curve search.
      if (!std::isfinite(target.x) || !std::isfinite(target.y))
        throw SimulationError(
            fmt::format("boundary node {} of curve {} moved from ({}, {}) to a non-finite position "
                        "({}, {})",
                        node, c, nodes.x[node].x, nodes.x[node].y, target.x, target.y));
      const CurvePoint cp = closest_on_curve_range(curve, target, lo, hi);
      if (cp.arc == lo || cp.arc == hi) ++counts.clamped;
      nodes.x[node] = cp.p;
      arcs[k] = cp.arc;
      tangent_[node] = cp.tangent;
    }
  }
}

void BoundaryHandler::move_interior_node(NodeSet& nodes, std::size_t i, Vec2 move, BoundaryCounts& counts,
                                         const std::function<void()>* before_snap) {
  const Vec2 from = nodes.x[i];
  const Vec2 target{from.x + move.x, from.y + move.y};
  if (!std::isfinite(target.x) || !std::isfinite(target.y))
    throw SimulationError(fmt::format("node {} moved from ({}, {}) to a non-finite position ({}, {})", i, from.x,
                                      from.y, target.x, target.y));
  // The disc of radius budget_[i] around the last exactly tested position holds from (the costs of
  // the moves since then are subtracted) and, when this move's cost is below what is left, target and
  // the whole move: no exact test needed (see clearance_budget in the header).
  const double cost = move_cost(target.x - from.x, target.y - from.y, target.x, target.y, budget_[i]);
  if (cost < budget_[i]) {
    nodes.x[i] = target;
    budget_[i] -= cost;
    return;
  }
  // The refresh (the same rule on the device, kernels/clearance.cl): a node known inside (budget > 0:
  // its position is in the disc of the last exact test) whose move costs less than the clearance D of
  // its target has its old position in the open disc of radius D around the target, which holds no
  // boundary point, so the disc, the target and the move are inside and the exact test would accept:
  // the node gets the budget D without it. Only moves comparable to the distance to the boundary
  // (and nodes without a budget) get the exact test.
  const double clearance = budget_[i] > 0.0 ? clearance_from(target) : -1.0;
  if (budget_[i] > 0.0 && refresh_accepts(target.x - from.x, target.y - from.y, target, clearance)) {
    nodes.x[i] = target;
    budget_[i] = clearance;
    return;
  }
  if (tree_.inside(target) && !tree_.crosses_boundary(from, target)) {
    nodes.x[i] = target;
    budget_[i] = clearance >= 0.0 ? clearance : clearance_from(target);
    return;
  }
  budget_[i] = 0.0;
  if (before_snap && *before_snap) (*before_snap)();
  insert_snapped(nodes, static_cast<int>(i), target);
  ++counts.snapped;
}

int BoundaryHandler::add_interior(NodeSet& nodes, Vec2 p, double q) {
  const int node = nodes.add(p, q, NodeKind::Interior, -1);
  tangent_.push_back(Vec2{});
  budget_.push_back(0.0);
  return node;
}

int BoundaryHandler::add_boundary(NodeSet& nodes, int curve, std::size_t pos, double arc, double q) {
  const auto c = static_cast<std::size_t>(curve);
  std::vector<double>& arcs = arcs_.at(c);
  std::vector<int>& list = nodes.curve_nodes.at(c);
  if (pos == 0 || pos >= list.size() || !(arcs[pos - 1] < arc && arc < arcs[pos]))
    throw SimulationError(fmt::format("boundary insertion on curve {} at arc {} does not fall inside gap {} ({}, {})",
                                      curve, arc, pos, pos > 0 && pos <= arcs.size() ? arcs[pos - 1] : NAN,
                                      pos < arcs.size() ? arcs[pos] : NAN));
  // The point at that arc position: a search restricted to [arc, arc].
  const CurvePoint cp = closest_on_curve_range(tree_.geometry().curves[c], Vec2{}, arc, arc);
  const int node = nodes.add(cp.p, q, NodeKind::Boundary, curve);
  tangent_.push_back(cp.tangent);
  budget_.push_back(0.0);
  list.insert(list.begin() + static_cast<std::ptrdiff_t>(pos), node);
  arcs.insert(arcs.begin() + static_cast<std::ptrdiff_t>(pos), cp.arc);
  return node;
}

void BoundaryHandler::move_interior(NodeSet& nodes, int node, Vec2 p) {
  const auto i = static_cast<std::size_t>(node);
  if (nodes.kind[i] != NodeKind::Interior)
    throw SimulationError(fmt::format("node {} is {}: only interior nodes are moved by population control", node,
                                      to_string(nodes.kind[i])));
  nodes.x[i] = p;
  budget_[i] = 0.0;
}

std::vector<int> BoundaryHandler::remove_nodes(NodeSet& nodes, const std::vector<char>& remove) {
  const std::size_t n = nodes.size();
  const bool ids = nodes.has_ids();
  std::vector<int> new_of_old(n, -1), old_of_new;
  old_of_new.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (i < remove.size() && remove[i]) {
      if (nodes.kind[i] == NodeKind::Fixed)
        throw SimulationError(fmt::format("population control asked to remove node {}, a critical point", i));
      continue;
    }
    new_of_old[i] = static_cast<int>(old_of_new.size());
    old_of_new.push_back(static_cast<int>(i));
  }
  // Curve lists first (they hold old indices), then the per-node arrays in place (k <= old index).
  for (std::size_t c = 0; c < nodes.curve_nodes.size(); ++c) {
    std::vector<int>& list = nodes.curve_nodes[c];
    std::vector<double>& arcs = arcs_[c];
    std::size_t kept = 0;
    for (std::size_t k = 0; k < list.size(); ++k) {
      const int renumbered = new_of_old[static_cast<std::size_t>(list[k])];
      if (renumbered < 0) continue;
      list[kept] = renumbered;
      arcs[kept] = arcs[k];
      ++kept;
    }
    list.resize(kept);
    arcs.resize(kept);
  }
  for (std::size_t k = 0; k < old_of_new.size(); ++k) {
    const auto i = static_cast<std::size_t>(old_of_new[k]);
    nodes.x[k] = nodes.x[i];
    nodes.q[k] = nodes.q[i];
    nodes.kind[k] = nodes.kind[i];
    nodes.curve[k] = nodes.curve[i];
    if (ids) nodes.id[k] = nodes.id[i];
    tangent_[k] = tangent_[i];
    budget_[k] = budget_[i];
  }
  const std::size_t m = old_of_new.size();
  nodes.x.resize(m);
  nodes.q.resize(m);
  nodes.kind.resize(m);
  nodes.curve.resize(m);
  if (ids) nodes.id.resize(m);
  tangent_.resize(m);
  budget_.resize(m);
  return old_of_new;
}

double BoundaryHandler::clearance_from(Vec2 p) const {
  const ClosestHit hit = tree_.closest(p);
  if (hit.segment < 0 || !std::isfinite(hit.distance)) return 0.0;
  // The computed distance is within a few ulps of |p| + d of the true one; 1e-6 more covers the
  // rounding of a float device's copy of the budget.
  constexpr double eps = std::numeric_limits<double>::epsilon();
  const double d = hit.distance - 16.0 * eps * (std::fabs(p.x) + std::fabs(p.y) + hit.distance);
  return d > 0.0 ? d * (1.0 - 1e-6) : 0.0;
}

bool BoundaryHandler::refresh_accepts(double ex, double ey, Vec2 target, double clearance) {
  return clearance > 0.0 && move_cost(ex, ey, target.x, target.y, clearance) < clearance;
}

double BoundaryHandler::move_cost(double ex, double ey, double px, double py, double budget) {
  // sqrt(e^2) is within 3 ulps of |e| and e within 1 ulp of the true difference; the absolute term
  // covers e's rounding near coordinates of size |p| and the rounding of budget - cost.
  constexpr double eps = std::numeric_limits<double>::epsilon();
  return std::sqrt(ex * ex + ey * ey) * (1.0 + 64.0 * eps) + 8.0 * eps * (std::fabs(px) + std::fabs(py) + budget);
}

void BoundaryHandler::insert_snapped(NodeSet& nodes, int node, Vec2 target) {
  const Geometry& geometry = tree_.geometry();
  const ClosestHit hit = tree_.closest_wall(target);
  if (hit.segment < 0)
    throw SimulationError(fmt::format("node {} left the domain at ({}, {}) and there is no boundary to snap it to",
                                      node, target.x, target.y));
  const Segment& segment = geometry.segments[static_cast<std::size_t>(hit.segment)];
  const auto c = static_cast<std::size_t>(segment.curve);
  const Curve& curve = geometry.curves[c];
  const auto k = static_cast<std::size_t>(segment.index);
  const double arc = curve.arc[k] + hit.t * (curve.arc[k + 1] - curve.arc[k]);
  // The gap [arcs[pos - 1], arcs[pos]] the point falls in; end points are never passed.
  std::vector<double>& arcs = arcs_[c];
  std::vector<int>& list = nodes.curve_nodes[c];
  auto pos = static_cast<std::size_t>(std::upper_bound(arcs.begin(), arcs.end(), arc) - arcs.begin());
  pos = std::clamp<std::size_t>(pos, 1, arcs.size() - 1);
  const double gap = arcs[pos] - arcs[pos - 1];
  const CurvePoint cp =
      closest_on_curve_range(curve, target, arcs[pos - 1] + kInsertMargin * gap, arcs[pos] - kInsertMargin * gap);
  const auto i = static_cast<std::size_t>(node);
  nodes.x[i] = cp.p;
  nodes.kind[i] = NodeKind::Boundary;
  nodes.curve[i] = static_cast<int>(c);
  tangent_[i] = cp.tangent;
  list.insert(list.begin() + static_cast<std::ptrdiff_t>(pos), node);
  arcs.insert(arcs.begin() + static_cast<std::ptrdiff_t>(pos), cp.arc);
}

}  // namespace pdmesh
