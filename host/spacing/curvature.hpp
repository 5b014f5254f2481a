// Boundary curvature as the curves' turning angles show it: a radius per segment, for the curvature
// size rule q <= R * theta (docs/spacing.md, "Curvature").
#pragma once
#include <vector>

#include "geometry/geometry.hpp"

namespace pdmesh {

// Per segment of geometry.segments: the radius of curvature of its curve there, +inf where the curve
// shows none. At an interior vertex that is not a critical point the curvature is that of the circle
// through it and its two neighbours, 2 sin|phi| / |p(k+1) - p(k-1)| with phi the turning angle; it
// counts only when a neighbouring vertex turns the same way (a lone kink is a corner of the polyline,
// not a curve). A segment takes the mean curvature of its two end vertices (those that count; a
// critical point or a curve end does not): on a regular polygon of radius R every segment gets R.
std::vector<double> segment_radii(const Geometry& geometry);

}  // namespace pdmesh
