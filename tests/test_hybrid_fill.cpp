// The hybrid initial fill (docs/initialization.md, "The hybrid fill"): an equilateral lattice as dense
// as the structured patterns in quads well inside the domain where q is nearly flat; the patterns
// elsewhere.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "geometry_fixtures.hpp"
#include "init/initial_distribution.hpp"
#include "spacing/refine_regions.hpp"
#include "spacing/spacing_field.hpp"

using namespace pdmesh;

namespace {

std::set<std::pair<double, double>> interior_points(const NodeSet& nodes) {
  std::set<std::pair<double, double>> out;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes.kind[i] == NodeKind::Interior) out.insert({nodes.x[i].x, nodes.x[i].y});
  return out;
}

}  // namespace

TEST_CASE("hybrid fill: the structured patterns next to the boundary, a lattice of their density inside",
          "[init][hybrid]") {
  // 20 x 20 with boundary segments 0.5 long: q ~ 0.5 everywhere (eq. 3.6).
  const Geometry g = fixtures::square(20.0, 40);
  const GeometryTree tree(g);
  const BoundarySpacing spacing(tree);
  const InitialDistribution hybrid = make_initial_distribution(tree, spacing, {InitMethod::Hybrid, 1, {}});
  const InitialDistribution structured = make_initial_distribution(tree, spacing, {InitMethod::Structured, 1, {}});
  const auto pattern_points = interior_points(structured.nodes);

  std::size_t near = 0, near_as_structured = 0, far = 0, on_lattice = 0, lattice_points = 0;
  for (std::size_t i = 0; i < hybrid.nodes.size(); ++i) {
    if (hybrid.nodes.kind[i] != NodeKind::Interior) continue;
    const Vec2 p = hybrid.nodes.x[i];
    const double q = hybrid.nodes.q[i];
    const double d = fixtures::brute_distance(g, p);
    CHECK(d >= kInitBoundaryClearance * q);
    const bool pattern = pattern_points.count({p.x, p.y}) > 0;
    lattice_points += !pattern;
    // A lattice quad's centre is at least 2 q beyond its half-diagonal from the boundary, so every
    // node within 2 q of it comes from a pattern, at the structured fill's place.
    if (d < 2.0 * q) {
      ++near;
      near_as_structured += pattern;
    }
    // A node 6.5 q inside lies in a quad (at most ~2.7 q wide) whose centre passes that test.
    if (d < 6.5 * q) continue;
    ++far;
    // On a lattice: six neighbours at the nearest distance, to rounding.
    double nearest = HUGE_VAL;
    for (std::size_t j = 0; j < hybrid.nodes.size(); ++j)
      if (j != i) nearest = std::min(nearest, dist(p, hybrid.nodes.x[j]));
    int six = 0;
    for (std::size_t j = 0; j < hybrid.nodes.size(); ++j)
      if (j != i) six += std::abs(dist(p, hybrid.nodes.x[j]) / nearest - 1.0) <= 1e-9;
    on_lattice += six == 6;
  }
  WARN("hybrid: " << hybrid.tree_nodes << " interior nodes (structured " << structured.tree_nodes << "), "
                  << lattice_points << " off the patterns; near " << near_as_structured << " of " << near << "; far "
                  << on_lattice << " of " << far << " on the lattice");
  CHECK(near > 0);
  CHECK(near_as_structured == near);
  CHECK(far > 0);
  CHECK(on_lattice >= 0.95 * far);
  CHECK(lattice_points > 0);
  // The lattice is as dense as the patterns it replaces, so the count stays the structured fill's.
  CHECK(std::abs(static_cast<double>(hybrid.tree_nodes) / static_cast<double>(structured.tree_nodes) - 1.0) <= 0.03);

  // Deterministic, whatever the seed.
  const InitialDistribution again = make_initial_distribution(tree, spacing, {InitMethod::Hybrid, 8, {}});
  REQUIRE(again.nodes.size() == hybrid.nodes.size());
  bool identical = true;
  for (std::size_t i = 0; i < again.nodes.size(); ++i) identical = identical && again.nodes.x[i] == hybrid.nodes.x[i];
  CHECK(identical);
}

