// Smooth curves (geometry.curves = "smooth") for a geometry with embedded constraints and points:
// constraints are smoothed like boundary curves, the meeting points that build_geometry inserted
// into a segment (a constraint's end on a curve, a crossing, a point put on a curve) move onto the
// smooth curves, and the dense polyline is checked for meetings the polylines do not have. See
// docs/geometry-input.md, "Smooth curves".
#pragma once
#include <functional>

#include "geometry/geometry.hpp"
#include "geometry/smooth_curve.hpp"

namespace pdmesh {

// The dense geometry of the smooth curves through `input`'s points, constraints and embedded points
// included; without them, the same as make_dense_geometry(SmoothCurves(input, corner_angle_deg), ...).
//
// Which points a smooth curve passes through: every input point of it except the meeting points
// that build_geometry inserted into one of its segments (they lie on the input chord, where the
// smooth curve does not). Such a point moves onto the smooth curve: to the point of the curve
// nearest it where one curve got it (a constraint's end on a curve, a point put on a curve), to the
// crossing of the two smooth curves where two did; the curves that had it as an input point (the
// constraint's end) end there. Meeting points that were input points of every curve stay where they
// are. A joint of constraint ends off the boundary curves is smooth like a joint of boundary curves
// (turning angle up to the corner angle); a constraint's end on a curve is a free end; a meeting
// point is a corner only where its own curve turns more than the corner angle there.
//
// Throws GeometryError where the smooth curves meet where the polylines do not (a constraint now
// crossing another curve), an embedded point is outside the smooth domain or within the dense
// polyline's accuracy (`options.tolerance` x q) of a smooth curve, or two smooth curves do not cross
// near the crossing of their polylines; the caller may fall back to the polylines.
DenseGeometry make_dense_embedded(const Geometry& input, double corner_angle_deg,
                                  const std::function<double(Vec2)>& size, const DenseOptions& options = {});

}  // namespace pdmesh
