// CurveScan (the vectorized closest-segment pass of small curves) against the brute-force oracle:
// the same segment, distance, point and parameter bit for bit, at points on segments and vertices, on
// symmetry lines (exact ties, decided by the lowest index), next to tiny features and far away; and
// which curves it takes (the others stay with the quadtree, whose answers must not change either).
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "closest_hit_check.hpp"
#include "geometry/brute_force_queries.hpp"
#include "geometry/curve_scan.hpp"
#include "geometry/geometry_tree.hpp"
#include "geometry_fixtures.hpp"

using namespace pdmesh;
using fixtures::unit;
using pdmesh_test::require_same;

namespace {

std::vector<std::vector<int>> ids_by_curve(const Geometry& g) {
  std::vector<std::vector<int>> ids(g.curves.size());
  for (std::size_t i = 0; i < g.segments.size(); ++i)
    ids[static_cast<std::size_t>(g.segments[i].curve)].push_back(static_cast<int>(i));
  return ids;
}

// Points of every awkward kind for a geometry (seeded).
Vec2 awkward_point(const Geometry& g, std::mt19937_64& rng) {
  const Box& e = g.extents;
  const Segment& s = g.segments[rng() % g.segments.size()];
  const double t = unit(rng);
  switch (rng() % 7) {
    case 0:
      return {e.lo.x - 0.2 * e.width() + 1.4 * e.width() * unit(rng),
              e.lo.y - 0.2 * e.height() + 1.4 * e.height() * unit(rng)};
    case 1:
      return (rng() & 1) ? s.a : s.b;
    case 2:
      return s.a + t * (s.b - s.a);
    case 3:  // the symmetry lines of the extents: exact ties on symmetric shapes
      return (rng() & 1) ? Vec2{e.centre().x, e.lo.y + e.height() * unit(rng)}
                         : Vec2{e.lo.x + e.width() * unit(rng), e.centre().y};
    case 4:
      return s.a + Vec2{(unit(rng) - 0.5) * 1e-9 * e.diagonal(), (unit(rng) - 0.5) * 1e-9 * e.diagonal()};
    case 5:
      return s.a + Vec2{(unit(rng) - 0.5) * 4 * s.length, (unit(rng) - 0.5) * 4 * s.length};
    default:
      return {(unit(rng) - 0.5) * 2e6 * e.diagonal(), (unit(rng) - 0.5) * 2e6 * e.diagonal()};
  }
}

void check_geometry(const Geometry& g, int queries, std::uint64_t seed) {
  const CurveScan scan(g, ids_by_curve(g));
  const int curves = static_cast<int>(g.curves.size());
  std::mt19937_64 rng(seed);
  std::vector<ClosestHit> hits(g.curves.size());
  for (int i = 0; i < queries; ++i) {
    const Vec2 p = i == 0 ? g.extents.centre() : awkward_point(g, rng);
    scan.closest(p, hits);
    for (int c = 0; c < curves; ++c)
      if (scan.covers(c)) require_same(hits[static_cast<std::size_t>(c)], brute_force::closest_on_curve(g, p, c), p, c);
  }
}

}  // namespace

TEST_CASE("CurveScan equals brute force on every covered curve", "[tree][scan]") {
  SECTION("circle in circle") { check_geometry(fixtures::circle_in_circle(), 4000, 11); }
  SECTION("square with hole (exact ties on the symmetry lines)") {
    check_geometry(fixtures::square_with_hole(), 4000, 12);
  }
  SECTION("multiscale (a 0.01 triangle beside a 1000 square)") { check_geometry(fixtures::multiscale(), 4000, 13); }
  SECTION("square of four sides, 7 segments each") { check_geometry(fixtures::square(2.0, 7), 4000, 14); }
  SECTION("a curve of kMaxSegments segments") {
    check_geometry(fixtures::jagged_polygon(CurveScan::kMaxSegments, 3), 2000, 15);
  }
  // The scan measures only the chunks (kWidth segments) whose box can hold the least: these put
  // exact ties in chunks far apart, and every chunk about as near to the centre.
  SECTION("one curve around a square, kMaxSegments segments: ties four sides apart") {
    check_geometry(fixtures::make_geometry({fixtures::rectangle({-1, -1}, {1, 1}, CurveScan::kMaxSegments / 4, true)}),
                   2000, 16);
  }
  SECTION("a regular polygon of kMaxSegments segments") {
    const double pi = std::acos(-1.0);
    check_geometry(
        fixtures::make_geometry({fixtures::arc_points({0, 0}, 1, 0, 2 * pi, CurveScan::kMaxSegments, {1, 0}, {1, 0})}),
        2000, 17);
  }
}