TEST_CASE("hybrid fill with a density: the start follows the estimate whatever the quads' area ratios",
          "[init][hybrid]") {
  // Squares of side 20 at uniform spacings whose quads fall at different places of the patterns'
  // ratio bands (the tree's leaves are the root side / 2^k). The structured patterns overfill the
  // estimate by a share that depends on where the ratios fall; with init.density the interior start
  // is that density times the estimate of the part beyond the keep rule's clearance, whatever q.
  const double density = 1.21;
  double lo = HUGE_VAL, hi = 0.0, lo_structured = HUGE_VAL, hi_structured = 0.0;
  for (const double q : {0.40, 0.43, 0.46, 0.50, 0.53, 0.57, 0.61, 0.66}) {
    const int m = static_cast<int>(std::lround(20.0 / q));
    const Geometry g = fixtures::square(20.0, m);
    const GeometryTree tree(g);
    const UniformSpacing spacing(q);
    InitOptions options{InitMethod::Hybrid, 1, {}};
    options.density = density;
    const InitialDistribution d = make_initial_distribution(tree, spacing, options);
    const InitialDistribution s = make_initial_distribution(tree, spacing, {InitMethod::Structured, 1, {}});
    // The estimate of the interior beyond the clearance: the square less a band of 0.5 q.
    const double inner = (20.0 - q) * (20.0 - q) * 2.0 / (std::sqrt(3.0) * q * q);
    const double r = static_cast<double>(d.tree_nodes) / inner;
    const double rs = static_cast<double>(s.tree_nodes) / inner;
    WARN("q " << q << ": hybrid with density " << d.tree_nodes << " interior nodes (" << r << " x the estimate), "
              << "structured " << s.tree_nodes << " (" << rs << ")");
    lo = std::min(lo, r);
    hi = std::max(hi, r);
    lo_structured = std::min(lo_structured, rs);
    hi_structured = std::max(hi_structured, rs);
  }
  CHECK(lo >= 0.9 * density);
  CHECK(hi <= 1.1 * density);
  // What the density corrects: the patterns' share of the estimate moves with q.
  CHECK(hi_structured / lo_structured > 1.2);
}

TEST_CASE("hybrid fill with a density where q is flat: graded quads keep the patterns, flat ones follow the estimate",
          "[init][hybrid]") {
  const double density = 1.25;
  SECTION("a field graded everywhere starts as the patterns do") {
    // q grows by 5 % of its value over less than a quad's width everywhere: no quad passes the flat test.
    const Geometry g = fixtures::square(20.0, 80);
    const GeometryTree tree(g);
    const ExpressionSpacing spacing("0.2 + 0.05 * x");
    InitOptions plain{InitMethod::Hybrid, 1, {}};
    InitOptions flat = plain;
    flat.density = density;
    flat.density_where = DensityWhere::Flat;
    InitOptions inside = flat;
    inside.density_where = DensityWhere::Inside;
    const auto p = interior_points(make_initial_distribution(tree, spacing, plain).nodes);
    CHECK(interior_points(make_initial_distribution(tree, spacing, flat).nodes) == p);
    // The same density on every quad wholly inside changes the start.
    CHECK(interior_points(make_initial_distribution(tree, spacing, inside).nodes) != p);
  }
  SECTION("on uniform fields the start moves from the patterns' count towards the density") {
    // Squares of side 4, too small for lattice quads, at spacings whose quads fall at different places of
    // the patterns' bands: on average over them the start comes closer to d times the estimate of the part
    // beyond the keep rule's clearance. (On larger flat domains the lattice quads keep the patterns'
    // density.)
    double off = 0.0, off_plain = 0.0;
    for (const double q : {0.40, 0.46, 0.53, 0.61, 0.66}) {
      const int m = static_cast<int>(std::lround(4.0 / q));
      const Geometry g = fixtures::square(4.0, m);
      const GeometryTree tree(g);
      const UniformSpacing spacing(q);
      InitOptions plain{InitMethod::Hybrid, 1, {}};
      InitOptions flat = plain;
      flat.density = density;
      flat.density_where = DensityWhere::Flat;
      const double inner = (4.0 - q) * (4.0 - q) * 2.0 / (std::sqrt(3.0) * q * q);
      const double rf = static_cast<double>(make_initial_distribution(tree, spacing, flat).tree_nodes) / inner;
      const double rs = static_cast<double>(make_initial_distribution(tree, spacing, plain).tree_nodes) / inner;
      WARN("q " << q << ": density where flat " << rf << " x the estimate, patterns " << rs);
      off += std::fabs(rf - density);
      off_plain += std::fabs(rs - density);
    }
    CHECK(off < off_plain);
  }
}

