// FeatureSize::closest against brute force: the least squared distance, then the lowest segment
// index, with and without a seed segment. The plate's lattice points where two wall segments meet at
// the closest vertex (an exact tie) were answered with the higher index before the search's pruning
// kept a margin; they are checked by name.
#include <catch2/catch.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "closest_hit_check.hpp"
#include "geometry/brute_force_queries.hpp"
#include "geometry/geometry.hpp"
#include "geometry/geometry_files.hpp"
#include "geometry_fixtures.hpp"
#include "geometry/geometry_tree.hpp"
#include "spacing/feature_size.hpp"
#include "spacing/size_sources.hpp"
#include "spacing/spacing_field.hpp"

using namespace pdmesh;
using fixtures::unit;
using pdmesh_test::require_same;

namespace {

// Random points around the geometry, points on segments and vertices, and points of a dyadic lattice
// (as the background tree's corners: exact ties to two segments are common there). Each query is
// asked without a seed and seeded with the previous answer and with a random segment.
void check(const Geometry& g, int queries, std::uint64_t seed) {
  const FeatureSize fs(g);
  std::mt19937_64 rng(seed);
  const Box& e = g.extents;
  int previous = -1;
  for (int i = 0; i < queries; ++i) {
    Vec2 p;
    const Segment& s = g.segments[rng() % g.segments.size()];
    switch (i % 4) {
      case 0:
        p = {e.lo.x - 0.1 * e.width() + 1.2 * e.width() * unit(rng),
             e.lo.y - 0.1 * e.height() + 1.2 * e.height() * unit(rng)};
        break;
      case 1:
        p = (rng() & 1) ? s.a : s.a + unit(rng) * (s.b - s.a);
        break;
      default: {
        const double step = std::ldexp(std::max(e.width(), e.height()), -7);
        p = {e.lo.x + step * std::floor(unit(rng) * 130.0 - 1.0), e.lo.y + step * std::floor(unit(rng) * 130.0 - 1.0)};
      }
    }
    const ClosestHit brute = brute_force::closest_by_square(g, p);
    require_same(fs.closest(p), brute, p);
    require_same(fs.closest(p, previous), brute, p);
    require_same(fs.closest(p, static_cast<int>(rng() % g.segments.size())), brute, p);
    previous = brute.segment;
  }
}

}  // namespace

TEST_CASE("FeatureSize::closest equals brute force, seeded or not", "[spacing][feature]") {
  SECTION("square of four sides") { check(fixtures::square(2.0, 7), 3000, 21); }
  SECTION("plate (corpus)") {
    const Geometry g = read_geometry({std::string(PDMESH_SOURCE_DIR) + "/cases/corpus/plate/plate.poly"}, {});
    check(g, 3000, 22);
    const FeatureSize fs(g);
    // Lattice points of the plate's run where the closest point is a vertex shared by two segments.
    for (const Vec2 p : {Vec2{-0.0625, 5.1597222222222223}, Vec2{5.692708333333333, 2.2256944444444446},
                         Vec2{5.692708333333333, 1.9435763888888893}, Vec2{5.7491319444444446, 1.9435763888888893},
                         Vec2{5.6362847222222223, 2.1128472222222223}}) {
      const ClosestHit brute = brute_force::closest_by_square(g, p);
      require_same(fs.closest(p), brute, p);
      require_same(fs.closest(p, brute.segment + 1), brute, p);
    }
  }
}

namespace {

Geometry gap_geometry(const std::string& name) {
  return read_geometry({std::string(PDMESH_SOURCE_DIR) + "/tests/data/gap/" + name + ".poly"}, {});
}

double source_at(const Geometry& g, Vec2 p, bool final_floor, double floor = 1.0) {
  const GeometryTree tree(g);
  SizeSourceOptions options;
  options.rows_in_gap = 2.0;
  options.input_boundary_floor = floor;
  options.final_floor = final_floor;
  return SizeSources(tree, options).at(p, 10.0);
}

}  // namespace

