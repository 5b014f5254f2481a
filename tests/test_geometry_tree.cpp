// GeometryTree against the brute-force oracle (thousands of seeded queries per geometry, including
// points exactly on segments, at vertices, on vertex rows and far away), and the oracle itself
// against closed forms.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "closest_hit_check.hpp"
#include "core/errors.hpp"
#include "geometry/brute_force_queries.hpp"
#include "geometry/geometry_tree.hpp"
#include "geometry_fixtures.hpp"

using namespace pdmesh;
using fixtures::unit;
using pdmesh_test::require_same;

namespace {

struct Named {
  std::string name;
  Geometry geometry;
};

std::vector<Named> all_geometries() {
  return {{"circle in circle", fixtures::circle_in_circle()},
          {"square with hole", fixtures::square_with_hole()},
          {"jagged 1501", fixtures::jagged_polygon(1501, 7)},
          {"multiscale", fixtures::multiscale()}};
}

// Query points of every awkward kind, seeded: uniform around the extents, exactly at vertices,
// on segments (exactly where the segment is axis-aligned), on the horizontal row of a vertex
// (the crossing-number corner case), just off vertices, near the tiny features, and far away.
Vec2 query_point(const Geometry& g, std::mt19937_64& rng) {
  const Box& e = g.extents;
  const double diag = e.diagonal();
  const Segment& s = g.segments[rng() % g.segments.size()];
  const double t = unit(rng);
  switch (rng() % 8) {
    case 0:
    case 1:
      return {e.lo.x - 0.2 * e.width() + 1.4 * e.width() * unit(rng),
              e.lo.y - 0.2 * e.height() + 1.4 * e.height() * unit(rng)};
    case 2:
      return (rng() & 1) ? s.a : s.b;
    case 3:
      if (s.a.y == s.b.y) return {s.a.x + t * (s.b.x - s.a.x), s.a.y};
      if (s.a.x == s.b.x) return {s.a.x, s.a.y + t * (s.b.y - s.a.y)};
      return s.a + t * (s.b - s.a);
    case 4:
      return {e.lo.x - 0.2 * e.width() + 1.4 * e.width() * unit(rng), s.a.y};
    case 5:
      return s.a + Vec2{(unit(rng) - 0.5) * 1e-9 * diag, (unit(rng) - 0.5) * 1e-9 * diag};
    case 6:
      return s.a + Vec2{(unit(rng) - 0.5) * 4 * s.length, (unit(rng) - 0.5) * 4 * s.length};
    default:
      return {(unit(rng) - 0.5) * 2e6 * diag, (unit(rng) - 0.5) * 2e6 * diag};
  }
}

}  // namespace

TEST_CASE("GeometryTree queries equal brute force", "[tree]") {
  for (const Named& n : all_geometries()) {
    SECTION(n.name) {
      const Geometry& g = n.geometry;
      const GeometryTree tree(g);
      const int curves = static_cast<int>(g.curves.size());
      std::mt19937_64 rng(20240607);
      std::vector<ClosestHit> per_tree, per_brute, per_near;
      int inside_count = 0, crossing_count = 0;
      for (int i = 0; i < 4000; ++i) {
        const Vec2 p = query_point(g, rng);
        require_same(tree.closest(p), brute_force::closest(g, p), p);
        const int c = static_cast<int>(rng() % curves);
        require_same(tree.closest_on_curve(p, c), brute_force::closest_on_curve(g, p, c), p);
        tree.closest_per_curve(p, per_tree);
        brute_force::closest_per_curve(g, p, per_brute);
        REQUIRE(per_tree.size() == per_brute.size());
        for (int k = 0; k < curves; ++k) require_same(per_tree[k], per_brute[k], p);
        // The seeded search: per_near holds the previous query's hits (a point far or near), and now
        // and then a seed that is no answer of this tree (another curve's segment, out of range).
        if (i % 7 == 3 && curves > 1) per_near[0].segment = per_near[1].segment;
        if (i % 11 == 5 && !per_near.empty()) per_near.back().segment = static_cast<int>(g.segments.size()) + 3;
        tree.closest_per_curve_near(p, per_near);
        REQUIRE(per_near.size() == per_brute.size());
        for (int k = 0; k < curves; ++k) require_same(per_near[k], per_brute[k], p);
        const bool in = tree.inside(p);
        INFO("inside query (" << p.x << ", " << p.y << ")");
        REQUIRE(in == brute_force::inside(g, p));
        inside_count += in;
        const Vec2 q = (rng() & 1) ? query_point(g, rng) : p + (0.5 + unit(rng)) * (query_point(g, rng) - p) * 0.01;
        const bool crosses = tree.crosses_boundary(p, q);
        INFO("move to (" << q.x << ", " << q.y << ")");
        REQUIRE(crosses == brute_force::crosses_boundary(g, p, q));
        crossing_count += crosses;
      }
      // The mix exercises both answers of each yes/no query.
      CHECK(inside_count > 400);
      CHECK(inside_count < 3600);
      CHECK(crossing_count > 400);
      CHECK(crossing_count < 3600);
    }
  }
}

