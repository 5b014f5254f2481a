// Tests of boundary handling: re-snapping boundary nodes along their curve and snapping interior
// nodes that leave the domain (convex and concave boundaries, corners, the closer of two curves).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "sim/boundary_handling.hpp"
#include "spacing/spacing_field.hpp"
#include "sim_fixtures.hpp"

using namespace pdmesh;

namespace {

struct ConstantSpacing final : SpacingField {
  double at(Vec2) const override { return 1.0; }
};

std::vector<Vec2> line(Vec2 a, Vec2 b, int segments) {
  std::vector<Vec2> p;
  for (int i = 0; i <= segments; ++i) p.push_back(a + (static_cast<double>(i) / segments) * (b - a));
  p.back() = b;
  return p;
}

// 10 x 10 square, counter-clockwise: bottom, right, top, left, 10 unit segments each.
Geometry square() {
  const Vec2 c[4] = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  const char* names[4] = {"bottom", "right", "top", "left"};
  std::vector<RawCurve> raw;
  for (int k = 0; k < 4; ++k) raw.push_back({names[k], line(c[k], c[(k + 1) % 4], 10), "square", 0, {}});
  return build_geometry(std::move(raw));
}

Geometry circle_in_circle() { return pdmesh_test::circle_circle(); }

int curve_named(const Geometry& g, const std::string& name) {
  for (std::size_t c = 0; c < g.curves.size(); ++c)
    if (g.curves[c].name == name) return static_cast<int>(c);
  FAIL("no curve " << name);
  return -1;
}

// Position of `node` in curve_nodes[c], or -1.
int slot_of(const NodeSet& nodes, int c, int node) {
  const auto& list = nodes.curve_nodes[static_cast<std::size_t>(c)];
  for (std::size_t k = 0; k < list.size(); ++k)
    if (list[k] == node) return static_cast<int>(k);
  return -1;
}

// Moves one node by d and applies boundary handling.
BoundaryCounts move_one(BoundaryHandler& handler, NodeSet& nodes, int node, Vec2 d) {
  std::vector<double> dx(nodes.size(), 0.0), dy(nodes.size(), 0.0);
  dx[static_cast<std::size_t>(node)] = d.x;
  dy[static_cast<std::size_t>(node)] = d.y;
  return handler.apply(nodes, dx, dy);
}

// Arc positions strictly increase along every curve.
void require_ordered(const BoundaryHandler& handler) {
  for (const auto& arcs : handler.arcs())
    for (std::size_t k = 1; k < arcs.size(); ++k) REQUIRE(arcs[k - 1] < arcs[k]);
}

}  // namespace

TEST_CASE("an interior node crossing a straight (convex) side is snapped onto it", "[sim]") {
  const Geometry g = square();
  const GeometryTree tree(g);
  NodeSet nodes = make_boundary_nodes(g, ConstantSpacing{});
  const int node = nodes.add({5.5, 0.3}, 1.0, NodeKind::Interior, -1);
  BoundaryHandler handler(tree, nodes);
  const BoundaryCounts counts = move_one(handler, nodes, node, {0.0, -0.8});
  CHECK(counts.snapped == 1);
  const int bottom = curve_named(g, "bottom");
  CHECK(nodes.x[static_cast<std::size_t>(node)] == Vec2{5.5, 0.0});
  CHECK(nodes.kind[static_cast<std::size_t>(node)] == NodeKind::Boundary);
  CHECK(nodes.curve[static_cast<std::size_t>(node)] == bottom);
  // Inserted between the nodes at x = 5 and x = 6 (fig. 5.7).
  const int k = slot_of(nodes, bottom, node);
  REQUIRE(k > 0);
  const auto& list = nodes.curve_nodes[static_cast<std::size_t>(bottom)];
  CHECK(nodes.x[static_cast<std::size_t>(list[static_cast<std::size_t>(k) - 1])] == Vec2{5.0, 0.0});
  CHECK(nodes.x[static_cast<std::size_t>(list[static_cast<std::size_t>(k) + 1])] == Vec2{6.0, 0.0});
  CHECK(handler.tangent(node).x == 1.0);
  CHECK(handler.tangent(node).y == 0.0);
  require_ordered(handler);
  std::vector<int> prev, next;
  handler.curve_neighbours(nodes, prev, next);
  CHECK(prev[static_cast<std::size_t>(node)] == list[static_cast<std::size_t>(k) - 1]);
  CHECK(next[static_cast<std::size_t>(node)] == list[static_cast<std::size_t>(k) + 1]);

  // A node that lands right on an existing boundary node is kept a quarter gap away from it.
  const int second = nodes.add({5.05, 0.4}, 1.0, NodeKind::Interior, -1);
  BoundaryHandler again(tree, nodes);
  move_one(again, nodes, second, {0.0, -0.6});
  CHECK(nodes.x[static_cast<std::size_t>(second)].x == Approx(5.125).epsilon(1e-15));
  CHECK(nodes.x[static_cast<std::size_t>(second)].y == 0.0);
  require_ordered(again);
}

