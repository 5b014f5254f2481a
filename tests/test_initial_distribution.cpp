// Tests of the initial node distribution (thesis ch. 4): boundary nodes, the initialization tree
// (refinement, 2:1 balance, kept leaves), structured/random fill, keep rule, overloading, estimate.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>
#include <vector>

#include "geometry/geometry.hpp"
#include "geometry_fixtures.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/init_tree.hpp"
#include "init/initial_distribution.hpp"
#include "spacing/spacing_field.hpp"

using namespace pdmesh;

namespace {

constexpr double kPi = std::numbers::pi;

using fixtures::brute_distance;
using fixtures::line;
using fixtures::square;

// A circle of radius r as two semicircles of `points` equally spaced points each, joined at (+-r, 0).
void add_circle(std::vector<RawCurve>& raw, double r, int points, const std::string& name) {
  const int n = points - 1;
  for (int half = 0; half < 2; ++half) {
    RawCurve curve;
    curve.name = name + (half == 0 ? "_upper" : "_lower");
    for (int i = 0; i <= n; ++i) {
      const double t = kPi * (half + static_cast<double>(i) / n);
      Vec2 p{r * std::cos(t), r * std::sin(t)};
      if (i == 0) p = {half == 0 ? r : -r, 0.0};
      if (i == n) p = {half == 0 ? -r : r, 0.0};
      curve.points.push_back(p);
    }
    raw.push_back(std::move(curve));
  }
}

Geometry circle_in_circle() {
  std::vector<RawCurve> raw;
  add_circle(raw, 10.0, 31, "outer");
  add_circle(raw, 0.5, 31, "inner");
  return build_geometry(std::move(raw));
}

// A brute-force oracle, independent of GeometryTree (brute_distance: geometry_fixtures.hpp).
bool brute_inside(const Geometry& g, Vec2 p) {
  bool in = false;
  for (const Segment& s : g.segments) {
    if ((s.a.y > p.y) != (s.b.y > p.y)) {
      const double x = s.a.x + (p.y - s.a.y) / (s.b.y - s.a.y) * (s.b.x - s.a.x);
      if (x > p.x) in = !in;
    }
  }
  return in;
}

// Checks the interior nodes: inside, clear of the boundary by the keep rule, q = q(x).
void check_interior(const Geometry& g, const SpacingField& spacing, const NodeSet& nodes) {
  std::size_t bad = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes.kind[i] != NodeKind::Interior) continue;
    const Vec2 p = nodes.x[i];
    const double q = spacing.at(p);
    const bool ok = brute_inside(g, p) && brute_distance(g, p) >= kInitBoundaryClearance * q && nodes.q[i] == q &&
                    nodes.curve[i] == -1;
    if (!ok && bad++ < 5)
      FAIL_CHECK("interior node " << i << " at (" << p.x << ", " << p.y << ") breaks the keep rule");
  }
  CHECK(bad == 0);
}

// Every pair of touching kept leaves (edges or corners) differs by at most one level.
void check_balance(const std::vector<Box>& quads) {
  std::size_t touching = 0, bad = 0;
  for (std::size_t i = 0; i < quads.size(); ++i) {
    for (std::size_t j = i + 1; j < quads.size(); ++j) {
      const Box& a = quads[i];
      const Box& b = quads[j];
      if (a.lo.x > b.hi.x || b.lo.x > a.hi.x || a.lo.y > b.hi.y || b.lo.y > a.hi.y) continue;
      ++touching;
      const double ratio = std::max(a.width(), b.width()) / std::min(a.width(), b.width());
      if (ratio > 2.0 * (1 + 1e-9)) ++bad;
    }
  }
  INFO("touching pairs " << touching);
  CHECK(touching > 0);
  CHECK(bad == 0);
}

const char* name_of(InitMethod m) { return to_string(m); }

}  // namespace

