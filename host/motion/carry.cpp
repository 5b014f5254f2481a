// Carrying nodes along with moving curves (carry.hpp).
#include "motion/carry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/predicates.hpp"

namespace pdmesh {

double carry_weight(double d, double radius) {
  if (!(radius > 0.0)) return 0.0;
  const double s = std::clamp(d / radius, 0.0, 1.0);
  return 1.0 - s * s * (3.0 - 2.0 * s);
}

std::vector<char> moving_nodes(const NodeSet& nodes, const std::vector<char>& moving_curves) {
  std::vector<char> out(nodes.size(), 0);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const int c = nodes.curve[i];
    if (nodes.kind[i] != NodeKind::Interior && c >= 0 && static_cast<std::size_t>(c) < moving_curves.size())
      out[i] = moving_curves[static_cast<std::size_t>(c)];
  }
  // A Fixed node's curve is its first curve; one shared by a moving curve moves too.
  for (std::size_t c = 0; c < nodes.curve_nodes.size() && c < moving_curves.size(); ++c) {
    if (!moving_curves[c]) continue;
    for (const int i : nodes.curve_nodes[c]) out[static_cast<std::size_t>(i)] = 1;
  }
  return out;
}

long first_inverted(const std::vector<std::array<int, 3>>& triangles, const std::vector<Vec2>& x) {
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& v = triangles[t];
    if (orient2d(x[static_cast<std::size_t>(v[0])], x[static_cast<std::size_t>(v[1])],
                 x[static_cast<std::size_t>(v[2])]) <= 0.0)
      return static_cast<long>(t);
  }
  return -1;
}

namespace {

// Distance from p to the moving curves of the tree's geometry.
double body_distance(const GeometryTree& tree, const std::vector<int>& body, Vec2 p) {
  double d = std::numeric_limits<double>::infinity();
  for (const int c : body) d = std::min(d, tree.closest_on_curve(p, c).distance);
  return d;
}

// One attempt with n sub-steps: the carried positions, or the first inverted triangle.
long attempt(const CarryRequest& r, const std::vector<int>& body, const std::vector<char>& rigid, int n,
             std::vector<Vec2>& x) {
  const NodeSet& nodes = *r.nodes;
  x = nodes.x;
  for (int k = 1; k <= n; ++k) {
    const RigidPose a = between(r.from, r.to, static_cast<double>(k - 1) / n);
    const RigidPose b = between(r.from, r.to, static_cast<double>(k) / n);
    const PoseChange step{a, b};
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      if (rigid[i]) {
        x[i] = step(x[i]);
        continue;
      }
      if (nodes.kind[i] != NodeKind::Interior) continue;
      // The distance to the body at pose a, measured on the geometry at pose `from`.
      const Vec2 at_from = r.from.apply(a.apply_inverse(x[i]));
      const double w = carry_weight(body_distance(*r.tree, body, at_from), r.radius);
      if (w <= 0.0) continue;
      const Vec2 moved = step(x[i]);
      x[i] = x[i] + w * (moved - x[i]);
    }
    const long bad = first_inverted(*r.triangles, x);
    if (bad >= 0) return bad;
  }
  return -1;
}

}  // namespace

CarryResult carry_nodes(const CarryRequest& r) {
  std::vector<int> body;
  for (std::size_t c = 0; c < r.moving.size(); ++c)
    if (r.moving[c]) body.push_back(static_cast<int>(c));
  const std::vector<char> rigid = moving_nodes(*r.nodes, r.moving);
  CarryResult out;
  long bad = -1;
  for (int h = 0; h <= r.max_halvings; ++h) {
    out.substeps = 1 << h;
    bad = attempt(r, body, rigid, out.substeps, out.x);
    if (bad < 0) return out;
  }
  const auto& v = (*r.triangles)[static_cast<std::size_t>(bad)];
  throw SimulationError(fmt::format(
      "motion: carrying the nodes inverts triangle {} (nodes {}, {}, {}) even in {} sub-steps; the motion between "
      "two steps is too large for the mesh around the body (more motion.steps, or a larger motion.blend)",
      bad, v[0], v[1], v[2], out.substeps));
}

}  // namespace pdmesh