TEST_CASE("GeometryTree: closest_on_curve_many equals brute force per point, whatever its seed", "[tree]") {
  for (const Named& n : all_geometries()) {
    SECTION(n.name) {
      const Geometry& g = n.geometry;
      const GeometryTree tree(g);
      REQUIRE(tree.curve_count() == static_cast<int>(g.curves.size()));
      std::mt19937_64 rng(20261204);
      // Runs of nearby points (the seeds are the answers) and scattered ones; points on vertices too.
      std::vector<Vec2> p(300);
      for (std::size_t i = 0; i < p.size(); ++i) {
        p[i] = i % 50 < 25 && i > 0 ? p[i - 1] + 1e-3 * (query_point(g, rng) - p[i - 1]) : query_point(g, rng);
        if (i % 23 == 4) p[i] = g.segments[rng() % g.segments.size()].b;
      }
      for (int c = 0; c < tree.curve_count(); ++c) {
        std::vector<double> distance(p.size());
        std::vector<int> segment(p.size());
        // Seeds: none, another curve's segment, one out of range, a segment of this curve.
        for (const int seed0 :
             {-1, static_cast<int>(rng() % g.segments.size()), static_cast<int>(g.segments.size()) + 3}) {
          int seed = seed0;
          tree.closest_on_curve_many(p.data(), p.size(), c, distance.data(), segment.data(), &seed);
          for (std::size_t i = 0; i < p.size(); ++i) {
            const ClosestHit b = brute_force::closest_on_curve(g, p[i], c);
            INFO("curve " << c << ", point " << i << " (" << p[i].x << ", " << p[i].y << "), seed " << seed0);
            REQUIRE(segment[i] == b.segment);
            REQUIRE(distance[i] == b.distance);
          }
          CHECK(seed == segment.back());
        }
      }
      int seed = -1;
      double d = 0.0;
      int s = 0;
      CHECK_THROWS_AS(tree.closest_on_curve_many(p.data(), 1, tree.curve_count(), &d, &s, &seed), std::out_of_range);
    }
  }
}

