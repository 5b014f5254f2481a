// Robust predicates against exact rational arithmetic (GMP) on nearly degenerate inputs:
// the sign of orient2d / incircle must match exactly, and the segment tests must match a
// rational parametric solution.
#include <gmp.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "core/predicates.hpp"
#include "seeded_random.hpp"

using pdmesh::Vec2;

namespace {

// RAII wrapper around mpq_t; doubles convert exactly.
struct Q {
  mpq_t v;
  Q() { mpq_init(v); }
  explicit Q(double d) {
    mpq_init(v);
    mpq_set_d(v, d);
  }
  Q(const Q& o) {
    mpq_init(v);
    mpq_set(v, o.v);
  }
  Q& operator=(const Q& o) {
    mpq_set(v, o.v);
    return *this;
  }
  ~Q() { mpq_clear(v); }
  int sign() const { return mpq_sgn(v); }
};
Q operator-(const Q& a, const Q& b) {
  Q r;
  mpq_sub(r.v, a.v, b.v);
  return r;
}
Q operator+(const Q& a, const Q& b) {
  Q r;
  mpq_add(r.v, a.v, b.v);
  return r;
}
Q operator*(const Q& a, const Q& b) {
  Q r;
  mpq_mul(r.v, a.v, b.v);
  return r;
}
Q operator/(const Q& a, const Q& b) {
  Q r;
  mpq_div(r.v, a.v, b.v);
  return r;
}
bool operator<(const Q& a, const Q& b) { return mpq_cmp(a.v, b.v) < 0; }

int sign_of(double v) { return (v > 0) - (v < 0); }

int exact_orient(Vec2 a, Vec2 b, Vec2 c) {
  const Q acx = Q(a.x) - Q(c.x), acy = Q(a.y) - Q(c.y);
  const Q bcx = Q(b.x) - Q(c.x), bcy = Q(b.y) - Q(c.y);
  return (acx * bcy - acy * bcx).sign();
}

int exact_incircle(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const Q adx = Q(a.x) - Q(d.x), ady = Q(a.y) - Q(d.y);
  const Q bdx = Q(b.x) - Q(d.x), bdy = Q(b.y) - Q(d.y);
  const Q cdx = Q(c.x) - Q(d.x), cdy = Q(c.y) - Q(d.y);
  const Q al = adx * adx + ady * ady, bl = bdx * bdx + bdy * bdy, cl = cdx * cdx + cdy * cdy;
  return (al * (bdx * cdy - cdx * bdy) + bl * (cdx * ady - adx * cdy) + cl * (adx * bdy - bdx * ady)).sign();
}

// Reference for closed-segment intersection: solve a + t(b-a) = c + u(d-c) in rationals.
bool exact_segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const Q rx = Q(b.x) - Q(a.x), ry = Q(b.y) - Q(a.y);
  const Q sx = Q(d.x) - Q(c.x), sy = Q(d.y) - Q(c.y);
  const Q qx = Q(c.x) - Q(a.x), qy = Q(c.y) - Q(a.y);
  const Q denom = rx * sy - ry * sx;
  const Q zero, one(1.0);
  if (denom.sign() != 0) {
    const Q t = (qx * sy - qy * sx) / denom, u = (qx * ry - qy * rx) / denom;
    return !(t < zero) && !(one < t) && !(u < zero) && !(one < u);
  }
  if ((qx * ry - qy * rx).sign() != 0) return false;  // parallel, not collinear
  if ((qx * sy - qy * sx).sign() != 0) return false;  // a-b degenerate, a not on line cd
  // Collinear (or degenerate): some point of one lies on the other. Check the four end points.
  auto on_segment = [](Vec2 p, Vec2 s0, Vec2 s1) {
    // p is collinear with s0, s1 here; test that it lies in the bounding box.
    return std::fmin(s0.x, s1.x) <= p.x && p.x <= std::fmax(s0.x, s1.x) && std::fmin(s0.y, s1.y) <= p.y &&
           p.y <= std::fmax(s0.y, s1.y);
  };
  if (exact_orient(c, d, a) != 0 && !(c == d)) return false;
  return on_segment(a, c, d) || on_segment(b, c, d) || on_segment(c, a, b) || on_segment(d, a, b);
}

bool exact_cross_properly(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  return exact_orient(a, b, c) * exact_orient(a, b, d) < 0 && exact_orient(c, d, a) * exact_orient(c, d, b) < 0;
}

using pdmesh_test::unit;

// Moves v by whole ulps. Zero stays zero: stepping into subnormals would underflow the products,
// which is outside the predicates' exactness contract.
double nudge(double v, int ulps) {
  if (v == 0.0) return v;
  for (; ulps > 0; --ulps) v = std::nextafter(v, 1e300);
  for (; ulps < 0; ++ulps) v = std::nextafter(v, -1e300);
  return v;
}

}  // namespace