TEST_CASE("A gap between two loops that never meet gets W / k beside long segments", "[spacing][feature]") {
  // A gap 0.05 wide between the unit square's bottom side (1 long) and a constraint segment or a
  // hole's side (0.8 long): k = 2 spacings of 0.025 across it, at the wall, mid-gap and next to the
  // inner side, when the boundary nodes are placed by the field.
  for (const std::string name : {"constraint_gap", "hole_gap"}) {
    INFO(name);
    const Geometry g = gap_geometry(name);
    for (const Vec2 p : {Vec2{0.5, 0.0}, Vec2{0.5, 0.025}, Vec2{0.3, 0.04}, Vec2{0.8, 0.01}}) {
      INFO("at (" << p.x << ", " << p.y << ")");
      CHECK(source_at(g, p, false) == Approx(0.025).epsilon(1e-9));
      // With the input points as boundary nodes the sources keep to the closest segment's length.
      CHECK(source_at(g, p, true) >= 0.8);
    }
  }
}

TEST_CASE("A gap that narrows to a tip within one loop keeps the sources' floor", "[spacing][feature]") {
  // Near the 11.3 degree corner of the wedge W / k tends to 0; the floor keeps the closest segment's length.
  const Geometry g = gap_geometry("wedge");
  for (const Vec2 p : {Vec2{0.9, 0.005}, Vec2{0.8, 0.02}}) {
    INFO("at (" << p.x << ", " << p.y << ")");
    CHECK(source_at(g, p, false, 0.0) < 0.05);  // the gap is seen
    CHECK(source_at(g, p, false) >= 1.0);
  }
}

TEST_CASE("A strait between two sides of one loop gets W / k beside long segments", "[spacing][feature]") {
  // A channel 0.1 wide between two single segments 10 long, whose ends connect only around a 4 x 4
  // square: k = 2 spacings of 0.05 across it, from mouth to mouth, when the boundary nodes are placed
  // by the field.
  const Geometry g = gap_geometry("strait");
  for (const Vec2 p : {Vec2{9.0, 2.0}, Vec2{4.1, 1.96}, Vec2{6.0, 2.04}, Vec2{13.9, 2.0}, Vec2{11.0, 1.95}}) {
    INFO("at (" << p.x << ", " << p.y << ")");
    CHECK(source_at(g, p, false) == Approx(0.05).epsilon(1e-9));
    // With the input points as boundary nodes the sources keep to the closest segment's length.
    CHECK(source_at(g, p, true) >= 10.0);
  }
}

TEST_CASE("A V inlet of long segments keeps the sources' floor though its sides connect far around too",
          "[spacing][feature]") {
  // The inlet's sides (8.02 long) meet at its 7.2 degree tip: the shorter way between two facing
  // points runs through the tip, however far the other way round the square is.
  const Geometry g = gap_geometry("inlet");
  for (const Vec2 p : {Vec2{5.0, 17.5}, Vec2{5.0, 14.0}, Vec2{5.2, 11.0}, Vec2{4.6, 10.2}}) {
    INFO("at (" << p.x << ", " << p.y << ")");
    CHECK(source_at(g, p, false, 0.0) < 1.0);  // the gap is seen
    CHECK(source_at(g, p, false) >= 8.0);
  }
}

