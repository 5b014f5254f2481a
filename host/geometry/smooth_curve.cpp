// Centripetal Catmull-Rom curves through the input points, corners kept at critical points, and
// their dense polyline as a Geometry (see smooth_curve.hpp and docs/geometry-input.md).
#include "geometry/smooth_curve.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "core/errors.hpp"
#include "geometry/geometry_detail.hpp"

namespace pdmesh {
namespace {

Vec2 unit(Vec2 v) {
  const double n = norm(v);
  return n > 0.0 ? (1.0 / n) * v : Vec2{};
}

// Knot interval of the centripetal parameterization.
double knot(Vec2 a, Vec2 b) { return std::sqrt(dist(a, b)); }

// Derivative with respect to the knot parameter at p, between its neighbours a and b (the
// centripetal Catmull-Rom tangent).
Vec2 knot_derivative(Vec2 a, Vec2 p, Vec2 b) {
  const double d0 = knot(a, p), d1 = knot(p, b);
  return (1.0 / d0) * (p - a) - (1.0 / (d0 + d1)) * (b - a) + (1.0 / d1) * (b - p);
}

// One end of a curve: end 0 is its first point, end 1 its last.
struct CurveEnd {
  int curve = -1;
  int end = 0;
};

// For every curve end, the other curve end at its joint (Geometry::critical lists both ends of a
// joint; a closed curve's two ends are each other's partners).
std::vector<std::array<CurveEnd, 2>> joint_partners(const Geometry& g) {
  std::vector<std::array<CurveEnd, 2>> partner(g.curves.size());
  for (const CriticalPoint& cp : g.critical) {
    if (cp.curves.size() != 2 || cp.indices.size() != 2) continue;
    CurveEnd ends[2];
    for (int k = 0; k < 2; ++k) {
      const Curve& curve = g.curves[static_cast<std::size_t>(cp.curves[k])];
      ends[k] = {cp.curves[k], cp.indices[k] == 0 ? 0 : 1};
      if (cp.indices[k] != 0 && cp.indices[k] + 1 != static_cast<int>(curve.points.size())) ends[k].curve = -1;
    }
    if (ends[0].curve < 0 || ends[1].curve < 0) continue;
    partner[static_cast<std::size_t>(ends[0].curve)][static_cast<std::size_t>(ends[0].end)] = ends[1];
    partner[static_cast<std::size_t>(ends[1].curve)][static_cast<std::size_t>(ends[1].end)] = ends[0];
  }
  return partner;
}

// The point before a curve's start (end == 0) or after its end (end == 1) across its joint, if the
// joint's turning angle is at most `limit`; otherwise nullptr (the curve end is a corner).
const Vec2* joint_neighbour(const Geometry& g, int c, int end, CurveEnd partner, double limit) {
  if (partner.curve < 0) return nullptr;
  const Curve& curve = g.curves[static_cast<std::size_t>(c)];
  const std::size_t n = curve.points.size();
  const Curve& other = g.curves[static_cast<std::size_t>(partner.curve)];
  const std::size_t on = other.points.size();
  // The other curve's point next to the joint: its second point if the joint is its start.
  const Vec2* across = partner.end == 0 ? &other.points[1] : &other.points[on - 2];
  const Vec2 here = end == 0 ? curve.points[0] : curve.points[n - 1];
  const Vec2 inner = end == 0 ? curve.points[1] : curve.points[n - 2];
  const double turn = end == 0 ? detail::turning_angle(here - *across, inner - here)
                               : detail::turning_angle(here - inner, *across - here);
  return turn <= limit ? across : nullptr;
}

// The tangent at a free (corner) end: the neighbouring tangent reflected about the end chord, scaled
// to the chord's length. `chord` points along the curve direction of the end piece.
Vec2 corner_tangent(Vec2 chord, Vec2 neighbour_derivative) {
  const Vec2 c = unit(chord), t = unit(neighbour_derivative);
  if (norm2(t) == 0.0) return chord;
  return norm(chord) * (2.0 * dot(c, t) * c - t);
}

}  // namespace

SmoothCurves::SmoothCurves(const Geometry& geometry, double corner_angle_deg) : geometry_(geometry) {
  const double limit = corner_angle_deg * std::numbers::pi / 180.0;
  const std::size_t curves = geometry.curves.size();
  const std::vector<std::array<CurveEnd, 2>> partner = joint_partners(geometry);
  start_.resize(curves);
  end_.resize(curves);
  for (std::size_t c = 0; c < curves; ++c) {
    const Curve& curve = geometry.curves[c];
    const auto& p = curve.points;
    const std::size_t n = p.size();
    const Vec2* before = joint_neighbour(geometry, static_cast<int>(c), 0, partner[c][0], limit);
    const Vec2* after = joint_neighbour(geometry, static_cast<int>(c), 1, partner[c][1], limit);
    // Knot derivative at every point that has neighbours on both sides within its section; free
    // (corner) points get none here.
    std::vector<Vec2> v(n);
    std::vector<std::uint8_t> free(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const bool interior_corner = i > 0 && i + 1 < n && i < curve.critical.size() && curve.critical[i] != 0;
      if (interior_corner || (i == 0 && before == nullptr) || (i + 1 == n && after == nullptr)) {
        free[i] = 1;
        continue;
      }
      const Vec2 a = i == 0 ? *before : p[i - 1];
      const Vec2 b = i + 1 == n ? *after : p[i + 1];
      v[i] = knot_derivative(a, p[i], b);
    }
    start_[c].resize(n - 1);
    end_[c].resize(n - 1);
    for (std::size_t k = 0; k + 1 < n; ++k) {
      const double delta = knot(p[k], p[k + 1]);
      const Vec2 chord = p[k + 1] - p[k];
      if (free[k] && free[k + 1]) {
        // A section of one segment: a straight line.
        start_[c][k] = end_[c][k] = chord;
        continue;
      }
      start_[c][k] = free[k] ? corner_tangent(chord, v[k + 1]) : delta * v[k];
      end_[c][k] = free[k + 1] ? corner_tangent(chord, v[k]) : delta * v[k + 1];
    }
  }
}

Vec2 SmoothCurves::at(int curve, int piece, double u) const {
  const auto c = static_cast<std::size_t>(curve), k = static_cast<std::size_t>(piece);
  const auto& p = geometry_.curves[c].points;
  if (u <= 0.0) return p[k];
  if (u >= 1.0) return p[k + 1];
  const double u2 = u * u, u3 = u2 * u;
  const double h00 = 2.0 * u3 - 3.0 * u2 + 1.0, h10 = u3 - 2.0 * u2 + u, h01 = -2.0 * u3 + 3.0 * u2, h11 = u3 - u2;
  return h00 * p[k] + h10 * start_[c][k] + h01 * p[k + 1] + h11 * end_[c][k];
}

Vec2 SmoothCurves::derivative(int curve, int piece, double u) const {
  const auto c = static_cast<std::size_t>(curve), k = static_cast<std::size_t>(piece);
  const auto& p = geometry_.curves[c].points;
  const double u2 = u * u;
  const double d00 = 6.0 * u2 - 6.0 * u, d10 = 3.0 * u2 - 4.0 * u + 1.0, d01 = -6.0 * u2 + 6.0 * u,
               d11 = 3.0 * u2 - 2.0 * u;
  return d00 * p[k] + d10 * start_[c][k] + d01 * p[k + 1] + d11 * end_[c][k];
}

void subdivide_piece(const SmoothCurves& s, int c, int k, double u0, Vec2 p0, double u1, Vec2 p1, double tol,
                     double min_len, int depth, std::vector<Vec2>& out) {
  double err = 0.0;
  for (const double f : {0.25, 0.5, 0.75})
    err = std::max(err, detail::distance_to_chord(p0, p1, s.at(c, k, u0 + f * (u1 - u0))));
  if (err > tol && dist(p0, p1) > min_len && depth < 40) {
    const double um = 0.5 * (u0 + u1);
    const Vec2 pm = s.at(c, k, um);
    subdivide_piece(s, c, k, u0, p0, um, pm, tol, min_len, depth + 1, out);
    subdivide_piece(s, c, k, um, pm, u1, p1, tol, min_len, depth + 1, out);
    return;
  }
  out.push_back(p1);
}

double piece_scale(Vec2 a, Vec2 b, double qa, double qb) {
  double h = dist(a, b);
  for (const double q : {qa, qb})
    if (q > 0.0 && std::isfinite(q)) h = std::min(h, q);
  return h;
}

void carry_input_marks(const Geometry& input, DenseGeometry& out) {
  Geometry& g = out.geometry;
  for (std::size_t c = 0; c < input.curves.size(); ++c) {
    const Curve& curve = input.curves[c];
    std::vector<std::uint8_t>& flags = g.curves[c].critical;
    std::fill(flags.begin(), flags.end(), std::uint8_t{0});
    for (std::size_t i = 0; i < curve.points.size(); ++i)
      flags[static_cast<std::size_t>(out.vertex[c][i])] = i < curve.critical.size() ? curve.critical[i] : 0;
  }
  g.critical = input.critical;
  for (CriticalPoint& cp : g.critical) {
    for (std::size_t k = 0; k < cp.curves.size(); ++k)
      cp.indices[k] = out.vertex[static_cast<std::size_t>(cp.curves[k])][static_cast<std::size_t>(cp.indices[k])];
    cp.p = g.curves[static_cast<std::size_t>(cp.curves[0])].points[static_cast<std::size_t>(cp.indices[0])];
  }
  out.source.resize(g.segments.size());
  for (std::size_t c = 0; c < input.curves.size(); ++c) {
    const int first = g.curves[c].first_segment;
    for (std::size_t k = 0; k + 1 < out.vertex[c].size(); ++k)
      for (int j = out.vertex[c][k]; j < out.vertex[c][k + 1]; ++j)
        out.source[static_cast<std::size_t>(first + j)] = input.curves[c].first_segment + static_cast<int>(k);
  }
}

DenseGeometry make_dense_geometry(const SmoothCurves& curves, const std::function<double(Vec2)>& size,
                                  const DenseOptions& options) {
  const Geometry& in = curves.geometry();
  DenseGeometry out;
  std::vector<RawCurve> raw(in.curves.size());
  out.vertex.resize(in.curves.size());
  for (std::size_t c = 0; c < in.curves.size(); ++c) {
    const Curve& curve = in.curves[c];
    RawCurve& r = raw[c];
    r.name = curve.name;
    r.file = curve.file;
    r.line = curve.line;
    r.points.push_back(curve.points[0]);
    r.lines.push_back(curve.line);
    out.vertex[c].push_back(0);
    double q_prev = size(curve.points[0]);
    for (int k = 0; k + 1 < static_cast<int>(curve.points.size()); ++k) {
      const Vec2 a = curve.points[static_cast<std::size_t>(k)], b = curve.points[static_cast<std::size_t>(k) + 1];
      const double q_next = size(b);
      const double h = piece_scale(a, b, q_prev, q_next);
      q_prev = q_next;
      subdivide_piece(curves, static_cast<int>(c), k, 0.0, a, 1.0, b, options.tolerance * h, options.min_fraction * h,
                      0, r.points);
      r.lines.resize(r.points.size(), curve.line + k);
      out.vertex[c].push_back(static_cast<int>(r.points.size()) - 1);
    }
  }
  // No interior corners are detected on the dense curves (corner angle 180): the input's critical
  // points are carried over below, at the same locations and in the same order.
  GeometryOptions geometry_options;
  geometry_options.join_tolerance = options.join_tolerance;
  geometry_options.corner_angle_deg = 180.0;
  try {
    out.geometry = build_geometry(std::move(raw), geometry_options);
  } catch (const GeometryError& e) {
    throw GeometryError(std::string("the smooth curves through the input points (geometry.curves = \"smooth\") ") +
                        "are not a valid geometry: " + e.what());
  }
  carry_input_marks(in, out);
  return out;
}

}  // namespace pdmesh