TEST_CASE("boundary nodes of a square: 4 shared corners, the rest Boundary, curve order", "[init]") {
  const int m = 13;
  const Geometry g = square(7.3, m);
  const GeometryTree tree(g);
  const BoundarySpacing spacing(tree);
  const NodeSet nodes = make_boundary_nodes(g, spacing);
  CHECK(nodes.count(NodeKind::Fixed) == 4);
  CHECK(nodes.count(NodeKind::Boundary) == 4 * (m - 1));
  CHECK(nodes.count(NodeKind::Interior) == 0);
  REQUIRE(nodes.curve_nodes.size() == 4);
  for (int c = 0; c < 4; ++c) {
    const auto& list = nodes.curve_nodes[c];
    REQUIRE(list.size() == static_cast<std::size_t>(m + 1));
    CHECK(nodes.kind[list.front()] == NodeKind::Fixed);
    CHECK(nodes.kind[list.back()] == NodeKind::Fixed);
    for (std::size_t i = 0; i < list.size(); ++i) {
      CHECK(nodes.x[list[i]] == g.curves[c].points[i]);
      CHECK(nodes.q[list[i]] == spacing.at(nodes.x[list[i]]));
      if (i > 0 && i + 1 < list.size()) {
        CHECK(nodes.kind[list[i]] == NodeKind::Boundary);
        CHECK(nodes.curve[list[i]] == c);
      }
    }
  }
  // Each corner is one node shared by the two curves meeting there.
  for (int c = 0; c < 4; ++c) {
    const auto& list = nodes.curve_nodes[c];
    bool shared = false;
    for (int d = 0; d < 4; ++d) {
      if (d == c) continue;
      const auto& other = nodes.curve_nodes[d];
      shared = shared || list.back() == other.front() || list.back() == other.back();
    }
    CHECK(shared);
  }
}

TEST_CASE("boundary nodes of circle in circle: one Fixed node per joint", "[init]") {
  const Geometry g = circle_in_circle();
  const GeometryTree tree(g);
  const BoundarySpacing spacing(tree);
  const NodeSet nodes = make_boundary_nodes(g, spacing);
  CHECK(nodes.count(NodeKind::Fixed) == 4);
  CHECK(nodes.count(NodeKind::Boundary) == 4 * 29);
  REQUIRE(nodes.curve_nodes.size() == 4);
  for (std::size_t c = 0; c < 4; ++c) {
    REQUIRE(nodes.curve_nodes[c].size() == 31);
    for (std::size_t i = 0; i < 31; ++i) CHECK(nodes.x[nodes.curve_nodes[c][i]] == g.curves[c].points[i]);
  }
  // Every Fixed node appears at an end of exactly two curves (twice per circle).
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes.kind[i] != NodeKind::Fixed) continue;
    int ends = 0;
    for (const auto& list : nodes.curve_nodes)
      ends += (list.front() == static_cast<int>(i)) + (list.back() == static_cast<int>(i));
    CHECK(ends == 2);
  }
}

TEST_CASE("a single closed curve lists its one end node at both ends", "[init]") {
  std::vector<RawCurve> raw(1);
  raw[0].name = "ring";
  for (int i = 0; i <= 17; ++i) {
    const double t = 2 * kPi * i / 17;
    raw[0].points.push_back(i == 17 ? Vec2{3.0, 0.0} : Vec2{3.0 * std::cos(t), 3.0 * std::sin(t)});
  }
  raw[0].points[0] = {3.0, 0.0};
  const Geometry g = build_geometry(std::move(raw));
  const GeometryTree tree(g);
  const BoundarySpacing spacing(tree);
  const NodeSet nodes = make_boundary_nodes(g, spacing);
  REQUIRE(nodes.curve_nodes.size() == 1);
  const auto& list = nodes.curve_nodes[0];
  REQUIRE(list.size() == 18);
  CHECK(list.front() == list.back());
  CHECK(nodes.kind[list.front()] == NodeKind::Fixed);
  CHECK(nodes.size() == 17);
}

TEST_CASE("estimate of a constant-spacing square matches the closed form", "[init]") {
  const double L = 7.3;
  const int m = 13;
  const Geometry g = square(L, m);
  const GeometryTree tree(g);
  const BoundarySpacing spacing(tree);
  const double q = L / m;
  CHECK(spacing.at({L / 2, L / 3}) == Approx(q).epsilon(1e-9));
  const double closed_form = L * L * 2.0 / (std::sqrt(3.0) * q * q);
  const double estimate = estimate_node_count(tree, spacing);
  WARN("square: estimate " << estimate << ", closed form " << closed_form);
  CHECK(estimate == Approx(closed_form).epsilon(0.02));
}

