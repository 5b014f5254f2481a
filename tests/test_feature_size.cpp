// FeatureSize::closest against brute force: the least squared distance, then the lowest segment
// index, with and without a seed segment. The plate's lattice points where two wall segments meet at
// the closest vertex (an exact tie) were answered with the higher index before the search's pruning
// kept a margin; they are checked by name.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "closest_hit_check.hpp"
#include "geometry/brute_force_queries.hpp"
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