TEST_CASE("an interior node moving into a hole (concave boundary) is snapped onto the hole", "[sim]") {
  const Geometry g = circle_in_circle();
  const GeometryTree tree(g);
  NodeSet nodes = make_boundary_nodes(g, ConstantSpacing{});
  const int node = nodes.add({0.9, 0.1}, 1.0, NodeKind::Interior, -1);
  BoundaryHandler handler(tree, nodes);
  const BoundaryCounts counts = move_one(handler, nodes, node, {-0.55, -0.05});
  CHECK(counts.snapped == 1);
  const auto i = static_cast<std::size_t>(node);
  CHECK(nodes.kind[i] == NodeKind::Boundary);
  CHECK(g.curves[static_cast<std::size_t>(nodes.curve[i])].name == "inner_upper");
  const double r = norm(nodes.x[i]);
  CHECK(r <= 0.5);
  CHECK(r >= 0.5 * std::cos(M_PI / 30));
  CHECK(tree.closest(nodes.x[i]).distance == 0.0);
  require_ordered(handler);
}

TEST_CASE("an interior node leaving at a corner is not snapped onto the critical point", "[sim]") {
  const Geometry g = square();
  const GeometryTree tree(g);
  NodeSet nodes = make_boundary_nodes(g, ConstantSpacing{});
  const int node = nodes.add({0.3, 0.2}, 1.0, NodeKind::Interior, -1);
  BoundaryHandler handler(tree, nodes);
  move_one(handler, nodes, node, {-0.5, -0.5});  // to (-0.2, -0.3): closest boundary point is the corner
  const auto i = static_cast<std::size_t>(node);
  CHECK(nodes.kind[i] == NodeKind::Boundary);
  const Vec2 p = nodes.x[i];
  CHECK(norm(p) == Approx(0.25).epsilon(1e-15));  // a quarter of the first gap away from the corner
  CHECK((p.x == 0.0 || p.y == 0.0));
  require_ordered(handler);
}

TEST_CASE("a node outside near two curves goes to the closer one", "[sim]") {
  const Geometry g = square();
  const GeometryTree tree(g);
  for (const auto& [target, expected_curve, expected] :
       {std::tuple{Vec2{-0.3, 0.4}, std::string("left"), Vec2{0.0, 0.4}},
        std::tuple{Vec2{0.4, -0.3}, std::string("bottom"), Vec2{0.4, 0.0}},
        std::tuple{Vec2{10.2, 9.5}, std::string("right"), Vec2{10.0, 9.5}}}) {
    NodeSet nodes = make_boundary_nodes(g, ConstantSpacing{});
    const Vec2 from{5.0, 5.0};
    const int node = nodes.add(from, 1.0, NodeKind::Interior, -1);
    BoundaryHandler handler(tree, nodes);
    move_one(handler, nodes, node, target - from);
    const auto i = static_cast<std::size_t>(node);
    INFO("target " << target.x << ", " << target.y);
    CHECK(g.curves[static_cast<std::size_t>(nodes.curve[i])].name == expected_curve);
    CHECK(nodes.x[i].x == Approx(expected.x).margin(1e-12));
    CHECK(nodes.x[i].y == Approx(expected.y).margin(1e-12));
  }
}