TEST_CASE("estimate resolves a narrow band of fine spacing inside coarse quads (shock, eq. 7.2)", "[init]") {
  // 200 x 200 square centred at the origin, 10 segments per side (q = 20 from the boundary), with
  // the thesis' shock field: q = 0.5 at x = 0, 20 far from it. Almost all nodes lie in the band.
  const Geometry g = square(200.0, 10, {-100.0, -100.0});
  const GeometryTree tree(g);
  const ExpressionSpacing spacing("0.5 + 19.5*tanh(x/16)^2");
  // Closed form in y, midpoint rule in x on a fine grid: integral of 200 * 2/(sqrt(3) q(x)^2) dx.
  const int n = 200000;
  double integral = 0.0;
  for (int i = 0; i < n; ++i) {
    const double x = -100.0 + (i + 0.5) * 200.0 / n;
    const double q = spacing.at({x, 0.0});
    integral += 200.0 * 2.0 / (std::sqrt(3.0) * q * q) * (200.0 / n);
  }
  const double estimate = estimate_node_count(tree, spacing);
  WARN("shock: estimate " << estimate << ", integral " << integral);
  CHECK(estimate == Approx(integral).epsilon(0.05));
}

TEST_CASE("estimate of circle in circle matches a brute-force grid integral", "[init]") {
  const Geometry g = circle_in_circle();
  const GeometryTree tree(g);
  const BoundarySpacing spacing(tree);
  // Midpoint rule on a 600 x 600 grid over [-10, 10]^2 with the brute-force inside test.
  const int n = 600;
  const double h = 20.0 / n;
  double brute = 0.0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const Vec2 p{-10 + (i + 0.5) * h, -10 + (j + 0.5) * h};
      if (!brute_inside(g, p)) continue;
      const double q = spacing.at(p);
      brute += h * h * 2.0 / (std::sqrt(3.0) * q * q);
    }
  }
  const double estimate = estimate_node_count(tree, spacing);
  WARN("circle in circle: estimate " << estimate << ", brute-force grid " << brute);
  CHECK(estimate == Approx(brute).epsilon(0.03));
}

TEST_CASE("node counts follow the estimate (square and circle in circle, both methods)", "[init]") {
  // Measured: all nodes (boundary + interior) against the hexagonal-packing estimate.
  const double tolerance = 0.25;
  for (InitMethod method : {InitMethod::Structured, InitMethod::Random, InitMethod::Hexagonal}) {
    {
      // The thesis' fig 7.1 square: 200 x 200 with 40 boundary points, q = 20.
      const Geometry g = square(200.0, 10);
      const GeometryTree tree(g);
      const BoundarySpacing spacing(tree);
      const InitialDistribution d = make_initial_distribution(tree, spacing, {method, 42, {}});
      WARN("square " << name_of(method) << ": nodes " << d.nodes.size() << " (interior " << d.tree_nodes
                     << "), estimate " << d.estimate << ", ratio " << d.nodes.size() / d.estimate);
      CHECK(d.tree_nodes == d.nodes.count(NodeKind::Interior));
      CHECK(d.overload_nodes == 0);
      CHECK(std::abs(d.nodes.size() / d.estimate - 1.0) <= tolerance);
      check_interior(g, spacing, d.nodes);
    }
    {
      const Geometry g = circle_in_circle();
      const GeometryTree tree(g);
      const BoundarySpacing spacing(tree);
      const InitialDistribution d = make_initial_distribution(tree, spacing, {method, 42, {}});
      WARN("circle in circle " << name_of(method) << ": nodes " << d.nodes.size() << " (interior " << d.tree_nodes
                               << "), estimate " << d.estimate << ", ratio " << d.nodes.size() / d.estimate);
      CHECK(std::abs(d.nodes.size() / d.estimate - 1.0) <= tolerance);
      check_interior(g, spacing, d.nodes);
    }
  }
}