namespace {

// The median over the interior nodes at least 6.5 q from the boundary (in lattice quads, see the first
// test) of the distance to their nearest node: the spacing of the lattice there.
double far_lattice_spacing(const Geometry& g, const NodeSet& nodes, double q) {
  std::vector<double> nearest;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes.kind[i] != NodeKind::Interior || fixtures::brute_distance(g, nodes.x[i]) < 6.5 * q) continue;
    double d = HUGE_VAL;
    for (std::size_t j = 0; j < nodes.size(); ++j)
      if (j != i) d = std::min(d, dist(nodes.x[i], nodes.x[j]));
    nearest.push_back(d);
  }
  if (nearest.empty()) return NAN;
  std::nth_element(nearest.begin(), nearest.begin() + nearest.size() / 2, nearest.end());
  return nearest[nearest.size() / 2];
}

}  // namespace

TEST_CASE("hybrid fill: init.lattice_levels puts the lattice quads on that many levels of q / sqrt(d) per octave",
          "[init][hybrid]") {
  const double density = 1.25;
  const auto density_options = [&](DensityWhere where, int levels) {
    InitOptions options{InitMethod::Hybrid, 1, {}};
    options.density = density;
    options.density_where = where;
    options.lattice_levels = levels;
    return options;
  };
  SECTION("where q is graded, with either density_where") {
    // q grows by 0.02 over the square, 0.14 % across a quad: every quad well inside is flat but none lies on
    // a plateau, and over the square q / sqrt(d) stays nearer one level than any other for 4 and 3 levels.
    for (const double q0 : {0.44, 0.54}) {
      const Geometry g = fixtures::square(20.0, static_cast<int>(std::lround(20.0 / q0)));
      const GeometryTree tree(g);
      const ExpressionSpacing spacing(std::to_string(q0) + " + 0.001 * x");
      for (const DensityWhere where : {DensityWhere::Flat, DensityWhere::Inside}) {
        for (const int levels : {4, 3}) {
          const double h = far_lattice_spacing(
              g, make_initial_distribution(tree, spacing, density_options(where, levels)).nodes, q0);
          const double level = std::round(levels * std::log2(q0 / std::sqrt(density)));
          INFO("q0 " << q0 << ", " << levels << " levels, " << (where == DensityWhere::Flat ? "flat" : "inside"));
          CHECK(std::fabs(h / std::exp2(level / levels) - 1.0) <= 1e-9);
        }
      }
    }
  }
  SECTION("where q is uniform, \"flat\" keeps the patterns' density and \"inside\" takes the levels") {
    int off_grid_without = 0;
    for (const double q : {0.43, 0.50, 0.57}) {
      const Geometry g = fixtures::square(20.0, static_cast<int>(std::lround(20.0 / q)));
      const GeometryTree tree(g);
      const UniformSpacing spacing(q);
      // "flat": a uniform field is one plateau, whose lattice quads keep the patterns' lattice, off the
      // 4-level grid in general, with or without the key.
      const auto flat_points =
          interior_points(make_initial_distribution(tree, spacing, density_options(DensityWhere::Flat, 0)).nodes);
      CHECK(interior_points(make_initial_distribution(tree, spacing, density_options(DensityWhere::Flat, 4)).nodes) ==
            flat_points);
      const double h_flat = far_lattice_spacing(
          g, make_initial_distribution(tree, spacing, density_options(DensityWhere::Flat, 0)).nodes, q);
      const double k = 4.0 * std::log2(h_flat);
      off_grid_without += std::fabs(k - std::round(k)) > 1e-6;
      // "inside": the key's levels, and without it 8 levels per octave.
      for (const int levels : {4, 3, 0}) {
        const double n = levels > 0 ? levels : 8.0;
        const double h = far_lattice_spacing(
            g, make_initial_distribution(tree, spacing, density_options(DensityWhere::Inside, levels)).nodes, q);
        const double level = std::round(n * std::log2(q / std::sqrt(density)));
        INFO("q " << q << ", inside, " << levels << " levels");
        CHECK(std::fabs(h / std::exp2(level / n) - 1.0) <= 1e-9);
      }
    }
    CHECK(off_grid_without > 0);
  }
  SECTION("without a density there is no level to take: the key changes nothing") {
    const Geometry g = fixtures::square(20.0, 40);
    const GeometryTree tree(g);
    const UniformSpacing spacing(0.5);
    InitOptions plain{InitMethod::Hybrid, 1, {}};
    InitOptions levels = plain;
    levels.lattice_levels = 4;
    CHECK(interior_points(make_initial_distribution(tree, spacing, levels).nodes) ==
          interior_points(make_initial_distribution(tree, spacing, plain).nodes));
  }
}

