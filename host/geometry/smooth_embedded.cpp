// Smooth curves with embedded constraints and points: which input points each smooth curve passes
// through, where the meeting points inserted into segments move, and the dense geometry with its
// checks (see smooth_embedded.hpp and docs/geometry-input.md, "Smooth curves").
#include "geometry/smooth_embedded.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "geometry/geometry_detail.hpp"
#include "geometry/geometry_tree.hpp"

namespace pdmesh {
namespace {

// The turn of the polyline a-p-b at p.
double turning_angle(Vec2 a, Vec2 p, Vec2 b) { return detail::turning_angle(p - a, b - p); }

using detail::where;

std::string point_text(Vec2 p) { return detail::format_point(p); }

// One curve of a meeting point: vertex `index` of input curve `curve`.
struct Member {
  int curve = 0;
  int index = 0;
};

// A meeting point of the input (an entry of Geometry::critical with a member inserted into a
// segment): where the smooth curves put it.
struct Move {
  int entry = 0;               // into Geometry::critical
  std::vector<Member> onto;    // the curves that do not pass through it (one or two)
  std::vector<Member> follow;  // the curves that end (or pass) there and move with it
  std::vector<double> u;       // per `onto` curve: the parameter on its piece
  Vec2 at;
};

class EmbeddedSmoothing {
 public:
  EmbeddedSmoothing(const Geometry& input, double corner_angle_deg, double join_tolerance)
      : in_(input), limit_(corner_angle_deg * std::numbers::pi / 180.0), corner_angle_deg_(corner_angle_deg) {
    tolerance_ = std::max(join_tolerance, 1e-12) * input.extents.diagonal();
    find_candidates();
    decide_drops();
    build_skeleton();
  }

  // Moves the inserted meeting points onto the smooth curves; the curves that end there follow, which
  // changes their own smooth curves (a constraint ending on a constraint that ends on a boundary):
  // repeated until nothing moves.
  void settle() {
    for (int round = 0; round < 16; ++round) {
      const SmoothCurves smooth(skeleton_, corner_angle_deg_);
      double moved = 0.0;
      for (Move& m : moves_) {
        place(smooth, m);
        for (const Member& f : m.follow) {
          Vec2& p = skeleton_.curves[static_cast<std::size_t>(f.curve)]
                        .points[static_cast<std::size_t>(skeleton_index_[f.curve][f.index])];
          moved = std::max(moved, dist(p, m.at));
          p = m.at;
        }
      }
      if (moved == 0.0) return;
    }
  }

  DenseGeometry dense(const std::function<double(Vec2)>& size, const DenseOptions& options) const;

 private:
  // Interior vertices that build_geometry may have inserted into a segment: points of meetings (two
  // curves or more at one place) and points put on a boundary curve where it does not turn (a
  // constraint's every vertex is critical, so a point put on a constraint is not told apart from its
  // input points and stays one). fixed_points curves keep every point.
  void find_candidates() {
    const std::size_t curves = in_.curves.size();
    candidate_.resize(curves);
    for (std::size_t c = 0; c < curves; ++c) candidate_[c].assign(in_.curves[c].points.size(), 0);
    for (const CriticalPoint& cp : in_.critical) {
      for (std::size_t j = 0; j < cp.curves.size(); ++j) {
        const Curve& curve = in_.curves[static_cast<std::size_t>(cp.curves[j])];
        const auto i = static_cast<std::size_t>(cp.indices[j]);
        if (i == 0 || i + 1 >= curve.points.size() || curve.fixed_points) continue;
        const bool placed = cp.curves.size() == 1 && !curve.constraint &&
                            turning_angle(curve.points[i - 1], curve.points[i], curve.points[i + 1]) <= limit_;
        if (cp.curves.size() >= 2 || placed) candidate_[static_cast<std::size_t>(cp.curves[j])][i] = 1;
      }
    }
  }