TEST_CASE("orient2d hand cases", "[predicates]") {
  CHECK(pdmesh::orient2d({0, 0}, {1, 0}, {0, 1}) > 0);
  CHECK(pdmesh::orient2d({0, 0}, {0, 1}, {1, 0}) < 0);
  CHECK(pdmesh::orient2d({0, 0}, {1, 1}, {2, 2}) == 0);
  CHECK(pdmesh::orient2d({0, 0}, {2, 0}, {1, 1}) == Approx(2.0));  // twice the area 1
  // 0.1, 0.2, 0.3 are not exactly collinear in binary; the exact sign is what GMP says.
  const Vec2 a{0.1, 0.1}, b{0.2, 0.2}, c{0.3, 0.3};
  CHECK(sign_of(pdmesh::orient2d(a, b, c)) == exact_orient(a, b, c));
}

TEST_CASE("orient2d: collinear points perturbed by ulps match exact signs", "[predicates]") {
  std::mt19937_64 rng(42);
  int nonzero = 0, zero = 0;
  for (int i = 0; i < 4000; ++i) {
    const double scale = std::ldexp(1.0, static_cast<int>(rng() % 60) - 30);
    Vec2 a{unit(rng) * scale, unit(rng) * scale}, b{unit(rng) * scale, unit(rng) * scale};
    double t = unit(rng) * 3.0 - 1.0;
    if (i % 4 == 0) {  // exactly representable collinear triples: integers times a power of two
      auto k = [&] { return static_cast<double>(rng() % 2001) * scale; };
      a = {k(), k()};
      b = {k(), k()};
      t = static_cast<double>(rng() % 5) - 2.0;
    }
    Vec2 c = a + t * (b - a);
    c.x = nudge(c.x, static_cast<int>(rng() % 5) - 2);
    c.y = nudge(c.y, static_cast<int>(rng() % 5) - 2);
    const int expected = exact_orient(a, b, c);
    INFO("case " << i);
    REQUIRE(sign_of(pdmesh::orient2d(a, b, c)) == expected);
    REQUIRE(sign_of(pdmesh::orient2d(b, c, a)) == expected);
    REQUIRE(sign_of(pdmesh::orient2d(b, a, c)) == -expected);
    (expected == 0 ? zero : nonzero)++;
  }
  CHECK(nonzero > 1000);
  CHECK(zero > 10);
}

TEST_CASE("orient2d: grid points and large magnitude differences", "[predicates]") {
  std::mt19937_64 rng(7);
  for (int i = 0; i < 3000; ++i) {
    // Grid with a non-representable step, translated far from the origin.
    const double step = 0.1, off = (i % 3 == 0) ? 0.0 : (i % 3 == 1 ? 1e6 : -3.7e9);
    auto g = [&] { return off + step * static_cast<double>(rng() % 9); };
    const Vec2 a{g(), g()}, b{g(), g()}, c{g(), g()};
    INFO("grid case " << i);
    REQUIRE(sign_of(pdmesh::orient2d(a, b, c)) == exact_orient(a, b, c));
  }
  for (int i = 0; i < 3000; ++i) {
    auto m = [&] {
      const double mag = std::ldexp(1.0, static_cast<int>(rng() % 120) - 60);
      return (unit(rng) - 0.5) * mag;
    };
    const Vec2 a{m(), m()}, b{m(), m()};
    Vec2 c = 0.5 * (a + b);  // near the midpoint: cancellation between huge and tiny terms
    c.y = nudge(c.y, static_cast<int>(rng() % 3) - 1);
    INFO("magnitude case " << i);
    REQUIRE(sign_of(pdmesh::orient2d(a, b, c)) == exact_orient(a, b, c));
  }
}

TEST_CASE("incircle hand cases", "[predicates]") {
  const Vec2 a{0, 0}, b{1, 0}, c{0, 1};
  CHECK(pdmesh::incircle(a, b, c, {0.5, 0.5}) > 0);
  CHECK(pdmesh::incircle(a, b, c, {1, 1}) == 0);  // unit square: cocircular
  CHECK(pdmesh::incircle(a, b, c, {2, 2}) < 0);
}