namespace {

// The share of the interior nodes at least `far` from the boundary whose nearest node lies at a spacing of
// the lattice levels 2^(k / levels): the nodes that started on one of the level lattices.
double share_on_levels(const Geometry& g, const NodeSet& nodes, double far, int levels) {
  int on = 0, all = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes.kind[i] != NodeKind::Interior || fixtures::brute_distance(g, nodes.x[i]) < far) continue;
    double d = HUGE_VAL;
    for (std::size_t j = 0; j < nodes.size(); ++j)
      if (j != i) d = std::min(d, dist(nodes.x[i], nodes.x[j]));
    const double k = levels * std::log2(d);
    on += std::fabs(k - std::round(k)) <= 1e-9;
    ++all;
  }
  return all > 0 ? static_cast<double>(on) / all : NAN;
}

}  // namespace

TEST_CASE("hybrid fill: init.hybrid_spread sets how flat q must be around a lattice quad", "[init][hybrid]") {
  // q grows from 0.5 to 0.9 across the square: by about 10 % over a quad and its two neighbours, more than the
  // factor 1.05 allows but within 1.2.
  const Geometry g = fixtures::square(20.0, 30);
  const GeometryTree tree(g);
  const ExpressionSpacing spacing("0.5 + 0.02 * x");
  const auto options = [](double spread) {
    InitOptions o{InitMethod::Hybrid, 1, {}};
    o.density = 1.25;
    o.density_where = DensityWhere::Flat;
    o.lattice_levels = 4;
    o.hybrid_spread = spread;
    return o;
  };
  const double far = 4.0;  // beyond the lattice test's clearance (2 q plus a quad's half-diagonal)
  const double narrow =
      share_on_levels(g, make_initial_distribution(tree, spacing, options(kHybridSpread)).nodes, far, 4);
  const double wide = share_on_levels(g, make_initial_distribution(tree, spacing, options(0.2)).nodes, far, 4);
  INFO("share of far nodes on a level lattice: spread 0.05 " << narrow << ", 0.2 " << wide);
  CHECK(narrow < 0.1);
  CHECK(wide > 0.8);
  SECTION("the default is the factor 1.05, and the key applies without a density too") {
    InitOptions plain{InitMethod::Hybrid, 1, {}};
    CHECK(plain.hybrid_spread == kHybridSpread);
    InitOptions wider = plain;
    wider.hybrid_spread = 0.2;
    CHECK(interior_points(make_initial_distribution(tree, spacing, wider).nodes) !=
          interior_points(make_initial_distribution(tree, spacing, plain).nodes));
  }
}