TEST_CASE("GeometryTree: closest_on_curve_many over lattice rows (grouped searches) equals brute force", "[tree]") {
  // Runs of lattice points, as the background field's batches give them: a group of a few nearby
  // points shares one descent of a curve's tree, and a spread-out group falls back to a search per
  // point. The curves: fine arcs (trees of many levels) with vertices on the lattice's rows, a square
  // whose sides meet at lattice points (ties between two segments along the diagonals), a short
  // polyline of a few segments (a tree of one leaf), a wave of 300 segments and a spiral (trees that
  // are not ring-like: the grouped searches), and the fixtures' geometries.
  const double pi = std::acos(-1.0);
  std::vector<Vec2> wave, spiral;
  for (int i = 0; i <= 300; ++i) wave.push_back({-1.5 + 0.01 * i, -1.6 + 0.1 * std::sin(8.0 * (-1.5 + 0.01 * i))});
  for (int i = 0; i <= 240; ++i) {
    const double a = 6.0 * pi * i / 240.0;
    spiral.push_back({2.5 + 0.02 * a * std::cos(a), 0.02 * a * std::sin(a)});
  }
  std::vector<Geometry> geometries = {
      fixtures::make_geometry({fixtures::arc_points({0.0, 0.0}, 1.0, 0.0, 2.0 * pi, 400, {1.0, 0.0}, {1.0, 0.0}),
                               fixtures::rectangle({-0.25, -0.25}, {0.25, 0.25}, 40, false),
                               {{1.5, 1.5}, {1.75, 1.5}, {1.75, 1.75}, {1.5, 1.75}},
                               wave,
                               spiral}),
      fixtures::circle_in_circle(), fixtures::jagged_polygon(1501, 7), fixtures::multiscale()};
  for (std::size_t k = 0; k < geometries.size(); ++k) {
    const Geometry& g = geometries[k];
    const GeometryTree tree(g);
    const Box& e = g.extents;
    std::vector<Vec2> p;
    // Coarse rows over a margin around the extents, then fine rows near each curve's first vertex
    // (groups among many close segments), then scattered points.
    for (int j = 0; j <= 40; ++j)
      for (int i = 0; i <= 40; ++i)
        p.push_back({e.lo.x - 0.25 * e.width() + 1.5 * e.width() * i / 40.0,
                     e.lo.y - 0.25 * e.height() + 1.5 * e.height() * j / 40.0});
    for (std::size_t c = 0; c < g.curves.size(); ++c) {
      const Segment* first = nullptr;
      for (const Segment& sg : g.segments)
        if (sg.curve == static_cast<int>(c) && !first) first = &sg;
      if (!first) continue;
      const double h = first->length / 8.0;
      for (int j = -16; j <= 16; ++j)
        for (int i = -16; i <= 16; ++i) p.push_back({first->a.x + h * i, first->a.y + h * j});
    }
    std::mt19937_64 rng(20261205);
    for (int i = 0; i < 200; ++i) p.push_back(query_point(g, rng));
    for (int c = 0; c < tree.curve_count(); ++c) {
      std::vector<double> distance(p.size());
      std::vector<int> segment(p.size());
      int seed = -1;
      // In batches of uneven lengths (a batch's last group is short).
      for (std::size_t first = 0; first < p.size(); first += 61) {
        const std::size_t n = std::min<std::size_t>(61, p.size() - first);
        tree.closest_on_curve_many(&p[first], n, c, &distance[first], &segment[first], &seed);
      }
      for (std::size_t i = 0; i < p.size(); ++i) {
        const ClosestHit b = brute_force::closest_on_curve(g, p[i], c);
        INFO("geometry " << k << ", curve " << c << ", point " << i << " (" << p[i].x << ", " << p[i].y << ")");
        REQUIRE(segment[i] == b.segment);
        REQUIRE(distance[i] == b.distance);
      }
    }
  }
}

TEST_CASE("GeometryTree: a curve around its queries (the sector bounds) gives brute force's answers", "[tree]") {
  // A far-field circle of 71 segments (one curve, and as two halves), off the origin, queried near its
  // centre, exactly at it (every segment nearly tied: the lowest index among the nearest must win),
  // along the rays through its vertices and out to the circle itself.
  const double pi = std::acos(-1.0);
  const Vec2 c{3.7, -1.2};
  const double r = 20.0;
  const auto circle = fixtures::arc_points(c, r, 0.0, 2.0 * pi, 71, {c.x + r, c.y}, {c.x + r, c.y});
  const std::vector<Vec2> upper(circle.begin(), circle.begin() + 36), lower(circle.begin() + 35, circle.end());
  for (const bool halves : {false, true}) {
    const Geometry g = halves ? fixtures::make_geometry({upper, lower}) : fixtures::make_geometry({circle});
    const GeometryTree tree(g);
    std::mt19937_64 rng(71);
    std::vector<Vec2> p = {c};
    for (int i = 0; i < 3000; ++i) {
      const double a = 2.0 * pi * unit(rng);
      const double rho = i % 3 == 0 ? 1e-9 * unit(rng) : i % 3 == 1 ? 2.0 * unit(rng) : r * unit(rng);
      p.push_back({c.x + rho * std::cos(a), c.y + rho * std::sin(a)});
    }
    for (std::size_t k = 0; k + 1 < circle.size(); k += 5)
      for (const double f : {1e-6, 0.1, 0.5, 0.999}) p.push_back(c + f * (circle[k] - c));
    std::vector<ClosestHit> per_curve;
    for (const Vec2 q : p) {
      tree.closest_per_curve(q, per_curve);
      for (int k = 0; k < tree.curve_count(); ++k)
        require_same(per_curve[static_cast<std::size_t>(k)], brute_force::closest_on_curve(g, q, k), q);
    }
  }
}

