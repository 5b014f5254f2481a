// The processed 2-D geometry (thesis ch. 4, "Geometry Processing"): segmented curves joined into
// closed loops, critical points, segments, arc lengths, extents and the even-odd domain area.
// Plain data: readers fill RawCurve lists, build_geometry() validates them and derives the rest.
#pragma once
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/vec2.hpp"

namespace pdmesh {

// A curve as read from a file, before validation.
struct RawCurve {
  std::string name;          // may be empty; build_geometry names it "curve<k>"
  std::vector<Vec2> points;  // as read
  std::string file;          // source file, for messages
  int line = 0;              // line of the curve's first point (or of its header), for messages
  // Optional: the source line of each point (same size as points). When empty, point k is taken
  // to be on line `line + k`, which is right for one-point-per-line formats such as .crv.
  std::vector<int> lines;
  // Every point is a critical point (a Fixed node that nothing moves, removes or splits): a boundary
  // layer's front, whose nodes the layer cells share (docs/boundary-layers.md).
  bool fixed_points = false;
  // An embedded constraint: a polyline inside the domain (open, or a closed loop that bounds a
  // subdomain rather than a hole) whose segments become chains of mesh edges and whose points
  // become nodes. It does not bound the domain (docs/geometry-input.md, "Embedded constraints").
  bool constraint = false;
};

// An isolated point inside the domain that must be a node of the mesh, as read from a file.
struct RawPoint {
  Vec2 p;
  std::string file;
  int line = 0;
};

// A hole point as read from a .poly file (Triangle's convention), before validation.
struct RawHolePoint {
  Vec2 p;
  std::string file;
  int line = 0;
};

// A regional attribute from a .poly file (Triangle's convention): the subdomain (the region bounded
// by segments) holding `p` is tagged with `attribute`; `max_area` > 0 caps its triangles' area.
struct GeometryRegion {
  Vec2 p;
  double attribute = 0.0;
  double max_area = -1.0;  // <= 0: no cap
  std::string file;
  int line = 0;
  // The attribute's name (a mesh file's physical surface or reference name, geometry.region_names);
  // empty: the writers call it "region_<attribute>".
  std::string name;
};

// The spacing that sizes a subdomain whose triangles should not exceed the area `max_area`
// (GeometryRegion::max_area; spacing/refine_regions.hpp, max_area_regions): the side of the
// equilateral triangle of that area over kMaxAreaSpacingMargin, since a settled mesh's largest
// triangles are about 1.6 times the area of the equilateral one of its spacing (the mean about
// 1.1 times): the largest then stay near the maximum area.
inline constexpr double kMaxAreaSpacingMargin = 1.3;
inline double max_area_spacing(double max_area) {
  return std::sqrt(4.0 * max_area / std::sqrt(3.0)) / kMaxAreaSpacingMargin;
}

// A name that stands for several curves (a mesh file's boundary name on separate stretches, which
// become curves NAME, NAME_2, ...: io/mesh_geometry.hpp): selections of curves by name
// (curves_by_name, layers/boundary_layers.hpp) take it for all of them. A group with a tag is a mesh
// file's physical group (one or more curves): the outputs write its curves as one group with that tag
// and name (Mesh::curve_groups).
struct CurveGroup {
  std::string name;
  std::vector<std::string> curves;
  long long tag = 0;  // 0: a name only
};

// One validated segmented boundary curve: an ordered polyline of >= 2 distinct consecutive points.
struct Curve {
  std::string name;
  std::vector<Vec2> points;
  std::vector<double> arc;             // cumulative arc length; arc[0] = 0, arc.back() = length
  std::vector<std::uint8_t> critical;  // per point: 1 if it is a critical point (joint or sharp corner)
  int first_segment = 0;               // index of its first segment in Geometry::segments
  std::string file;                    // where it came from
  int line = 0;
  bool fixed_points = false;  // RawCurve::fixed_points: every point critical, no node between them
  bool constraint = false;    // RawCurve::constraint: an embedded constraint, not a domain boundary
  double length() const { return arc.empty() ? 0.0 : arc.back(); }
  int segment_count() const { return static_cast<int>(points.size()) - 1; }
};

// Segment k of curve c joins curves[c].points[k] -> points[k+1].
struct Segment {
  Vec2 a, b;
  int curve = 0;
  int index = 0;  // k within the curve
  double length = 0.0;
};

// The largest |coordinate| of any segment end (0 for none): the scale of the rounding in distances
// to the segments, for the margins of exact searches (spacing/feature_size).
inline double coordinate_magnitude(const std::vector<Segment>& segments) {
  double m = 0.0;
  for (const Segment& s : segments)
    for (const double v : {s.a.x, s.a.y, s.b.x, s.b.y}) m = v > m ? v : (-v > m ? -v : m);
  return m;
}

// A closed loop: curves chained end to start (a curve may be traversed reversed).
struct Loop {
  std::vector<int> curves;
  std::vector<std::uint8_t> reversed;
  double signed_area = 0.0;  // > 0 counter-clockwise
  int depth = 0;             // how many other loops contain it; even depth = outer boundary of a region
};

// A critical point: a fixed node of the initial distribution. Either where curves join
// or a vertex whose turning angle exceeds the corner threshold.
struct CriticalPoint {
  Vec2 p;
  std::vector<int> curves;   // curves meeting here
  std::vector<int> indices;  // the point index within each of those curves
};

// geometry.hull, for .poly files: mesh the convex hull of all vertices (Triangle's -c, its box.poly
// convention). Automatic: only when the segments enclose no area (no closed loop).
enum class PolyHull { Automatic, On, Off };

struct GeometryOptions {
  // Curve end points closer than join_tolerance * (extents diagonal) are the same point.
  double join_tolerance = 1e-9;
  // A vertex inside a curve whose turning angle exceeds this (degrees) is a critical point.
  double corner_angle_deg = 30.0;
  PolyHull hull = PolyHull::Automatic;  // .poly files only
};

struct Geometry {
  std::vector<Curve> curves;
  std::vector<Segment> segments;  // curve-major order; curves[c].first_segment indexes here
  std::vector<Loop> loops;
  std::vector<CriticalPoint> critical;
  Box extents;
  double area = 0.0;  // even-odd interior area of all loops
  // Hole points from .poly files: accepted, checked to lie in a hole, otherwise unused (even-odd rule).
  // With the file and line they came from, for the errors of a geometry built around them (a far field).
  std::vector<RawHolePoint> hole_points;
  // Embedded points: nodes the mesh must have inside the domain, with the file and line they came from.
  std::vector<RawPoint> embedded_points;
  // Regional attributes (.poly files): the outputs tag each triangle with the attribute of the
  // region it lies in (mesh/region_tags.hpp), 0 outside every region.
  std::vector<GeometryRegion> regions;
  // Remarks of the readers (a .poly read differently from the even-odd rule, vertices kept or
  // dropped): printed on stderr by the command.
  std::vector<std::string> notes;
  // Names that stand for several curves (mesh files as geometry).
  std::vector<CurveGroup> groups;
};

// Everything a geometry reader hands on: curves (boundaries and constraints), hole points and
// embedded points, before validation; with .poly files also the regions and the readers' notes, and
// with mesh files the curve groups, which build_geometry leaves to the caller (read_geometry copies
// them onto the Geometry).
struct RawGeometry {
  std::vector<RawCurve> curves;
  std::vector<RawHolePoint> holes;
  std::vector<RawPoint> points;
  std::vector<GeometryRegion> regions;
  std::vector<std::string> notes;
  std::vector<CurveGroup> groups;  // handed on like regions and notes
};

// Validates raw curves and derives everything else. Throws GeometryError naming the file, line,
// curve and segment on: fewer than 2 points, non-finite coordinates, zero-length segments,
// repeated consecutive points, loops that do not close, curves that intersect themselves or each other.
Geometry build_geometry(std::vector<RawCurve> raw, const GeometryOptions& options = {});
// The same, with hole points: each must lie outside the even-odd domain (in a hole or outside every
// loop), otherwise GeometryError naming its file and line. They end up in Geometry::hole_points.
Geometry build_geometry(std::vector<RawCurve> raw, const std::vector<RawHolePoint>& holes,
                        const GeometryOptions& options = {});
// The same for everything a reader hands on, embedded constraints and points included
// (docs/geometry-input.md, "Embedded constraints"). Constraint curves are checked like boundary
// curves but join no loop and may be open; where they meet each other or a boundary curve (a
// crossing, a T-junction, an end on a curve, within the join tolerance) the meeting point becomes a
// vertex of both and a critical point. Every constraint and point must lie inside the domain
// (GeometryError naming its file, line, curve and the point otherwise); a point within the join
// tolerance of a curve becomes a critical vertex of that curve, the others end up in
// Geometry::embedded_points. Without constraints and points: exactly the overload above.
Geometry build_geometry(RawGeometry raw, const GeometryOptions& options = {});

}  // namespace pdmesh