TEST_CASE("an interior node that stays inside moves freely", "[sim]") {
  const Geometry g = square();
  const GeometryTree tree(g);
  NodeSet nodes = make_boundary_nodes(g, ConstantSpacing{});
  const int node = nodes.add({5.0, 5.0}, 1.0, NodeKind::Interior, -1);
  BoundaryHandler handler(tree, nodes);
  const BoundaryCounts counts = move_one(handler, nodes, node, {0.25, -0.5});
  CHECK(counts.snapped == 0);
  CHECK(nodes.x[static_cast<std::size_t>(node)] == Vec2{5.25, 4.5});
  CHECK(nodes.kind[static_cast<std::size_t>(node)] == NodeKind::Interior);
}

TEST_CASE("boundary nodes are re-snapped along their curve and never pass a neighbour", "[sim]") {
  const Geometry g = square();
  const GeometryTree tree(g);
  NodeSet nodes = make_boundary_nodes(g, ConstantSpacing{});
  const int bottom = curve_named(g, "bottom");
  const auto& list = nodes.curve_nodes[static_cast<std::size_t>(bottom)];
  const int at3 = list[3], at1 = list[1];
  REQUIRE(nodes.x[static_cast<std::size_t>(at3)] == Vec2{3.0, 0.0});
  BoundaryHandler handler(tree, nodes);
  CHECK(handler.tangent(at3).x == 1.0);

  BoundaryCounts counts = move_one(handler, nodes, at3, {0.2, 0.3});  // off the curve: back onto it
  CHECK(counts.clamped == 0);
  CHECK(nodes.x[static_cast<std::size_t>(at3)].x == Approx(3.2).epsilon(1e-15));
  CHECK(nodes.x[static_cast<std::size_t>(at3)].y == 0.0);
  counts = move_one(handler, nodes, at3, {5.0, 0.0});  // towards x = 4: at most 0.45 of the gap
  CHECK(counts.clamped == 1);
  CHECK(nodes.x[static_cast<std::size_t>(at3)].x == Approx(3.2 + 0.45 * 0.8).epsilon(1e-15));
  counts = move_one(handler, nodes, at1, {-3.0, -1.0});  // towards the corner (a critical point)
  CHECK(counts.clamped == 1);
  CHECK(nodes.x[static_cast<std::size_t>(at1)].x == Approx(0.55).epsilon(1e-15));
  require_ordered(handler);
}

TEST_CASE("a boundary node at a polyline vertex slides along the mean tangent", "[sim]") {
  const Geometry g = circle_in_circle();
  const GeometryTree tree(g);
  NodeSet nodes = make_boundary_nodes(g, ConstantSpacing{});
  const int upper = curve_named(g, "outer_upper");
  const int node = nodes.curve_nodes[static_cast<std::size_t>(upper)][15];  // the top, (0, 10)
  BoundaryHandler handler(tree, nodes);
  const Vec2 t = handler.tangent(node);
  CHECK(t.y == Approx(0.0).margin(1e-12));
  CHECK(std::fabs(t.x) == Approx(1.0).epsilon(1e-12));
  // Re-snapped onto the polyline after a tangential move.
  move_one(handler, nodes, node, 0.3 * t);
  CHECK(tree.closest(nodes.x[static_cast<std::size_t>(node)]).distance < 1e-12);
  CHECK(nodes.x[static_cast<std::size_t>(node)].x == Approx(0.3 * t.x).margin(1e-3));
}

