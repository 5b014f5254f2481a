// The far-field curve (farfield.hpp): its segment length, its smallest size and the polygon.
#include "geometry/farfield.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "core/errors.hpp"

namespace pdmesh {

namespace {

const char* shape_name(FarfieldShape s) { return s == FarfieldShape::Circle ? "circle" : "box"; }

double largest_extent(const Box& b) { return std::max(b.width(), b.height()); }

// The sides of the circle's polygon at segment length `segment` (at least farfield_min_sides()).
int circle_sides(double radius, double segment) {
  const double n = std::ceil(2.0 * std::numbers::pi * radius / segment - 1e-9);
  return std::max(farfield_min_sides(), static_cast<int>(std::min(n, 1e7)));
}

// Segments per side of the box of half-width `half` at segment length `segment`.
int box_segments(double half, double segment) {
  return std::max(1, static_cast<int>(std::min(std::ceil(2.0 * half / segment - 1e-9), 1e7)));
}

}  // namespace

int farfield_min_sides() {
  // R (1 - cos(pi / n)) <= tol R  <=>  n >= pi / acos(1 - tol).
  return static_cast<int>(std::ceil(std::numbers::pi / std::acos(1.0 - kFarfieldRadiusTolerance)));
}

double farfield_segment_length(const Box& extents, const Farfield& f, double body_spacing, double gradation) {
  const double reach = f.size * largest_extent(extents);
  double segment = 2.0 * std::numbers::pi * reach / farfield_min_sides();
  if (gradation > 0.0 && body_spacing > 0.0) {
    // The graded field's bound at the far field's least distance from the bounding box: the box
    // reaches out to half its diagonal from the centre.
    const double clearance = std::max(0.0, reach - 0.5 * extents.diagonal());
    segment = std::min(segment, body_spacing + gradation * clearance);
  }
  return segment;
}

double farfield_min_size(const Box& extents, const Farfield& f, double segment) {
  const double extent = largest_extent(extents);
  if (f.shape == FarfieldShape::Box) return 0.5;
  const int n = circle_sides(f.size * extent, segment);
  return 0.5 * extents.diagonal() / extent / std::cos(std::numbers::pi / n);
}

RawCurve farfield_curve(const Box& extents, const Farfield& f, double body_spacing, double gradation) {
  const double extent = largest_extent(extents);
  if (!(extent > 0.0) || !std::isfinite(extent))
    throw InputError(fmt::format("{}: the far field needs an input of positive extent, got {}", f.label, extent));
  const double segment = farfield_segment_length(extents, f, body_spacing, gradation);
  const double min_size = farfield_min_size(extents, f, segment);
  if (!(f.size > min_size)) {
    throw InputError(
        fmt::format("{}: a {} far field of size {} (x the largest extent {:.6g}) would cross or lie inside the input "
                    "(its bounding box {:.6g} x {:.6g}); the size must be above {:.4f}",
                    f.label, shape_name(f.shape), f.size, extent, extents.width(), extents.height(), min_size));
  }
  RawCurve c;
  c.name = kFarfieldName;
  c.file = f.label;
  const Vec2 o = extents.centre();
  const double reach = f.size * extent;
  if (f.shape == FarfieldShape::Circle) {
    const int n = circle_sides(reach, segment);
    for (int k = 0; k < n; ++k) {
      const double t = 2.0 * std::numbers::pi * k / n;
      c.points.push_back({o.x + reach * std::cos(t), o.y + reach * std::sin(t)});
    }
  } else {
    const int m = box_segments(reach, segment);
    const Vec2 corners[4] = {
        {o.x - reach, o.y - reach}, {o.x + reach, o.y - reach}, {o.x + reach, o.y + reach}, {o.x - reach, o.y + reach}};
    for (int side = 0; side < 4; ++side) {
      const Vec2 a = corners[side], b = corners[(side + 1) % 4];
      for (int k = 0; k < m; ++k) {
        const double t = static_cast<double>(k) / m;
        c.points.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
      }
    }
  }
  c.points.push_back(c.points.front());
  return c;
}

Geometry with_farfield(const Geometry& body, const Farfield& f, double gradation, const GeometryOptions& options) {
  std::vector<RawCurve> raw;
  double length = 0.0;
  std::size_t segments = 0;
  for (const Curve& c : body.curves) {
    if (c.name == kFarfieldName) {
      throw InputError(
          fmt::format("{}:{}: curve '{}' has the far field's name; rename it (geometry.curve_names) "
                      "or leave out {}",
                      c.file, c.line, c.name, f.label));
    }
    RawCurve r;
    r.name = c.name;
    r.points = c.points;
    r.file = c.file;
    r.line = c.line;
    r.fixed_points = c.fixed_points;
    r.constraint = c.constraint;
    if (!c.constraint) {
      length += c.length();
      segments += static_cast<std::size_t>(c.segment_count());
    }
    raw.push_back(std::move(r));
  }
  const double body_spacing = segments > 0 ? length / static_cast<double>(segments) : 0.0;
  raw.push_back(farfield_curve(body.extents, f, body_spacing, gradation));
  std::vector<RawHolePoint> holes;
  for (const Vec2 p : body.hole_points) holes.push_back({p, f.label, 0});
  Geometry g = build_geometry(std::move(raw), holes, options);
  g.embedded_points = body.embedded_points;
  g.regions = body.regions;
  g.notes = body.notes;
  return g;
}

}  // namespace pdmesh