TEST_CASE("GeometryTree: every point on the boundary is inside", "[tree]") {
  for (const Named& n : all_geometries()) {
    const Geometry& g = n.geometry;
    const GeometryTree tree(g);
    INFO(n.name);
    for (std::size_t i = 0; i < g.segments.size(); ++i) {
      const Segment& s = g.segments[i];
      REQUIRE(tree.inside(s.a));
      REQUIRE(tree.inside(s.b));
      REQUIRE(tree.closest(s.a).distance == 0.0);
      if (s.a.y == s.b.y || s.a.x == s.b.x) {
        const Vec2 mid = 0.5 * (s.a + s.b);  // exact for axis-aligned segments
        REQUIRE(tree.inside(mid));
        REQUIRE(tree.closest(mid).distance == 0.0);
      }
    }
  }
}

TEST_CASE("Brute force matches closed forms on the square with a hole", "[tree]") {
  const Geometry g = fixtures::square_with_hole();
  const GeometryTree tree(g);
  std::mt19937_64 rng(42);
  for (int i = 0; i < 3000; ++i) {
    // Coordinates on a 1/1024 grid offset by 1/2048 never lie on the boundary lines 0, 1.5, 2.5, 4.
    const Vec2 p{-1 + (static_cast<int>(rng() % 6144) + 0.5) / 1024.0,
                 -1 + (static_cast<int>(rng() % 6144) + 0.5) / 1024.0};
    const bool in_outer = p.x > 0 && p.x < 4 && p.y > 0 && p.y < 4;
    const bool in_hole = p.x > 1.5 && p.x < 2.5 && p.y > 1.5 && p.y < 2.5;
    INFO("p = (" << p.x << ", " << p.y << ")");
    REQUIRE(brute_force::inside(g, p) == (in_outer && !in_hole));
    // Distance to the outer square boundary (point inside or outside it), and to the hole.
    const auto box_boundary_distance = [](Vec2 q, double lo, double hi) {
      const double dx = std::fmax(std::fmax(lo - q.x, q.x - hi), 0.0),
                   dy = std::fmax(std::fmax(lo - q.y, q.y - hi), 0.0);
      if (dx > 0 || dy > 0) return std::hypot(dx, dy);
      return std::fmin(std::fmin(q.x - lo, hi - q.x), std::fmin(q.y - lo, hi - q.y));
    };
    const double expected = std::fmin(box_boundary_distance(p, 0, 4), box_boundary_distance(p, 1.5, 2.5));
    REQUIRE(brute_force::closest(g, p).distance == Approx(expected).epsilon(1e-14));
    REQUIRE(brute_force::closest_on_curve(g, p, 1).distance ==
            Approx(box_boundary_distance(p, 1.5, 2.5)).epsilon(1e-14));
  }
}

TEST_CASE("Crossing number counts a vertex on the ray once", "[tree]") {
  // Diamond: the ray from the centre passes exactly through the right vertex (1, 0), and the ray from
  // (-2, 0) passes through both side vertices: exactly once each.
  const Geometry g = fixtures::make_geometry({{{1, 0}, {0, 1}, {-1, 0}, {0, -1}, {1, 0}}});
  const GeometryTree tree(g);
  CHECK(tree.inside({0, 0}));
  CHECK(brute_force::inside(g, {0, 0}));
  CHECK_FALSE(tree.inside({-2, 0}));
  CHECK_FALSE(tree.inside({2, 0}));
  CHECK(tree.inside({0.5, 0.5}));  // on an edge
  CHECK(tree.inside({-1, 0}));     // a vertex
  CHECK_FALSE(tree.inside({0.5, 0.5 + 1e-16}));
  // A horizontal edge on the ray row: the U-shape (0,0)-(3,0)-(3,2)-(2,2)-(2,1)-(1,1)-(1,2)-(0,2).
  const Geometry u =
      fixtures::make_geometry({{{0, 0}, {3, 0}, {3, 2}, {2, 2}, {2, 1}, {1, 1}, {1, 2}, {0, 2}, {0, 0}}});
  const GeometryTree ut(u);
  CHECK(ut.inside({0.5, 1}));
  CHECK(ut.inside({1.5, 1}));  // on the horizontal edge
  CHECK_FALSE(ut.inside({1.5, 1.5}));
  CHECK(ut.inside({2.5, 1}));
  CHECK_FALSE(ut.inside({-0.5, 1}));
  CHECK(ut.inside({0.5, 2}));  // on the top edge
  CHECK_FALSE(ut.inside({1.5, 2}));
}