TEST_CASE("closest point in an arc range", "[sim]") {
  const Geometry g = square();
  const Curve& bottom = g.curves[static_cast<std::size_t>(curve_named(g, "bottom"))];
  CurvePoint cp = closest_on_curve_range(bottom, {4.5, 3.0}, 2.0, 7.0);
  CHECK(cp.p == Vec2{4.5, 0.0});
  CHECK(cp.arc == 4.5);
  CHECK(cp.distance == 3.0);
  cp = closest_on_curve_range(bottom, {9.0, -1.0}, 2.5, 7.25);
  CHECK(cp.arc == 7.25);
  CHECK(cp.p.x == 7.25);
  cp = closest_on_curve_range(bottom, {-4.0, 0.0}, 2.5, 7.25);
  CHECK(cp.arc == 2.5);
}

TEST_CASE("clearance budget: a lower bound of the distance, and skipped moves stay inside", "[sim][boundary]") {
  for (const Geometry& g : {square(), circle_in_circle()}) {
    const GeometryTree tree(g);
    const NodeSet nodes = make_boundary_nodes(g, ConstantSpacing{});
    const BoundaryHandler handler(tree, nodes);
    std::mt19937_64 rng(20261121);
    const Box& e = g.extents;
    int inside = 0, walked = 0;
    for (int trial = 0; trial < 400; ++trial) {
      Vec2 p{e.lo.x + pdmesh_test::uniform(rng) * e.width(), e.lo.y + pdmesh_test::uniform(rng) * e.height()};
      if (!tree.inside(p)) continue;
      ++inside;
      // Brute force over every segment.
      double d = HUGE_VAL;
      for (std::size_t s = 0; s < g.segments.size(); ++s)
        d = std::min(d, closest_on_segment(p, g.segments[s], static_cast<int>(s)).distance);
      const double c = handler.clearance_from(p);
      REQUIRE(c <= d);
      CHECK(c >= d * (1.0 - 1e-5));
      // A random walk spending the budget: every move the budget admits is one the exact test accepts.
      double budget = c;
      for (int step = 0; step < 50; ++step) {
        const double angle = 2.0 * std::numbers::pi * pdmesh_test::uniform(rng);
        const double length = (step % 7 == 6 ? 2.0 : 0.3) * pdmesh_test::uniform(rng) * c;
        const Vec2 to{p.x + length * std::cos(angle), p.y + length * std::sin(angle)};
        const double cost = BoundaryHandler::move_cost(to.x - p.x, to.y - p.y, to.x, to.y, budget);
        if (!(cost < budget)) break;
        REQUIRE(tree.inside(to));
        REQUIRE_FALSE(tree.crosses_boundary(p, to));
        budget -= cost;
        p = to;
        ++walked;
      }
    }
    CHECK(inside > 100);
    CHECK(walked > 1000);
  }
}

TEST_CASE("clearance budget: a node walking out is snapped in the same iteration as by the exact test",
          "[sim][boundary]") {
  // Steps of 0.07 from y = 0.9 towards the bottom side: every position is tested, the move from
  // y_12 = 0.9 - 12 * 0.07 (> 0) to y_13 (< 0) crosses, and only that one.
  const Geometry g = square();
  const GeometryTree tree(g);
  NodeSet nodes = make_boundary_nodes(g, ConstantSpacing{});
  const int node = nodes.add({5.5, 0.9}, 1.0, NodeKind::Interior, -1);
  BoundaryHandler handler(tree, nodes);
  double y = 0.9;
  for (int iteration = 1; iteration <= 13; ++iteration) {
    move_one(handler, nodes, node, {0.0, -0.07});
    const auto i = static_cast<std::size_t>(node);
    y = y - 0.07;
    INFO("iteration " << iteration);
    if (iteration < 13) {
      REQUIRE(nodes.kind[i] == NodeKind::Interior);
      REQUIRE(nodes.x[i].y == y);
      // The budget shrinks as the node approaches the side: it never exceeds the distance.
      REQUIRE(handler.clearance_budget(node) <= nodes.x[i].y);
    } else {
      REQUIRE(nodes.kind[i] == NodeKind::Boundary);
      REQUIRE(nodes.x[i].y == 0.0);
    }
  }
}
