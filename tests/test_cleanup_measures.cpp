// Tests of the cleanup's triangle measures (cleanup/measures.hpp) that stand for one another.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstring>
#include <random>

#include "cleanup/measures.hpp"
#include "seeded_random.hpp"

using namespace pdmesh;
using namespace pdmesh::cleanup;

namespace {

// The k-th of a run of counter-clockwise, clockwise and nearly degenerate triangles at several scales
// and offsets: every fifth has its third corner nearly on the line through the first two.
std::array<Vec2, 3> random_triangle(std::mt19937_64& rng, int k) {
  const double scale = std::pow(10.0, 6.0 * pdmesh_test::unit(rng) - 3.0);
  const Vec2 o{1e3 * (pdmesh_test::unit(rng) - 0.5), 1e3 * (pdmesh_test::unit(rng) - 0.5)};
  const auto at = [&] { return o + scale * Vec2{pdmesh_test::unit(rng), pdmesh_test::unit(rng)}; };
  const Vec2 a = at(), b = at();
  const Vec2 c = k % 5 == 0 ? a + 0.5 * (b - a) : at();
  return {a, b, c};
}

// Bit for bit: == alone would take -0.0 for 0.0.
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST_CASE("aspect_ratio_and_inradius gives aspect_ratio and inradius bit for bit", "[cleanup]") {
  std::mt19937_64 rng(20261204);
  for (int k = 0; k < 200000; ++k) {
    const auto [a, b, c] = random_triangle(rng, k);
    double r = -1.0;
    const double ar = aspect_ratio_and_inradius(a, b, c, r);
    INFO("triangle " << k);
    CHECK(same_bits(ar, aspect_ratio(a, b, c)));
    CHECK(same_bits(r, inradius(a, b, c)));
  }
  // Two equal points: a zero area, an infinite aspect ratio and a zero inradius.
  double r = -1.0;
  CHECK(std::isinf(aspect_ratio_and_inradius({0, 0}, {0, 0}, {1, 0}, r)));
  CHECK(r == 0.0);
}

TEST_CASE("the measures from squared sides give min_angle_sine and aspect_ratio bit for bit", "[cleanup]") {
  std::mt19937_64 rng(20261205);
  for (int k = 0; k < 200000; ++k) {
    const auto [a, b, c] = random_triangle(rng, k);
    // The sides as the smoother takes them: the one opposite a moved vertex once, the others from
    // either end (norm2(b - a) and norm2(a - b) are the same number).
    const double ab = k % 2 == 0 ? norm2(b - a) : norm2(a - b), bc = norm2(c - b), ca = norm2(a - c);
    const double twice_area = cross(b - a, c - a);
    INFO("triangle " << k);
    CHECK(same_bits(min_angle_sine_of_squares(ab, bc, ca, twice_area), min_angle_sine(a, b, c)));
    CHECK(same_bits(aspect_ratio_of_squares(ab, bc, ca, twice_area), aspect_ratio(a, b, c)));
  }
  CHECK(min_angle_sine_of_squares(0.0, 0.0, 1.0, 0.0) == -1.0);  // two sides of zero length
  CHECK(std::isinf(aspect_ratio_of_squares(0.0, 1.0, 1.0, 0.0)));
}
