// The far-field curve (farfield.hpp): its segment length, its smallest size and the polygon.
#include "geometry/farfield.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "geometry/geometry_detail.hpp"

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

namespace {

// What with_farfield leaves out of the body, kind by kind, for its notes.
struct LeftOut {
  int count = 0;
  std::string first;  // the first one: a curve's name and file:line, or a point
  void add(const std::string& what) {
    if (count++ == 0) first = what;
  }
};

std::string point_label(Vec2 p, const std::string& file, int line) {
  return fmt::format("{} ({})", detail::format_point(p), detail::where(file, line));
}

std::string curve_label(const Curve& c) {
  return fmt::format("curve '{}' ({})", c.name, detail::where(c.file, c.line));
}

// One note per kind left out, after `label` (where the far field was given).
void note_left_out(std::vector<std::string>& notes, const std::string& label, const LeftOut& what, const char* singular,
                   const char* plural, const char* why) {
  if (what.count == 0) return;
  notes.push_back(fmt::format("{}: the far field leaves out {} {} inside the body{}, the first: {}", label, what.count,
                              what.count == 1 ? singular : plural, why, what.first));
}

}  // namespace

Geometry with_farfield(const Geometry& body, const Farfield& f, double gradation, const GeometryOptions& options) {
  for (const Curve& c : body.curves) {
    if (c.name == kFarfieldName) {
      throw InputError(
          fmt::format("{}:{}: curve '{}' has the far field's name; rename it (geometry.curve_names) "
                      "or leave out {}",
                      c.file, c.line, c.name, f.label));
    }
  }
  // The body is solid with FarfieldCavities::Solid: the curves of nested loops (depth >= 1) and the
  // embedded constraints (inside the body's domain, so inside the body) are left out; a point is
  // inside the body when it lies inside one of the outermost loops (they do not nest, so an odd count
  // of crossings of their segments).
  const bool solid = f.cavities == FarfieldCavities::Solid;
  std::vector<std::uint8_t> keep(body.curves.size(), 1);
  std::vector<int> outer;  // the segments of the outermost loops
  LeftOut loops, constraints, holes_out, points_out, regions_out;
  if (solid) {
    for (const Loop& loop : body.loops) {
      if (loop.depth > 0) {
        for (const int c : loop.curves) keep[static_cast<std::size_t>(c)] = 0;
        loops.add(curve_label(body.curves[static_cast<std::size_t>(loop.curves[0])]));
        continue;
      }
      for (const int c : loop.curves) {
        const Curve& curve = body.curves[static_cast<std::size_t>(c)];
        for (int k = 0; k < curve.segment_count(); ++k) outer.push_back(curve.first_segment + k);
      }
    }
    for (std::size_t c = 0; c < body.curves.size(); ++c) {
      if (!body.curves[c].constraint) continue;
      keep[c] = 0;
      constraints.add(curve_label(body.curves[c]));
    }
  }
  const auto inside_body = [&](Vec2 p) { return solid && detail::ray_crossings(body.segments, outer, p) % 2 == 1; };

  std::vector<RawCurve> raw;
  double length = 0.0;
  std::size_t segments = 0;
  for (std::size_t k = 0; k < body.curves.size(); ++k) {
    const Curve& c = body.curves[k];
    if (!c.constraint) {
      length += c.length();
      segments += static_cast<std::size_t>(c.segment_count());
    }
    if (!keep[k]) continue;
    RawCurve r;
    r.name = c.name;
    r.points = c.points;
    r.file = c.file;
    r.line = c.line;
    r.fixed_points = c.fixed_points;
    r.constraint = c.constraint;
    raw.push_back(std::move(r));
  }
  const double body_spacing = segments > 0 ? length / static_cast<double>(segments) : 0.0;
  raw.push_back(farfield_curve(body.extents, f, body_spacing, gradation));
  std::vector<RawHolePoint> holes;
  for (const RawHolePoint& h : body.hole_points) {
    if (inside_body(h.p)) {
      holes_out.add(point_label(h.p, h.file, h.line));
      continue;
    }
    holes.push_back(h);
  }
  // Embedded points lie in the body's domain, so inside the body; with the cavities meshed, the
  // even-odd rule of the new geometry checks them again.
  std::vector<RawPoint> points;
  for (const RawPoint& p : body.embedded_points) {
    if (solid) {
      points_out.add(point_label(p.p, p.file, p.line));
      continue;
    }
    points.push_back(p);
  }
  Geometry g = points.empty()
                   ? build_geometry(std::move(raw), holes, options)
                   : build_geometry(RawGeometry{std::move(raw), holes, std::move(points), {}, {}, {}}, options);
  for (const GeometryRegion& r : body.regions) {
    if (inside_body(r.p)) {
      regions_out.add(point_label(r.p, r.file, r.line));
      continue;
    }
    g.regions.push_back(r);
  }
  g.notes = body.notes;
  g.groups = body.groups;
  const char* meshed = " (farfield.cavities = \"mesh\" meshes them)";
  note_left_out(g.notes, f.label, loops, "loop nested", "loops nested", meshed);
  note_left_out(g.notes, f.label, holes_out, "hole point", "hole points", "");
  note_left_out(g.notes, f.label, constraints, "embedded constraint curve", "embedded constraint curves", "");
  note_left_out(g.notes, f.label, points_out, "embedded point", "embedded points", "");
  note_left_out(g.notes, f.label, regions_out, "region point", "region points", "");
  return g;
}

}  // namespace pdmesh
