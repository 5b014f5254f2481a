// Internal helpers shared by the build_geometry source files (not part of the public interface):
// source locations for messages, polyline angles and distances, the even-odd crossing test and the
// intersection check.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "geometry/geometry.hpp"

namespace pdmesh::detail {

// Source line of every point of every curve, kept beside Geometry only while building it.
using PointLines = std::vector<std::vector<int>>;

// "FILE:LINE" (or "curve input" when the curve has no file).
std::string where(const std::string& file, int line);
// "(x, y)" with the shortest round-trip representation of each coordinate.
std::string format_point(Vec2 p);

// The angle (radians, [0, pi]) by which a polyline turns from direction `in` to direction `out`;
// a vertex is a corner where it exceeds the corner angle.
inline double turning_angle(Vec2 in, Vec2 out) { return std::atan2(std::fabs(cross(in, out)), dot(in, out)); }
// The parameter in [0, 1] of the point of segment ab nearest p (0 for a point segment), and that
// point's distance from p.
inline double chord_param(Vec2 a, Vec2 b, Vec2 p) {
  const Vec2 d = b - a;
  const double len2 = norm2(d);
  return len2 > 0.0 ? std::clamp(dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
}
inline double distance_to_chord(Vec2 a, Vec2 b, Vec2 p) { return dist(p, a + chord_param(a, b, p) * (b - a)); }

// Number of boundary segments crossed by the ray from p towards +x (exact, via orient2d).
// Only meaningful when p lies on no segment; odd means inside the even-odd domain.
int ray_crossings(const std::vector<Segment>& segments, const std::vector<int>& which, Vec2 p);
// True when p lies on one of the segments (exactly).
bool on_any_segment(const std::vector<Segment>& segments, Vec2 p);

// Throws GeometryError for the first (lowest-index) pair of segments that share a point they may
// not share: anything but consecutive segments of one curve at their common vertex, or two curve
// ends meeting at a joint. Uses a uniform grid so the cost is about linear in the segment count.
void check_intersections(const Geometry& geometry, const PointLines& lines);

// Embedded constraints (geometry/constraint_split.cpp). Moves every constraint curve end that lies
// within `tolerance` of another curve's vertex onto that vertex.
void snap_constraint_ends(std::vector<Curve>& curves, double tolerance);
// Inserts, into both curves, the points where a constraint segment meets a segment of another curve
// (crossings, T-junctions, an end within `tolerance` of a segment) and puts embedded points within
// `tolerance` of a curve on it. Returns per curve and point whether the point must be critical (a
// meeting point or a placed embedded point); `lines` follows the inserted points; `free_points`
// receives the points that lie on no curve (duplicates within `tolerance` merged). GeometryError
// when a constraint runs along another curve.
std::vector<std::vector<std::uint8_t>> split_at_constraints(std::vector<Curve>& curves, PointLines& lines,
                                                            const std::vector<RawPoint>& points, double tolerance,
                                                            std::vector<RawPoint>& free_points);

}  // namespace pdmesh::detail