namespace {

// Point sets for the grouped searches, in the order the background field's batches give them (runs
// of nearby points): coarse lattice rows over and around the extents; fine rows around a vertex
// (groups among many close segments); runs of points on one segment and on vertices (distance 0,
// exact ties between the two segments at a vertex); rows far outside (groups whose bound reaches
// far); scattered points (spread-out groups, which fall back to a search per point).
std::vector<Vec2> group_points(const Geometry& g, std::uint64_t seed) {
  const Box& e = g.extents;
  const double w = e.width(), h = e.height();
  std::vector<Vec2> p;
  for (int j = 0; j <= 40; ++j)
    for (int i = 0; i <= 40; ++i)
      p.push_back({e.lo.x - 0.25 * w + 1.5 * w * i / 40.0, e.lo.y - 0.25 * h + 1.5 * h * j / 40.0});
  std::mt19937_64 rng(seed);
  for (int k = 0; k < 4; ++k) {
    const Segment& s = g.segments[rng() % g.segments.size()];
    const double step = s.length / 8.0;
    for (int j = -12; j <= 12; ++j)
      for (int i = -12; i <= 12; ++i) p.push_back({s.a.x + step * i, s.a.y + step * j});
    for (int i = 0; i <= 20; ++i) p.push_back(s.a + (i / 20.0) * (s.b - s.a));
  }
  for (int k = 0; k < 40; ++k) p.push_back(g.segments[rng() % g.segments.size()].a);
  for (int j = 0; j <= 6; ++j)
    for (int i = 0; i <= 30; ++i) p.push_back({e.lo.x + 8.0 * w + 0.2 * w * i, e.lo.y - 5.0 * h + 0.3 * h * j});
  for (int i = 0; i < 300; ++i)
    p.push_back({e.lo.x - 0.5 * w + 2.0 * w * unit(rng), e.lo.y - 0.5 * h + 2.0 * h * unit(rng)});
  return p;
}

// A rectangle with a hole on one side of x = 0 and an embedded constraint on the other (side = +1: the
// hole at x < 0), placed symmetrically: from the points of that line below them, the hole's corner
// (-0.5 side, 1) and the constraint's end (0.5 side, 1) are the gap's far side at exactly the same
// distance. The constraint meets the rectangle's side, so its loop touches the rectangle's and the
// hole's does not: the two candidates differ in width()'s `apart`.
Geometry tie_geometry(double side) {
  RawGeometry raw;
  raw.curves.push_back(fixtures::raw_polyline(fixtures::rectangle({-3, -1}, {3, 3}, 4, true), "outer"));
  raw.curves.push_back(fixtures::raw_polyline(
      fixtures::rectangle({side < 0 ? 0.5 : -2.0, 1.0}, {side < 0 ? 2.0 : -0.5, 2.0}, 3, false), "hole"));
  RawCurve constraint = fixtures::raw_polyline({{0.5 * side, 1.0}, {3.0 * side, 1.0}}, "constraint");
  constraint.constraint = true;
  raw.curves.push_back(constraint);
  return build_geometry(raw);
}

// The geometries of the grouped-search tests, through build_geometry (FeatureSize needs the loops).
std::vector<std::pair<std::string, Geometry>> group_geometries() {
  std::vector<std::pair<std::string, Geometry>> out;
  out.emplace_back("square of four sides", fixtures::square(2.0, 7));
  for (const std::string name : {"constraint_gap", "hole_gap", "wedge", "strait", "inlet"})
    out.emplace_back(name, read_geometry({std::string(PDMESH_SOURCE_DIR) + "/tests/data/gap/" + name + ".poly"}, {}));
  out.emplace_back("plate", read_geometry({std::string(PDMESH_SOURCE_DIR) + "/cases/corpus/plate/plate.poly"}, {}));
  // An annulus of fine circles (a gap all round, the groups' bounds reaching across it).
  out.emplace_back("annulus", build_geometry({fixtures::circle_curve(1.0, 400, 0.0, "inner"),
                                              fixtures::circle_curve(1.3, 300, 0.1, "outer")}));
  // A triangle: a curve of three segments (one leaf).
  out.emplace_back("triangle", build_geometry({fixtures::raw_polyline({{0, 0}, {1, 0}, {0.3, 0.8}, {0, 0}}, "t")}));
  out.emplace_back("tie", tie_geometry(1.0));
  out.emplace_back("tie mirrored", tie_geometry(-1.0));
  out.emplace_back("30P30N", read_geometry({std::string(PDMESH_SOURCE_DIR) + "/cases/30p30n/airfoil.crv",
                                            std::string(PDMESH_SOURCE_DIR) + "/cases/30p30n/farfield.crv"},
                                           {}));
  return out;
}

}  // namespace

TEST_CASE("FeatureSize::closest_many (grouped searches) equals closest point by point", "[spacing][feature]") {
  for (const auto& [name, g] : group_geometries()) {
    INFO(name);
    const FeatureSize fs(g);
    std::vector<Vec2> p = group_points(g, 41);
    // The line of ties.
    if (name.starts_with("tie"))
      for (int i = 0; i <= 40; ++i) p.push_back({0.0, -0.95 + 1.9 * i / 40.0});
    std::vector<ClosestHit> hit(p.size());
    FeatureSize::SearchSeed seed;
    // In batches of uneven lengths (a batch's last group is short).
    for (std::size_t first = 0; first < p.size(); first += 61)
      fs.closest_many(&p[first], std::min<std::size_t>(61, p.size() - first), &hit[first], seed);
    REQUIRE(seed.segment == hit.back().segment);
    for (std::size_t i = 0; i < p.size(); ++i) {
      INFO("point " << i);
      require_same(hit[i], fs.closest(p[i]), p[i]);
      require_same(hit[i], brute_force::closest_by_square(g, p[i]), p[i]);
    }
  }
}