TEST_CASE("CurveScan: the centre of a square is a tie of four sides, the lowest index wins", "[tree][scan]") {
  const Geometry g = fixtures::make_geometry({fixtures::rectangle({-1, -1}, {1, 1}, 1, true)});
  const CurveScan scan(g, ids_by_curve(g));
  REQUIRE(scan.covers(0));
  std::vector<ClosestHit> hits(1);
  scan.closest({0.0, 0.0}, hits);
  CHECK(hits[0].segment == 0);
  CHECK(hits[0].distance == 1.0);
  require_same(hits[0], brute_force::closest_on_curve(g, {0.0, 0.0}, 0), {0.0, 0.0}, 0);
}

TEST_CASE("CurveScan: which curves it takes", "[tree][scan]") {
  // A point segment (a == b) is scanned (its parameter is 0); a segment whose length squared is
  // subnormal is not (1 / |b - a|^2 would overflow): the tree answers for its curve.
  const Geometry g =
      fixtures::make_geometry({{{0, 0}, {1, 0}, {1, 0}, {1, 1}}, {{0, 5}, {1e-160, 5}}, {{0, 3}, {2, 3}}});
  const std::vector<std::vector<int>> ids = ids_by_curve(g);
  const CurveScan scan(g, ids);
  CHECK(scan.covers(0));
  CHECK_FALSE(scan.covers(1));
  CHECK(scan.covers(2));
  std::vector<ClosestHit> hits(3);
  for (const Vec2 p : {Vec2{1, 0}, Vec2{1.5, 0.2}, Vec2{0.5, -1}, Vec2{3, 3}}) {
    scan.closest(p, hits);
    for (const int c : {0, 2})
      require_same(hits[static_cast<std::size_t>(c)], brute_force::closest_on_curve(g, p, c), p, c);
  }
  // More segments than kMaxSegments: the tree's.
  const Geometry big = fixtures::jagged_polygon(CurveScan::kMaxSegments + 1, 5);
  CHECK_FALSE(CurveScan(big, ids_by_curve(big)).covers(0));
  const Geometry edge = fixtures::jagged_polygon(CurveScan::kMaxSegments, 5);
  CHECK(CurveScan(edge, ids_by_curve(edge)).covers(0));
}

TEST_CASE("GeometryTree: per-curve queries beyond the scan's coordinate range still equal brute force",
          "[tree][scan]") {
  const Geometry g = fixtures::circle_in_circle();
  const GeometryTree tree(g);
  std::vector<ClosestHit> per_tree, per_near, per_brute;
  for (const Vec2 p : {Vec2{1e120, 3.0}, Vec2{-2.0, -1e101}, Vec2{1e99, 1e99}, Vec2{0.5, 0.25}}) {
    tree.closest_per_curve(p, per_tree);
    tree.closest_per_curve_near(p, per_near);
    brute_force::closest_per_curve(g, p, per_brute);
    for (std::size_t c = 0; c < per_brute.size(); ++c) {
      require_same(per_tree[c], per_brute[c], p, static_cast<int>(c));
      require_same(per_near[c], per_brute[c], p, static_cast<int>(c));
    }
  }
}

TEST_CASE("GeometryTree: the closest segment by its square, from the per-curve searches", "[tree][scan]") {
  // A jagged curve of 600 segments stays on its tree beside small curves: where it is as near as the
  // best of them the answer is left undetermined, elsewhere it must be brute force's.
  Geometry mixed = fixtures::jagged_polygon(600, 9);
  const Geometry square = fixtures::make_geometry({fixtures::rectangle({3, -1}, {5, 1}, 3, true)});
  for (Segment s : square.segments) {
    s.curve = 1;
    mixed.segments.push_back(s);
  }
  mixed.curves.push_back(square.curves[0]);
  mixed.extents.add(square.extents.lo);
  mixed.extents.add(square.extents.hi);
  const std::vector<std::pair<std::string, Geometry>> geometries = {{"circle in circle", fixtures::circle_in_circle()},
                                                                    {"square with hole", fixtures::square_with_hole()},
                                                                    {"multiscale", fixtures::multiscale()},
                                                                    {"jagged beside a square", mixed}};
  for (const auto& [name, g] : geometries) {
    INFO(name);
    const GeometryTree tree(g);
    std::mt19937_64 rng(31);
    std::vector<ClosestHit> hits;
    int determined = 0;
    const int queries = 3000;
    for (int i = 0; i < queries; ++i) {
      const Vec2 p = i == 0 ? g.extents.centre() : awkward_point(g, rng);
      ClosestHit by_square;
      tree.closest_per_curve_near(p, hits, &by_square);
      if (by_square.segment < 0) continue;
      ++determined;
      require_same(by_square, brute_force::closest_by_square(g, p), p, -1);
    }
    // Undetermined only beside a curve on its tree (the mixed geometry's jagged curve).
    if (name != "jagged beside a square")
      CHECK(determined == queries);
    else
      CHECK(determined > queries / 10);
  }
}
