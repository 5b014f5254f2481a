// The transforms of periodic curves and how far a transformed curve misses its image.
#include "geometry/periodic.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "geometry/geometry_tree.hpp"

namespace pdmesh {

PeriodicTransform PeriodicTransform::translation(Vec2 d) {
  PeriodicTransform t;
  t.shift = d;
  return t;
}

PeriodicTransform PeriodicTransform::rotation(Vec2 center, double angle_deg) {
  PeriodicTransform t;
  t.center = center;
  t.angle_rad = angle_deg * std::numbers::pi / 180.0;
  t.cos_a = std::cos(t.angle_rad);
  t.sin_a = std::sin(t.angle_rad);
  return t;
}

Vec2 PeriodicTransform::apply(Vec2 p) const {
  if (!is_rotation()) return {p.x + shift.x, p.y + shift.y};
  const double x = p.x - center.x, y = p.y - center.y;
  return {cos_a * x - sin_a * y + center.x, sin_a * x + cos_a * y + center.y};
}

std::array<double, 16> PeriodicTransform::affine() const {
  // image = R source + (c - R c + shift)
  const double tx = center.x - (cos_a * center.x - sin_a * center.y) + shift.x;
  const double ty = center.y - (sin_a * center.x + cos_a * center.y) + shift.y;
  const double minus_sin = sin_a == 0.0 ? 0.0 : -sin_a;  // 0, not -0, in the files of a translation
  return {cos_a, minus_sin, 0.0, tx, sin_a, cos_a, 0.0, ty, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0};
}

namespace {

double distance_to_polyline(Vec2 p, const std::vector<Vec2>& line) {
  double best = INFINITY;
  for (std::size_t k = 0; k + 1 < line.size(); ++k) {
    Segment s;
    s.a = line[k];
    s.b = line[k + 1];
    best = std::min(best, closest_on_segment(p, s, 0).distance);
  }
  return best;
}

}  // namespace

PeriodicMiss periodic_miss(const Curve& source, const Curve& image, const PeriodicTransform& t) {
  std::vector<Vec2> mapped;
  mapped.reserve(source.points.size());
  for (const Vec2& p : source.points) mapped.push_back(t.apply(p));
  PeriodicMiss miss;
  for (const Vec2& p : mapped)
    if (const double d = distance_to_polyline(p, image.points); d > miss.distance) miss = {d, p};
  for (const Vec2& p : image.points)
    if (const double d = distance_to_polyline(p, mapped); d > miss.distance) miss = {d, p};
  return miss;
}

bool periodic_reversed(const Curve& source, const Curve& image, const PeriodicTransform& t) {
  const Vec2 first = t.apply(source.points.front());
  return dist(first, image.points.back()) < dist(first, image.points.front());
}

Vec2 inferred_translation(const Curve& source, const Curve& image) {
  const Vec2 s0 = source.points.front(), s1 = source.points.back();
  const Vec2 same = image.points.front() - s0, against = image.points.back() - s0;
  const double miss_same = dist(s1 + same, image.points.back());
  const double miss_against = dist(s1 + against, image.points.front());
  return miss_same <= miss_against ? same : against;
}

}  // namespace pdmesh