TEST_CASE("FeatureSize::width_many (grouped searches) equals width point by point", "[spacing][feature]") {
  for (const auto& [name, g] : group_geometries()) {
    INFO(name);
    const FeatureSize fs(g);
    const GeometryTree tree(g);
    std::vector<Vec2> p = group_points(g, 42);
    if (name.starts_with("tie"))
      for (int i = 0; i <= 40; ++i) p.push_back({0.0, -0.95 + 1.9 * i / 40.0});
    const double size = std::max(g.extents.width(), g.extents.height());
    int found_any = 0;
    // Search radii from a few segment lengths to the whole geometry and beyond (+inf: no bound), and
    // queries with no search (no radius, no closest segment) among them.
    for (const double reach : {0.0, 0.01, 0.1, 0.5, 2.0, std::numeric_limits<double>::infinity()}) {
      INFO("max width " << reach << " x " << size);
      std::vector<FeatureSize::WidthQuery> q(p.size());
      for (std::size_t i = 0; i < p.size(); ++i) {
        q[i].x = p[i];
        q[i].nearest = fs.closest(p[i]);
        q[i].inside = i % 7 == 3 ? !tree.inside(p[i]) : tree.inside(p[i]);
        q[i].max_width = i % 11 == 5 ? 0.0 : reach * size;
        if (i % 13 == 7) q[i].nearest.segment = -1;
      }
      std::vector<double> width(p.size());
      std::vector<std::uint8_t> apart(p.size());
      for (std::size_t first = 0; first < p.size(); first += 61) {
        const std::size_t n = std::min<std::size_t>(61, p.size() - first);
        bool a[61];
        fs.width_many(&q[first], n, &width[first], a);
        for (std::size_t i = 0; i < n; ++i) apart[first + i] = a[i] ? 1 : 0;
      }
      int found = 0;
      for (std::size_t i = 0; i < p.size(); ++i) {
        bool a = false;
        const double w = fs.width(q[i].x, q[i].nearest, q[i].inside, q[i].max_width, &a);
        INFO("point " << i << " (" << p[i].x << ", " << p[i].y << "): width " << width[i] << ", point by point " << w);
        REQUIRE(std::bit_cast<std::uint64_t>(width[i]) == std::bit_cast<std::uint64_t>(w));
        REQUIRE(apart[i] == (a ? 1 : 0));
        if (std::isfinite(w)) ++found;
      }
      found_any += found;
    }
    // Gaps are found in every geometry but the convex ones, so the comparison covers found widths.
    if (name != "square of four sides") CHECK(found_any > 100);
  }
}

TEST_CASE("SizeSources::at_many equals at point by point", "[spacing][feature]") {
  for (const auto& [name, g] : group_geometries()) {
    INFO(name);
    const GeometryTree tree(g);
    const std::vector<Vec2> p = group_points(g, 43);
    const double size = std::max(g.extents.width(), g.extents.height());
    std::vector<double> limit(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) limit[i] = size * (0.01 + 0.3 * static_cast<double>(i % 17) / 17.0);
    for (int variant = 0; variant < 3; ++variant) {
      SizeSourceOptions options;
      options.rows_in_gap = variant == 1 ? 0.0 : 2.0;
      options.curvature_angle = variant == 0 ? 0.0 : 10.0;
      options.input_boundary_floor = variant == 2 ? 0.5 : 0.0;
      options.final_floor = variant != 2;
      options.scale = variant == 2 ? 1.1 : 1.0;
      INFO("variant " << variant);
      const SizeSources sources(tree, options);
      std::vector<double> q(p.size());
      FeatureSize::SearchSeed seed;
      for (std::size_t first = 0; first < p.size(); first += 64)
        sources.at_many(&p[first], &limit[first], std::min<std::size_t>(64, p.size() - first), &q[first], seed);
      for (std::size_t i = 0; i < p.size(); ++i) {
        const double one = sources.at(p[i], limit[i]);
        INFO("point " << i << " (" << p[i].x << ", " << p[i].y << "): " << q[i] << ", point by point " << one);
        REQUIRE(std::bit_cast<std::uint64_t>(q[i]) == std::bit_cast<std::uint64_t>(one));
      }
    }
  }
}