TEST_CASE("crosses_boundary by hand", "[tree]") {
  const Geometry g = fixtures::square_with_hole();  // [0,4]^2 minus [1.5,2.5]^2
  const GeometryTree tree(g);
  CHECK_FALSE(tree.crosses_boundary({0.5, 0.5}, {1.0, 1.0}));
  CHECK(tree.crosses_boundary({0.5, 0.5}, {-1.0, 0.5}));       // leaves through the outer square
  CHECK(tree.crosses_boundary({0.5, 0.5}, {0.0, 0.5}));        // ends on the boundary: touches
  CHECK(tree.crosses_boundary({1.0, 2.0}, {3.0, 2.0}));        // through the hole
  CHECK(tree.crosses_boundary({1.0, 1.0}, {3.0, 3.0}));        // through the hole's corners
  CHECK(tree.crosses_boundary({1.0, 1.5}, {2.0, 1.5}));        // along the hole's edge
  CHECK_FALSE(tree.crosses_boundary({0.0, 0.5}, {0.5, 0.5}));  // starts on the boundary, moves in
  CHECK_FALSE(tree.crosses_boundary({0.0, 0.0}, {0.5, 0.5}));  // starts at a corner, moves in
  CHECK(tree.crosses_boundary({0.0, 0.5}, {0.0, 0.7}));        // slides along the boundary
  // Leaves straight out from a boundary point: it meets the boundary only at a, which is allowed;
  // callers detect this by inside(b).
  CHECK_FALSE(tree.crosses_boundary({0.0, 0.5}, {-0.5, 0.5}));
  CHECK_FALSE(tree.inside({-0.5, 0.5}));
  CHECK_FALSE(tree.crosses_boundary({0.5, 0.5}, {0.5, 0.5}));  // no move
  CHECK_FALSE(tree.crosses_boundary({0.0, 4.0}, {0.0, 5.0}));  // from the corner away along the side's line
  CHECK(tree.crosses_boundary({0.0, 4.0}, {0.0, 3.0}));        // from the corner along the side
}

TEST_CASE("GeometryTree shape and leaf boxes", "[tree]") {
  for (const Named& n : all_geometries()) {
    const Geometry& g = n.geometry;
    const GeometryTree tree(g);
    INFO(n.name);
    const GeometryTreeStats s = tree.stats();
    CHECK(s.max_depth <= GeometryTree::kMaxDepth);
    CHECK(s.leaves == static_cast<int>(tree.leaf_boxes().size()));
    CHECK(s.nodes == 1 + 4 * ((s.leaves - 1) / 3));
    CHECK(s.stored_segments >= static_cast<int>(g.segments.size()));
    // Every segment end point lies in some leaf box; leaves tile the root without overlap of area.
    double area = 0;
    Box root;
    for (const Box& b : tree.leaf_boxes()) {
      area += b.width() * b.height();
      root.add(b.lo);
      root.add(b.hi);
    }
    CHECK(area == Approx(root.width() * root.height()).epsilon(1e-9));
    for (const Segment& seg : g.segments) CHECK(root.contains(seg.a));
    for (int c = 0; c < static_cast<int>(g.curves.size()); ++c) {
      Box expected;
      for (const Vec2 p : g.curves[c].points) expected.add(p);
      const Box got = tree.curve_box(c);
      CHECK((got.lo == expected.lo && got.hi == expected.hi));
    }
  }
}