  // A candidate is dropped when it lies on the chord between the kept points around it (within the
  // join tolerance, as the split puts them); a meeting that cannot move (a curve that must keep the
  // point passes there, or three curves got it) keeps it on every curve.
  void decide_drops() {
    for (;;) {
      drop_.resize(in_.curves.size());
      for (std::size_t c = 0; c < in_.curves.size(); ++c) {
        const auto& p = in_.curves[c].points;
        const std::size_t n = p.size();
        drop_[c].assign(n, 0);
        std::size_t a = 0;
        for (std::size_t i = 1; i + 1 < n; ++i) {
          if (!candidate_[c][i]) {
            a = i;
            continue;
          }
          std::size_t b = i + 1;
          while (b + 1 < n && candidate_[c][b]) ++b;
          if (detail::distance_to_chord(p[a], p[b], p[i]) <= tolerance_)
            drop_[c][i] = 1;
          else
            a = i;
        }
      }
      bool changed = false;
      moves_.clear();
      for (std::size_t e = 0; e < in_.critical.size(); ++e) {
        const CriticalPoint& cp = in_.critical[e];
        Move m;
        m.entry = static_cast<int>(e);
        m.at = cp.p;
        bool pinned = false;
        for (std::size_t j = 0; j < cp.curves.size(); ++j) {
          const Member member{cp.curves[j], cp.indices[j]};
          const Curve& curve = in_.curves[static_cast<std::size_t>(member.curve)];
          if (drop_[static_cast<std::size_t>(member.curve)][static_cast<std::size_t>(member.index)]) {
            m.onto.push_back(member);
          } else {
            m.follow.push_back(member);
            if (!curve.constraint || curve.fixed_points) pinned = true;
          }
        }
        if (m.onto.empty()) continue;
        if (pinned || m.onto.size() > 2) {
          for (const Member& d : m.onto)
            candidate_[static_cast<std::size_t>(d.curve)][static_cast<std::size_t>(d.index)] = 0;
          changed = true;
          continue;
        }
        moves_.push_back(std::move(m));
      }
      if (!changed) return;
    }
  }

  // The curves through their kept points, flagged for SmoothCurves: an interior point is a corner
  // where the curve turns more than the corner angle there (or on a fixed_points curve); curve ends
  // join where ends of the same kind (boundary or constraint) meet, as two and no more, constraint
  // ends only away from the boundary curves.
  void build_skeleton() {
    const std::size_t curves = in_.curves.size();
    skeleton_index_.resize(curves);
    input_index_.resize(curves);
    skeleton_.curves.resize(curves);
    for (std::size_t c = 0; c < curves; ++c) {
      const Curve& curve = in_.curves[c];
      Curve& s = skeleton_.curves[c];
      s.name = curve.name;
      s.constraint = curve.constraint;
      s.fixed_points = curve.fixed_points;
      skeleton_index_[c].assign(curve.points.size(), -1);
      for (std::size_t i = 0; i < curve.points.size(); ++i) {
        if (drop_[c][i]) {
          // A dropped point lies in the piece that starts at the last kept point.
          skeleton_index_[c][i] = static_cast<int>(s.points.size()) - 1;
          continue;
        }
        skeleton_index_[c][i] = static_cast<int>(s.points.size());
        input_index_[c].push_back(static_cast<int>(i));
        s.points.push_back(curve.points[i]);
      }
      const std::size_t n = s.points.size();
      s.critical.assign(n, 0);
      for (std::size_t i = 1; i + 1 < n; ++i)
        s.critical[i] =
            curve.fixed_points || turning_angle(s.points[i - 1], s.points[i], s.points[i + 1]) > limit_ ? 1 : 0;
    }
    for (const CriticalPoint& cp : in_.critical) {
      const bool on_boundary = std::any_of(cp.curves.begin(), cp.curves.end(),
                                           [&](int c) { return !in_.curves[static_cast<std::size_t>(c)].constraint; });
      for (const bool constraint : {false, true}) {
        // Constraint ends that meet on a boundary curve are free ends (two borders between regions
        // that reach the coast there are not one line), so that each meets it at its own angle.
        if (constraint && on_boundary) continue;
        CriticalPoint part{cp.p, {}, {}};
        for (std::size_t j = 0; j < cp.curves.size(); ++j) {
          const auto c = static_cast<std::size_t>(cp.curves[j]);
          const auto i = static_cast<std::size_t>(cp.indices[j]);
          if (in_.curves[c].constraint != constraint || drop_[c][i]) continue;
          part.curves.push_back(cp.curves[j]);
          part.indices.push_back(skeleton_index_[c][i]);
        }
        if (!part.curves.empty()) skeleton_.critical.push_back(std::move(part));
      }
    }
  }