TEST_CASE("incircle: cocircular pythagorean points, translated and nudged", "[predicates]") {
  // Points with integer coordinates on circles of radius 5, 25, 65 (pythagorean triples).
  const std::vector<std::vector<Vec2>> circles = {
      {{3, 4}, {-3, 4}, {3, -4}, {-3, -4}, {4, 3}, {-4, 3}, {4, -3}, {-4, -3}, {5, 0}, {-5, 0}, {0, 5}, {0, -5}},
      {{7, 24}, {-24, 7}, {15, -20}, {-20, -15}, {25, 0}, {0, -25}, {24, -7}},
      {{16, 63}, {-33, 56}, {39, -52}, {-60, -25}, {63, 16}, {-65, 0}, {25, 60}}};
  std::mt19937_64 rng(11);
  int zero = 0, total = 0;
  for (int i = 0; i < 4000; ++i) {
    const auto& circle = circles[rng() % circles.size()];
    Vec2 p[4];
    for (auto& v : p) v = circle[rng() % circle.size()];
    if (pdmesh::orient2d(p[0], p[1], p[2]) == 0) continue;  // repeated points: skip
    // Scale by a non-power of two and translate: rounding makes them nearly, not exactly, cocircular.
    const double s = (i % 2) ? 1.0 : 0.013, tx = (i % 4 < 2) ? 0.0 : 1234.567, ty = (i % 8 < 4) ? 0.0 : -0.3;
    for (auto& v : p) v = Vec2{tx + s * v.x, ty + s * v.y};
    p[3].x = nudge(p[3].x, static_cast<int>(rng() % 3) - 1);
    const int expected = exact_incircle(p[0], p[1], p[2], p[3]);
    INFO("case " << i << " d = (" << p[3].x << ", " << p[3].y << ")");
    REQUIRE(sign_of(pdmesh::incircle(p[0], p[1], p[2], p[3])) == expected);
    REQUIRE(sign_of(pdmesh::incircle(p[1], p[2], p[0], p[3])) == expected);
    REQUIRE(sign_of(pdmesh::incircle(p[1], p[0], p[2], p[3])) == -expected);
    zero += (expected == 0);
    ++total;
  }
  CHECK(total > 2000);
  CHECK(zero > 100);
}

TEST_CASE("incircle: random grid points and large magnitudes", "[predicates]") {
  std::mt19937_64 rng(99);
  for (int i = 0; i < 4000; ++i) {
    const double off = (i % 2) ? 0.0 : 1e5;
    auto g = [&] { return off + 0.1 * static_cast<double>(rng() % 6); };
    const Vec2 a{g(), g()}, b{g(), g()}, c{g(), g()}, d{g(), g()};
    INFO("grid case " << i);
    REQUIRE(sign_of(pdmesh::incircle(a, b, c, d)) == exact_incircle(a, b, c, d));
  }
  for (int i = 0; i < 2000; ++i) {
    auto m = [&] {
      const double mag = std::ldexp(1.0, static_cast<int>(rng() % 60) - 30);
      return (unit(rng) - 0.5) * mag;
    };
    const Vec2 a{m(), m()}, b{m(), m()}, c{m(), m()};
    // d near a vertex: the determinant nearly vanishes.
    const Vec2 d{nudge(a.x, static_cast<int>(rng() % 5) - 2), nudge(a.y, static_cast<int>(rng() % 5) - 2)};
    INFO("magnitude case " << i);
    REQUIRE(sign_of(pdmesh::incircle(a, b, c, d)) == exact_incircle(a, b, c, d));
  }
}

TEST_CASE("segment tests: hand cases", "[predicates]") {
  using pdmesh::segments_cross_properly;
  using pdmesh::segments_intersect;
  const Vec2 o{0, 0}, x2{2, 0}, y2{0, 2}, q{2, 2};
  CHECK(segments_intersect(o, q, x2, y2));  // X crossing
  CHECK(segments_cross_properly(o, q, x2, y2));
  CHECK(segments_intersect(o, x2, x2, q));  // shared end point
  CHECK_FALSE(segments_cross_properly(o, x2, x2, q));
  CHECK(segments_intersect(o, x2, {1, 0}, {1, 5}));  // T junction
  CHECK_FALSE(segments_cross_properly(o, x2, {1, 0}, {1, 5}));
  CHECK(segments_intersect(o, x2, {1, 0}, {3, 0}));  // collinear overlap
  CHECK_FALSE(segments_cross_properly(o, x2, {1, 0}, {3, 0}));
  CHECK(segments_intersect(o, x2, {2, 0}, {3, 0}));          // collinear, touching
  CHECK_FALSE(segments_intersect(o, x2, {2.5, 0}, {3, 0}));  // collinear, disjoint
  CHECK_FALSE(segments_intersect(o, x2, {0, 1}, {2, 1}));    // parallel
  CHECK(segments_intersect(o, x2, {1, 0}, {1, 0}));          // point segment on ab
  CHECK_FALSE(segments_intersect(o, x2, {1, 1e-300}, {1, 1e-300}));
  CHECK(segments_intersect({0, 1}, {0, 3}, {0, 2}, {0, 2.5}));  // vertical collinear containment
}

TEST_CASE("segment tests: random grid segments match a rational solution", "[predicates]") {
  std::mt19937_64 rng(5);
  int hits = 0;
  for (int i = 0; i < 6000; ++i) {
    // Small grids make collinear, touching and degenerate configurations frequent.
    const double step = (i % 2) ? 1.0 : 0.1;
    auto g = [&] { return step * static_cast<double>(rng() % 4); };
    const Vec2 a{g(), g()}, b{g(), g()}, c{g(), g()}, d{g(), g()};
    INFO("case " << i);
    const bool expected = exact_segments_intersect(a, b, c, d);
    REQUIRE(pdmesh::segments_intersect(a, b, c, d) == expected);
    REQUIRE(pdmesh::segments_intersect(d, c, b, a) == expected);
    REQUIRE(pdmesh::segments_cross_properly(a, b, c, d) == exact_cross_properly(a, b, c, d));
    hits += expected;
  }
  CHECK(hits > 1000);
}