TEST_CASE("hexagonal fill: near the hexagonal-packing estimate, a lattice of spacing q away from the boundary",
          "[init][hexagonal]") {
  // A square and an annulus whose boundary segments are 0.5 long, so that eq. 3.6 gives q ~ 0.5
  // everywhere; and the thesis' graded circle in circle.
  std::vector<RawCurve> ring;
  add_circle(ring, 10.0, 64, "outer");
  add_circle(ring, 5.0, 33, "inner");
  const Geometry annulus = build_geometry(std::move(ring));
  const Geometry sq = square(20.0, 40);
  const Geometry graded = circle_in_circle();
  for (const auto& [name, g, tolerance] : {std::tuple{"square", &sq, 0.08}, std::tuple{"annulus", &annulus, 0.08},
                                           std::tuple{"circle in circle", &graded, 0.08}}) {
    const GeometryTree tree(*g);
    const BoundarySpacing spacing(tree);
    const InitialDistribution d = make_initial_distribution(tree, spacing, {InitMethod::Hexagonal, 1, {}});
    const double ratio = d.nodes.size() / d.estimate;
    WARN(name << " hexagonal: nodes " << d.nodes.size() << ", estimate " << d.estimate << ", ratio " << ratio);
    CHECK(std::abs(ratio - 1.0) <= tolerance);
    check_interior(*g, spacing, d.nodes);
    // Away from the boundary the nodes of the uniform cases sit on one lattice: nearest neighbour at q
    // (within 10%: the lattice spacing is q's level, within 4.4%) and six neighbours within 1.2 q.
    // The graded case changes level every ~9% of q, with a seam each time.
    std::size_t far = 0, on_lattice = 0;
    for (std::size_t i = 0; i < d.nodes.size(); ++i) {
      const Vec2 p = d.nodes.x[i];
      const double q = d.nodes.q[i];
      if (d.nodes.kind[i] != NodeKind::Interior || brute_distance(*g, p) < 3.0 * q) continue;
      ++far;
      double nearest = HUGE_VAL;
      int close = 0;
      for (std::size_t j = 0; j < d.nodes.size(); ++j) {
        if (j == i) continue;
        const double r = dist(p, d.nodes.x[j]);
        nearest = std::min(nearest, r);
        close += r < 1.2 * q;
      }
      on_lattice += std::abs(nearest / q - 1.0) <= 0.1 && close == 6;
    }
    WARN(name << ": " << on_lattice << " of " << far << " nodes away from the boundary on the lattice");
    CHECK(far > 0);
    if (g != &graded) CHECK(on_lattice >= 0.95 * far);
  }
}

TEST_CASE("random fill is reproducible with a seed and differs with another", "[init]") {
  const Geometry g = circle_in_circle();
  const GeometryTree tree(g);
  const BoundarySpacing spacing(tree);
  const auto a = make_initial_distribution(tree, spacing, {InitMethod::Random, 7, {}});
  const auto b = make_initial_distribution(tree, spacing, {InitMethod::Random, 7, {}});
  const auto c = make_initial_distribution(tree, spacing, {InitMethod::Random, 8, {}});
  REQUIRE(a.nodes.size() == b.nodes.size());
  bool identical = true;
  for (std::size_t i = 0; i < a.nodes.size(); ++i) identical = identical && a.nodes.x[i] == b.nodes.x[i];
  CHECK(identical);
  bool differs = a.nodes.size() != c.nodes.size();
  for (std::size_t i = 0; !differs && i < a.nodes.size(); ++i) differs = !(a.nodes.x[i] == c.nodes.x[i]);
  CHECK(differs);
  // The structured fill does not depend on the seed.
  const auto s1 = make_initial_distribution(tree, spacing, {InitMethod::Structured, 7, {}});
  const auto s2 = make_initial_distribution(tree, spacing, {InitMethod::Structured, 8, {}});
  REQUIRE(s1.nodes.size() == s2.nodes.size());
  for (std::size_t i = 0; i < s1.nodes.size(); ++i) CHECK(s1.nodes.x[i] == s2.nodes.x[i]);
}