TEST_CASE("GeometryTree edge cases", "[tree]") {
  SECTION("many segments meeting at the root centre") {
    // A fan of 24 segments from the centre of a square: splitting cannot separate them there.
    std::vector<std::vector<Vec2>> fan;
    for (int i = 0; i < 24; ++i) {
      const double a = 2 * M_PI * i / 24;
      fan.push_back({{0, 0}, {std::cos(a), std::sin(a)}});
    }
    const Geometry g = fixtures::make_geometry(fan);
    const GeometryTree tree(g);
    CHECK(tree.stats().nodes < 2000);
    std::mt19937_64 rng(3);
    for (int i = 0; i < 500; ++i) {
      const Vec2 p = query_point(g, rng);
      require_same(tree.closest(p), brute_force::closest(g, p), p);
    }
    CHECK(tree.closest({0, 0}).segment == 0);  // all 24 tie at distance 0
  }
  SECTION("leaves of more than 64 segments") {
    // closest() scans a leaf's entries in blocks of 64. Segments that all meet at the root centre
    // stay in one leaf however deep the split: 150 curves of one segment each (one leaf of 150 in
    // the tree over all segments) and one zigzag curve of 300 segments that all touch the centre (one
    // leaf of 300 in that curve's tree). The answers must be the brute force's, whichever block holds
    // the closest segment, seeded by the previous point's answers or not.
    std::vector<std::vector<Vec2>> curves;
    for (int i = 0; i < 150; ++i) {
      const double a = 2 * M_PI * i / 150;
      curves.push_back({{0, 0}, {std::cos(a), std::sin(a)}});
    }
    std::vector<Vec2> zigzag{{0, 0}};
    for (int i = 0; i < 150; ++i) {
      const double a = 2 * M_PI * (i + 0.5) / 150;
      zigzag.push_back({0.5 * std::cos(a), 0.5 * std::sin(a)});
      zigzag.push_back({0, 0});
    }
    curves.push_back(zigzag);
    const Geometry g = fixtures::make_geometry(curves);
    const GeometryTree tree(g);
    CHECK(tree.stats().max_depth <= 1);  // no split separates them: the leaves are the long ones
    std::mt19937_64 rng(5);
    std::vector<ClosestHit> near, brute;
    for (int i = 0; i < 2000; ++i) {
      const double r = (i % 2 == 0 ? 0.3 : 1.5) * unit(rng), a = 2 * M_PI * unit(rng);
      const Vec2 p = i % 7 == 0 ? query_point(g, rng) : Vec2{r * std::cos(a), r * std::sin(a)};
      require_same(tree.closest(p), brute_force::closest(g, p), p);
      require_same(tree.closest_on_curve(p, 150), brute_force::closest_on_curve(g, p, 150), p);
      tree.closest_per_curve_near(p, near);
      brute_force::closest_per_curve(g, p, brute);
      REQUIRE(near.size() == brute.size());
      for (std::size_t k = 0; k < near.size(); ++k) require_same(near[k], brute[k], p);
    }
  }
  SECTION("no segments") {
    const Geometry g;
    const GeometryTree tree(g);
    CHECK(tree.closest({1, 2}).segment == -1);
    CHECK_FALSE(tree.inside({1, 2}));
    CHECK_FALSE(tree.crosses_boundary({0, 0}, {1, 1}));
    CHECK(tree.leaf_boxes().empty());
  }
  SECTION("bad curve index and bad segment data") {
    const Geometry g = fixtures::square_with_hole();
    const GeometryTree tree(g);
    CHECK_THROWS_AS(tree.closest_on_curve({0, 0}, 2), std::out_of_range);
    CHECK_THROWS_AS(tree.closest_on_curve({0, 0}, -1), std::out_of_range);
    Geometry bad = fixtures::square_with_hole();
    bad.segments[3].curve = 7;
    CHECK_THROWS_AS(GeometryTree(bad), GeometryError);
    Geometry nan = fixtures::square_with_hole();
    nan.segments[5].b.x = std::nan("");
    CHECK_THROWS_WITH(GeometryTree(nan), Catch::Matchers::Contains("segment 5"));
  }
}

TEST_CASE("GeometryTree on a geometry from build_geometry", "[tree]") {
  // The fixture's curves, validated and processed by build_geometry (joints, loops, critical points).
  std::vector<RawCurve> raw;
  for (const Curve& c : fixtures::circle_in_circle().curves) {
    RawCurve r;
    r.name = c.name;
    r.points = c.points;
    r.file = "fixture";
    r.line = 1;
    raw.push_back(r);
  }
  const Geometry g = build_geometry(raw);
  const GeometryTree tree(g);
  std::mt19937_64 rng(99);
  std::vector<ClosestHit> per_tree, per_brute;
  for (int i = 0; i < 3000; ++i) {
    const Vec2 p = query_point(g, rng);
    require_same(tree.closest(p), brute_force::closest(g, p), p);
    tree.closest_per_curve(p, per_tree);
    brute_force::closest_per_curve(g, p, per_brute);
    for (std::size_t k = 0; k < per_tree.size(); ++k) require_same(per_tree[k], per_brute[k], p);
    REQUIRE(tree.inside(p) == brute_force::inside(g, p));
    // Away from the polygons (which lie within 0.05 of the circles) the annulus 3 < r < 10 decides.
    const double r = norm(p);
    if (std::fabs(r - 3) > 0.05 && std::fabs(r - 10) > 0.05) REQUIRE(tree.inside(p) == (r > 3 && r < 10));
  }
}
