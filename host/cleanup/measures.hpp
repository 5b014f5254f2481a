// Triangle measures the cleanup decides with: the sine of the smallest angle (its quality score),
// the aspect ratio, circumcentre and inradius. Plain floating point: orientation decisions that must be
// exact use core/predicates; these only rank candidates.
#pragma once
#include <algorithm>
#include <cmath>

#include "core/vec2.hpp"

namespace pdmesh::cleanup {

// Sine of the smallest angle of (a, b, c): 2A / (product of the two longest edges), which is
// monotone in the smallest angle (always <= 60 degrees), costs one square root, and is negative for
// a clockwise triangle, so an inverted triangle ranks below every valid one.
inline double min_angle_sine(Vec2 a, Vec2 b, Vec2 c) {
  const double ab = norm2(b - a), bc = norm2(c - b), ca = norm2(a - c);
  const double twice_area = cross(b - a, c - a);
  // The smallest angle is opposite the shortest edge; the product of the other two is the rest.
  const double shortest = std::min({ab, bc, ca});
  const double product = shortest == ab ? bc * ca : (shortest == bc ? ab * ca : ab * bc);
  return product > 0.0 ? twice_area / std::sqrt(product) : -1.0;
}

// min_angle_sine(a, b, c) from ab = norm2(b - a), bc = norm2(c - b), ca = norm2(a - c) and twice_area =
// cross(b - a, c - a): the same operations, so the same value bit for bit.
inline double min_angle_sine_of_squares(double ab, double bc, double ca, double twice_area) {
  const double shortest = std::min({ab, bc, ca});
  const double product = shortest == ab ? bc * ca : (shortest == bc ? ab * ca : ab * bc);
  return product > 0.0 ? twice_area / std::sqrt(product) : -1.0;
}

// The sine of the smaller of the two angles of (a, b, c) other than the one at vertex `skip` (0, 1, 2 for
// a, b, c); negative for a clockwise triangle. Of two angles whose sum is below 180 degrees the smaller
// has the smaller sine, so this ranks as the smaller angle does, as min_angle_sine does.
inline double min_angle_sine_except(Vec2 a, Vec2 b, Vec2 c, int skip) {
  const double ab = dist(a, b), bc = dist(b, c), ca = dist(c, a);
  const double twice_area = cross(b - a, c - a);
  // The sine of the angle at a vertex is 2A over the product of the two edges that meet there.
  const double at_a = ab * ca, at_b = ab * bc, at_c = bc * ca;
  const double p1 = skip == 0 ? at_b : at_a, p2 = skip == 2 ? at_b : at_c;
  return p1 > 0.0 && p2 > 0.0 ? std::min(twice_area / p1, twice_area / p2) : -1.0;
}

// The sine of an angle in degrees (targets are given in degrees), and back (a score as an angle,
// for reports).
inline double sine_from_degrees(double d) { return std::sin(d / 57.29577951308232); }
inline double degrees_from_sine(double s) { return std::asin(std::clamp(s, -1.0, 1.0)) * 57.29577951308232; }

// Aspect ratio R / (2 r) as the thesis appendix defines it (mesh/quality.cpp computes it the same
// way: l1 l2 l3 s / (8 A^2), s the half perimeter); +inf for a degenerate or inverted triangle.
inline double aspect_ratio(Vec2 a, Vec2 b, Vec2 c) {
  const double la = dist(b, c), lb = dist(c, a), lc = dist(a, b);
  const double area = 0.5 * cross(b - a, c - a);
  const double s = 0.5 * (la + lb + lc);
  return area > 0.0 ? la * lb * lc * s / (8.0 * area * area) : HUGE_VAL;
}

// aspect_ratio(a, b, c) from la = dist(b, c), lb = dist(c, a), lc = dist(a, b) and twice_area =
// cross(b - a, c - a): the same operations, so the same value bit for bit.
inline double aspect_ratio_of_lengths(double la, double lb, double lc, double twice_area) {
  const double area = 0.5 * twice_area;
  const double s = 0.5 * (la + lb + lc);
  return area > 0.0 ? la * lb * lc * s / (8.0 * area * area) : HUGE_VAL;
}

// aspect_ratio(a, b, c) from the squared edge lengths and twice_area of min_angle_sine_of_squares: the
// same operations (dist(b, c) is the square root of norm2(c - b), and so on), so the same value bit for bit.
inline double aspect_ratio_of_squares(double ab, double bc, double ca, double twice_area) {
  return aspect_ratio_of_lengths(std::sqrt(bc), std::sqrt(ca), std::sqrt(ab), twice_area);
}

// Circumcentre of a non-degenerate triangle (relative to a for accuracy).
inline Vec2 circumcentre(Vec2 a, Vec2 b, Vec2 c) {
  const Vec2 u = b - a, v = c - a;
  const double d = 2.0 * cross(u, v);
  const double uu = norm2(u), vv = norm2(v);
  return {a.x + (v.y * uu - u.y * vv) / d, a.y + (u.x * vv - v.x * uu) / d};
}

inline double inradius(Vec2 a, Vec2 b, Vec2 c) {
  const double perimeter = dist(a, b) + dist(b, c) + dist(c, a);
  return perimeter > 0.0 ? std::fabs(cross(b - a, c - a)) / perimeter : 0.0;
}

// aspect_ratio(a, b, c), and inradius(a, b, c) in `r`, from one computation of the three edge lengths
// (the smoother's moves need both for every triangle of a star): the same operations in the same
// order as the two functions, so the same values bit for bit (dist(x, y) == dist(y, x) exactly).
inline double aspect_ratio_and_inradius(Vec2 a, Vec2 b, Vec2 c, double& r) {
  const double la = dist(b, c), lb = dist(c, a), lc = dist(a, b);
  const double twice_area = cross(b - a, c - a);
  const double perimeter = lc + la + lb;
  r = perimeter > 0.0 ? std::fabs(twice_area) / perimeter : 0.0;
  const double area = 0.5 * twice_area;
  const double s = 0.5 * (la + lb + lc);
  return area > 0.0 ? la * lb * lc * s / (8.0 * area * area) : HUGE_VAL;
}

}  // namespace pdmesh::cleanup