TEST_CASE("overloading adds exactly the remainder to reach the total", "[init]") {
  const Geometry g = circle_in_circle();
  const GeometryTree tree(g);
  const BoundarySpacing spacing(tree);
  for (InitMethod method : {InitMethod::Structured, InitMethod::Random}) {
    const auto base = make_initial_distribution(tree, spacing, {method, 3, {}});
    const std::size_t total = base.nodes.size() + 137;
    const auto over = make_initial_distribution(tree, spacing, {method, 3, total});
    CHECK(over.nodes.size() == total);
    CHECK(over.overload_nodes == 137);
    CHECK(over.tree_nodes == base.tree_nodes);
    // The tree fill is unchanged by overloading; the extra nodes obey the same keep rule.
    for (std::size_t i = 0; i < base.nodes.size(); ++i) CHECK(over.nodes.x[i] == base.nodes.x[i]);
    check_interior(g, spacing, over.nodes);
    // A total at or below what the fill produced changes nothing.
    const auto under = make_initial_distribution(tree, spacing, {method, 3, base.nodes.size() - 5});
    CHECK(under.nodes.size() == base.nodes.size());
    CHECK(under.overload_nodes == 0);
  }
}

TEST_CASE("initialization tree: refined along the geometry, 2:1 balanced, outside leaves dropped", "[init]") {
  const Geometry g = circle_in_circle();
  const GeometryTree tree(g);
  const BoundarySpacing spacing(tree);
  const InitTree init(tree, spacing);
  const InitTreeOptions defaults;
  std::vector<Box> kept;
  double kept_area = 0.0;
  for (const InitLeaf& leaf : init.leaves()) {
    const double side = init.side(leaf.level);
    if (!leaf.segments.empty()) {
      // The refinement rule: side <= min(shortest touching segment, q at the centre).
      double shortest = INFINITY;
      for (int s : leaf.segments) shortest = std::fmin(shortest, g.segments[s].length);
      CHECK(side <= defaults.refine_factor * std::fmin(shortest, spacing.at(leaf.box.centre())));
    }
    // Segment lists are exact: a segment is listed iff it touches the closed box.
    for (std::size_t s = 0; s < g.segments.size(); s += 7) {
      const bool listed =
          std::find(leaf.segments.begin(), leaf.segments.end(), static_cast<int>(s)) != leaf.segments.end();
      CHECK(listed == segment_touches_box(g.segments[s].a, g.segments[s].b, leaf.box));
    }
    CHECK(leaf.kept == (!leaf.segments.empty() || brute_inside(g, leaf.box.centre())));
    if (leaf.kept) {
      kept.push_back(leaf.box);
      kept_area += leaf.box.width() * leaf.box.height();
    }
  }
  CHECK(kept.size() == init.kept().size());
  CHECK(kept.size() < init.leaves().size());
  // Kept leaves cover the domain: at least its area, at most the root box.
  CHECK(kept_area >= g.area);
  CHECK(kept_area < init.root().width() * init.root().height());
  check_balance(kept);
  const auto d = make_initial_distribution(tree, spacing, {});
  CHECK(d.tree_quads.size() == kept.size());
  check_balance(d.tree_quads);
}

TEST_CASE("segment_touches_box: corners, edges, crossings and misses", "[init]") {
  const Box b{{0, 0}, {1, 1}};
  CHECK(segment_touches_box({-1, -1}, {0, 0}, b));                  // ends on a corner
  CHECK(segment_touches_box({-1, 0.5}, {2, 0.5}, b));               // crosses through
  CHECK(segment_touches_box({0.2, 0.2}, {0.3, 0.4}, b));            // inside
  CHECK(segment_touches_box({-1, 1}, {1, -1}, b));                  // touches the corner (0, 0) only
  CHECK(segment_touches_box({-1, 1.0000001}, {1.0000001, -1}, b));  // clips the corner
  CHECK_FALSE(segment_touches_box({-1, 0.9}, {0.9, -1.1}, b));      // passes below-left of (0, 0)
  CHECK_FALSE(segment_touches_box({2, 0}, {3, 5}, b));
  CHECK(segment_touches_box({1, 2}, {1, -2}, b));  // along the right edge
}
