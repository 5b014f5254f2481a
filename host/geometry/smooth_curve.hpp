// Smooth curves through the input points (case key geometry.curves = "smooth"): a centripetal
// Catmull-Rom spline per curve, with corners kept at the critical points, and its dense polyline,
// which then stands for the curve everywhere the nodes live (sliding, snapping, inside tests, fill,
// mesh boundary). The input polyline keeps defining the spacing field (its segment lengths are eq.
// 3.6's l_s). See docs/geometry-input.md, "Smooth curves".
#pragma once
#include <functional>
#include <vector>

#include "geometry/geometry.hpp"

namespace pdmesh {

// The smooth interpolant of every curve of a geometry, as cubic Hermite pieces: piece k of curve c
// runs from points[k] (u = 0) to points[k+1] (u = 1). Tangents are the centripetal Catmull-Rom ones
// (knots t_{i+1} = t_i + |P_{i+1} - P_i|^(1/2)), which have no cusps or self-intersections within a
// piece and do not overshoot where the point spacing jumps. The curve is C1 (in the knot parameter)
// at every interior point, and across a joint whose turning angle is at most the corner angle (the
// point of the other curve serves as neighbour); at a critical point with a sharper turn it keeps
// the corner: the end tangent is the interior tangent reflected about the end chord (the tangent of
// the circular arc through the end point that meets the next tangent), or the chord itself for a
// section of one segment, which therefore stays straight.
class SmoothCurves {
 public:
  SmoothCurves(const Geometry& geometry, double corner_angle_deg);

  // Point of piece k of curve c at u in [0, 1]; exactly the input point at u = 0 and u = 1.
  Vec2 at(int curve, int piece, double u) const;
  // Derivative with respect to u.
  Vec2 derivative(int curve, int piece, double u) const;
  const Geometry& geometry() const { return geometry_; }

 private:
  const Geometry& geometry_;
  // Per curve, per piece: the Hermite end derivatives (with respect to u).
  std::vector<std::vector<Vec2>> start_, end_;
};

// Appends to `out` the dense points of piece k of curve c over [u0, u1] after p0 (p0 and p1 are the
// points at u0 and u1): the piece is bisected until each chord is within `tol` of the curve (tested
// at its quarter points) or shorter than `min_len`.
void subdivide_piece(const SmoothCurves& s, int c, int k, double u0, Vec2 p0, double u1, Vec2 p1, double tol,
                     double min_len, int depth, std::vector<Vec2>& out);

struct DenseOptions {
  // Chord tolerance: each dense segment deviates from the smooth curve by at most tolerance x h,
  // h = min(q at both ends of the input segment, its length), q the run's spacing field (`size`).
  double tolerance = 1e-3;
  // Dense segments are not split below min_fraction x h (bounds the count where the spacing field
  // is far finer than the curvature radius; the nodes could not resolve such a bend anyway).
  double min_fraction = 1.0 / 16.0;
  double join_tolerance = 1e-9;  // as the input geometry's, for build_geometry
};

// The dense polyline of the smooth curves, built into a validated Geometry with the same curves
// (names, order, files, lines), loops and critical points (same locations, same order) as the input.
struct DenseGeometry {
  Geometry geometry;
  // vertex[c][i]: the index in the dense curve c of input point i (the input points are vertices).
  std::vector<std::vector<int>> vertex;
  // source[s]: the input segment (index into the input Geometry::segments) that dense segment s
  // refines.
  std::vector<int> source;
};

// The length that scales a piece's chord tolerance and shortest chord (DenseOptions): the input
// segment ab's length, or q at an end where that is smaller (a q that is not positive and finite
// is left out).
double piece_scale(Vec2 a, Vec2 b, double qa, double qb);

// Marks a built dense geometry (out.geometry, out.vertex) with the input's: each curve's critical
// flags and the critical points at the dense vertices of their input points (cp.p the dense
// vertex), and each dense segment's source.
void carry_input_marks(const Geometry& input, DenseGeometry& out);

// Builds the dense geometry; size(p) is the spacing field's q at p (the geometry layer knows no
// spacing field: the caller passes its at()). Throws GeometryError when the smooth curves intersect
// themselves or each other (build_geometry's checks; the caller may fall back to the polylines).
DenseGeometry make_dense_geometry(const SmoothCurves& curves, const std::function<double(Vec2)>& size,
                                  const DenseOptions& options = {});

}  // namespace pdmesh
