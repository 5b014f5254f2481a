// Periodic curves (docs/geometry-input.md, "Periodic curves"): the rigid transform that maps a source
// curve onto its image (a translation or a rotation about a centre), and how far it misses.
#pragma once
#include <array>

#include "core/vec2.hpp"
#include "geometry/geometry.hpp"

namespace pdmesh {

// x -> R (x - center) + center + shift: a translation (angle 0) or a rotation about `center`
// (shift 0). cos_a and sin_a are kept so that every caller maps a point to the same bits.
struct PeriodicTransform {
  Vec2 shift{0.0, 0.0};
  Vec2 center{0.0, 0.0};
  double angle_rad = 0.0;
  double cos_a = 1.0, sin_a = 0.0;

  static PeriodicTransform translation(Vec2 d);
  static PeriodicTransform rotation(Vec2 center, double angle_deg);
  bool is_rotation() const { return angle_rad != 0.0; }
  Vec2 apply(Vec2 p) const;
  // The 4 x 4 affine matrix of the transform, row-major (Gmsh's $Periodic convention: image = A source).
  std::array<double, 16> affine() const;
};

// Where a transformed source curve misses its image: the largest distance from a point of one
// polyline to the other (T(source) against the image, both ways), and the point of the larger side
// where it occurs (in the image's coordinates).
struct PeriodicMiss {
  double distance = 0.0;
  Vec2 at{0.0, 0.0};
};
PeriodicMiss periodic_miss(const Curve& source, const Curve& image, const PeriodicTransform& t);

// True when T(source) runs against the image: T(source's first point) is nearer the image's last point.
bool periodic_reversed(const Curve& source, const Curve& image, const PeriodicTransform& t);

// The translation that maps the source curve's ends onto the image's (either way round: the one whose
// ends miss the least).
Vec2 inferred_translation(const Curve& source, const Curve& image);

}  // namespace pdmesh