  // Where move m's point lies on the current smooth curves.
  void place(const SmoothCurves& smooth, Move& m) const {
    const Vec2 p0 = in_.critical[static_cast<std::size_t>(m.entry)].p;
    m.u.clear();
    if (m.onto.size() == 1) {
      const auto [c, k] = piece_of(m.onto[0]);
      const double u = nearest_on_piece(smooth, c, k, p0);
      m.u.push_back(u);
      m.at = smooth.at(c, k, u);
      return;
    }
    const auto [c1, k1] = piece_of(m.onto[0]);
    const auto [c2, k2] = piece_of(m.onto[1]);
    const auto& s1 = skeleton_.curves[static_cast<std::size_t>(c1)].points;
    const auto& s2 = skeleton_.curves[static_cast<std::size_t>(c2)].points;
    double u1 = detail::chord_param(s1[static_cast<std::size_t>(k1)], s1[static_cast<std::size_t>(k1) + 1], p0);
    double u2 = detail::chord_param(s2[static_cast<std::size_t>(k2)], s2[static_cast<std::size_t>(k2) + 1], p0);
    // Newton's method on at1(u1) = at2(u2): the smooth pieces lie close to their chords, which cross
    // at p0, so the crossing is near the chord parameters.
    bool converged = false;
    for (int it = 0; it < 50 && !converged; ++it) {
      const Vec2 f = smooth.at(c1, k1, u1) - smooth.at(c2, k2, u2);
      const Vec2 d1 = smooth.derivative(c1, k1, u1), d2 = smooth.derivative(c2, k2, u2);
      const double det = cross(d1, d2);
      if (!(std::fabs(det) > 0.0)) break;
      // Solve d1 du1 - d2 du2 = -f.
      const double du1 = cross(f, d2) / det, du2 = cross(f, d1) / det;
      u1 = std::clamp(u1 - du1, -0.5, 1.5);
      u2 = std::clamp(u2 - du2, -0.5, 1.5);
      converged = std::fabs(du1) <= 1e-15 && std::fabs(du2) <= 1e-15;
      if (!converged && it > 5) converged = norm(smooth.at(c1, k1, u1) - smooth.at(c2, k2, u2)) <= 1e-15 * scale();
    }
    const Curve& a = in_.curves[static_cast<std::size_t>(c1)];
    const Curve& b = in_.curves[static_cast<std::size_t>(c2)];
    if (!converged || u1 <= 0.0 || u1 >= 1.0 || u2 <= 0.0 || u2 >= 1.0)
      throw GeometryError(fmt::format(
          "the smooth curves '{}' and '{}' do not cross within the segments whose polylines cross at {} ({}, {})",
          a.name, b.name, point_text(p0), where(a.file, a.line), where(b.file, b.line)));
    m.u = {u1, u2};
    m.at = smooth.at(c1, k1, u1);
  }

  // The skeleton curve and piece that a dropped member lies in.
  std::pair<int, int> piece_of(Member m) const { return {m.curve, skeleton_index_[m.curve][m.index]}; }

  // The parameter of the point of piece k of curve c nearest p: the best of 65 samples, then a
  // golden-section search between its neighbours.
  static double nearest_on_piece(const SmoothCurves& smooth, int c, int k, Vec2 p) {
    constexpr int kSamples = 64;
    int best = 0;
    double best_d = HUGE_VAL;
    for (int j = 0; j <= kSamples; ++j) {
      const double d = norm2(smooth.at(c, k, static_cast<double>(j) / kSamples) - p);
      if (d < best_d) {
        best_d = d;
        best = j;
      }
    }
    double lo = std::max(0.0, (best - 1.0) / kSamples), hi = std::min(1.0, (best + 1.0) / kSamples);
    const double g = (std::sqrt(5.0) - 1.0) / 2.0;
    for (int it = 0; it < 80 && hi - lo > 1e-15; ++it) {
      const double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
      if (norm2(smooth.at(c, k, x1) - p) <= norm2(smooth.at(c, k, x2) - p))
        hi = x2;
      else
        lo = x1;
    }
    return 0.5 * (lo + hi);
  }

  double scale() const { return std::max(1.0, in_.extents.diagonal()); }

  const Geometry& in_;
  double limit_ = 0.0;
  double corner_angle_deg_ = 0.0;
  double tolerance_ = 0.0;
  std::vector<std::vector<std::uint8_t>> candidate_, drop_;
  std::vector<Move> moves_;
  Geometry skeleton_;                             // the kept points of every curve, with moved ends
  std::vector<std::vector<int>> skeleton_index_;  // input vertex -> skeleton vertex (dropped: its piece)
  std::vector<std::vector<int>> input_index_;     // skeleton vertex -> input vertex
};

// One point to put into a piece of the dense polyline: input vertex `vertex` at parameter u.
struct PieceInsert {
  double u = 0.0;
  Vec2 p;
  int vertex = 0;
};

DenseGeometry EmbeddedSmoothing::dense(const std::function<double(Vec2)>& size, const DenseOptions& options) const {
  const SmoothCurves smooth(skeleton_, corner_angle_deg_);
  const std::size_t curves = in_.curves.size();
  // The moved points, per curve and piece.
  std::vector<std::vector<std::vector<PieceInsert>>> inserts(curves);
  for (std::size_t c = 0; c < curves; ++c) inserts[c].resize(skeleton_.curves[c].points.size());
  for (const Move& m : moves_)
    for (std::size_t j = 0; j < m.onto.size(); ++j) {
      const auto [c, k] = piece_of(m.onto[j]);
      inserts[static_cast<std::size_t>(c)][static_cast<std::size_t>(k)].push_back({m.u[j], m.at, m.onto[j].index});
    }
  DenseGeometry out;
  RawGeometry raw;
  raw.curves.resize(curves);
  out.vertex.resize(curves);
  for (std::size_t c = 0; c < curves; ++c) {
    const Curve& curve = in_.curves[c];
    const auto& sp = skeleton_.curves[c].points;
    RawCurve& r = raw.curves[c];
    r.name = curve.name;
    r.file = curve.file;
    r.line = curve.line;
    r.constraint = curve.constraint;
    out.vertex[c].assign(curve.points.size(), -1);
    r.points.push_back(sp[0]);
    r.lines.push_back(curve.line);
    out.vertex[c][0] = 0;
    for (std::size_t k = 0; k + 1 < sp.size(); ++k) {
      const Vec2 a = sp[k], b = sp[k + 1];
      const double h = piece_scale(a, b, size(a), size(b));
      const double tol = options.tolerance * h, min_len = options.min_fraction * h;
      std::vector<PieceInsert> list = inserts[c][k];
      std::sort(list.begin(), list.end(), [](const PieceInsert& x, const PieceInsert& y) { return x.u < y.u; });
      double u0 = 0.0;
      Vec2 p0 = a;
      int from = input_index_[c][k];
      for (const PieceInsert& ins : list) {
        // The moved points keep their order along the curve, or the input segments would not map.
        if (ins.vertex <= from)
          throw GeometryError(
              fmt::format("the meeting points on curve '{}' near {} change their order on its smooth curve ({})",
                          curve.name, point_text(ins.p), where(curve.file, curve.line)));
        subdivide_piece(smooth, static_cast<int>(c), static_cast<int>(k), u0, p0, ins.u, ins.p, tol, min_len, 0,
                        r.points);
        r.lines.resize(r.points.size(), curve.line + from);
        out.vertex[c][static_cast<std::size_t>(ins.vertex)] = static_cast<int>(r.points.size()) - 1;
        u0 = ins.u;
        p0 = ins.p;
        from = ins.vertex;
      }
      subdivide_piece(smooth, static_cast<int>(c), static_cast<int>(k), u0, p0, 1.0, b, tol, min_len, 0, r.points);
      r.lines.resize(r.points.size(), curve.line + from);
      out.vertex[c][static_cast<std::size_t>(input_index_[c][k + 1])] = static_cast<int>(r.points.size()) - 1;
    }
  }
  for (std::size_t c = 0; c < curves; ++c)
    if (std::find(out.vertex[c].begin(), out.vertex[c].end(), -1) != out.vertex[c].end())
      throw GeometryError(fmt::format("curve '{}': an input point has no place on its smooth curve ({})",
                                      in_.curves[c].name, where(in_.curves[c].file, in_.curves[c].line)));
  std::vector<std::vector<Vec2>> put(curves);
  for (std::size_t c = 0; c < curves; ++c) put[c] = raw.curves[c].points;
  raw.points = in_.embedded_points;
  // No interior corners on the dense curves (corner angle 180): the input's critical points are
  // carried over below, at their (moved) locations and in the same order.
  GeometryOptions geometry_options;
  geometry_options.join_tolerance = options.join_tolerance;
  geometry_options.corner_angle_deg = 180.0;
  const std::string prefix =
      "the smooth curves through the input points (geometry.curves = \"smooth\") are not a valid geometry: ";
  try {
    out.geometry = build_geometry(std::move(raw), geometry_options);
  } catch (const GeometryError& e) {
    throw GeometryError(prefix + e.what());
  }
  Geometry& g = out.geometry;
  // The dense curves meet where the input's do, at shared vertices; a point build_geometry inserted
  // is a meeting the polylines do not have (a smoothed constraint bulging across another curve).
  for (std::size_t c = 0; c < curves; ++c) {
    const auto& pts = g.curves[c].points;
    if (pts == put[c]) continue;
    std::size_t j = 0;
    while (j < put[c].size() && pts[j] == put[c][j]) ++j;
    const Vec2 at = pts[j];
    std::string other = "another curve";
    for (std::size_t d = 0; d < curves; ++d) {
      const auto& dp = g.curves[d].points;
      if (d != c && std::find(dp.begin(), dp.end(), at) != dp.end()) {
        other = fmt::format("'{}'", g.curves[d].name);
        break;
      }
    }
    throw GeometryError(prefix + fmt::format("the smooth curve '{}' meets {} at {}, where the input polylines do not "
                                             "meet ({}); a smoothed curve bulges across the other",
                                             g.curves[c].name, other, point_text(at),
                                             where(in_.curves[c].file, in_.curves[c].line)));
  }
  if (g.embedded_points.size() != in_.embedded_points.size()) {
    for (const RawPoint& rp : in_.embedded_points) {
      const bool kept = std::any_of(g.embedded_points.begin(), g.embedded_points.end(),
                                    [&](const RawPoint& e) { return e.p == rp.p; });
      if (!kept)
        throw GeometryError(
            prefix + fmt::format("{}: point {} lies on a smooth curve", where(rp.file, rp.line), point_text(rp.p)));
    }
  }
  if (!g.embedded_points.empty()) {
    // A point closer to a smooth curve than the dense polyline's accuracy is on it as far as the
    // dense polyline can tell: on which side it lies is not known.
    const GeometryTree tree(g);
    for (const RawPoint& rp : g.embedded_points) {
      const ClosestHit hit = tree.closest(rp.p);
      const double q = size(rp.p);
      const double accuracy = options.tolerance * (q > 0.0 && std::isfinite(q) ? q : 0.0);
      if (hit.segment >= 0 && hit.distance <= accuracy) {
        const Curve& near = g.curves[static_cast<std::size_t>(g.segments[static_cast<std::size_t>(hit.segment)].curve)];
        throw GeometryError(
            prefix + fmt::format("{}: point {} lies {:.3g} from the smooth curve '{}', within the dense polyline's "
                                 "accuracy ({:.3g}); an embedded point must lie clearly inside the domain",
                                 where(rp.file, rp.line), point_text(rp.p), hit.distance, near.name, accuracy));
      }
    }
  }
  // The input's critical flags and points, at the dense vertices (moved meeting points included).
  carry_input_marks(in_, out);
  return out;
}

}  // namespace

DenseGeometry make_dense_embedded(const Geometry& input, double corner_angle_deg,
                                  const std::function<double(Vec2)>& size, const DenseOptions& options) {
  const bool embedded = !input.embedded_points.empty() || std::any_of(input.curves.begin(), input.curves.end(),
                                                                      [](const Curve& c) { return c.constraint; });
  if (!embedded) return make_dense_geometry(SmoothCurves(input, corner_angle_deg), size, options);
  EmbeddedSmoothing smoothing(input, corner_angle_deg, options.join_tolerance);
  smoothing.settle();
  return smoothing.dense(size, options);
}

}  // namespace pdmesh
