// boundary.nodes = "spacing": boundary nodes re-placed along each curve between its critical points
// at equal integral of ds/q, then shortened where a chord strays from the curve (the validity rule).
#include "init/boundary_placement.hpp"

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"
#include "fmt/format.h"

namespace pdmesh {
namespace {

// Sub-intervals per q of arc length for the integral of ds/q (midpoint rule on each).
constexpr double kSamplesPerSpacing = 4.0;
// At most this many sub-intervals per polyline segment (a segment far longer than q).
constexpr int kMaxSamplesPerSegment = 1 << 16;

// One section of a curve between consecutive critical vertices, sampled for the integral: the
// sub-interval ends in arc length (ends[0] = arc of the first vertex), and per sub-interval q at
// its midpoint, the cap the validity rule puts on the edge length there, and the target length
// h = min(q, cap).
struct Section {
  int first = 0, last = 0;  // vertex indices
  std::vector<double> ends;
  std::vector<double> q;
  std::vector<double> cap;
  std::vector<double> h;
};

double checked_q(const SpacingField& spacing, const Curve& curve, Vec2 p) {
  const double q = spacing.at(p);
  if (!(q > 0.0) || !std::isfinite(q))
    throw LimitError(
        fmt::format("boundary nodes: the spacing at ({}, {}) on curve '{}' is {}; it must be a positive "
                    "finite number",
                    p.x, p.y, curve.name, q));
  return q;
}

Section sample_section(const Curve& curve, const SpacingField& spacing, int first, int last) {
  Section s;
  s.first = first;
  s.last = last;
  s.ends.push_back(curve.arc[static_cast<std::size_t>(first)]);
  for (int k = first; k < last; ++k) {
    const auto i = static_cast<std::size_t>(k);
    const double a0 = curve.arc[i], a1 = curve.arc[i + 1], len = a1 - a0;
    const Vec2 pa = curve.points[i], pb = curve.points[i + 1];
    const double q_mid = checked_q(spacing, curve, 0.5 * (pa + pb));
    const double want = std::ceil(kSamplesPerSpacing * len / q_mid);
    const int m = want >= kMaxSamplesPerSegment ? kMaxSamplesPerSegment : std::max(1, static_cast<int>(want));
    for (int j = 0; j < m; ++j) {
      const double t = (j + 0.5) / m;
      s.q.push_back(m == 1 ? q_mid : checked_q(spacing, curve, pa + t * (pb - pa)));
      s.ends.push_back(j + 1 == m ? a1 : a0 + (j + 1.0) / m * len);
    }
  }
  s.h = s.q;
  s.cap.assign(s.q.size(), INFINITY);
  return s;
}

// Arc positions of the n - 1 interior nodes at equal steps of the integral of ds/h.
std::vector<double> equal_integral(const Section& s, int n) {
  std::vector<double> cumulative(s.ends.size(), 0.0);
  for (std::size_t i = 0; i < s.h.size(); ++i) cumulative[i + 1] = cumulative[i] + (s.ends[i + 1] - s.ends[i]) / s.h[i];
  const double total = cumulative.back();
  std::vector<double> arcs;
  std::size_t i = 0;
  for (int j = 1; j < n; ++j) {
    const double target = total * j / n;
    while (i + 1 < s.h.size() && cumulative[i + 1] < target) ++i;
    // Within sub-interval i the integrand is constant: linear in arc length.
    const double f = std::clamp((target - cumulative[i]) / (cumulative[i + 1] - cumulative[i]), 0.0, 1.0);
    arcs.push_back(s.ends[i] + f * (s.ends[i + 1] - s.ends[i]));
  }
  return arcs;
}

double section_integral(const Section& s) {
  double total = 0.0;
  for (std::size_t i = 0; i < s.h.size(); ++i) total += (s.ends[i + 1] - s.ends[i]) / s.h[i];
  return total;
}

// Caps the edge length at `target` over [a, b]; the cap grows by at most `grading` per unit arc
// length away from there (forward and backward sweeps over the sub-interval midpoints), so that the
// edge lengths change gradually along the curve. q itself is not graded.
void shorten(Section& s, double a, double b, double target, double grading) {
  const std::size_t m = s.cap.size();
  for (std::size_t i = 0; i < m; ++i)
    if (s.ends[i + 1] > a && s.ends[i] < b) s.cap[i] = std::min(s.cap[i], target);
  auto mid = [&](std::size_t i) { return 0.5 * (s.ends[i] + s.ends[i + 1]); };
  for (std::size_t i = 1; i < m; ++i) s.cap[i] = std::min(s.cap[i], s.cap[i - 1] + grading * (mid(i) - mid(i - 1)));
  for (std::size_t i = m - 1; i-- > 0;) s.cap[i] = std::min(s.cap[i], s.cap[i + 1] + grading * (mid(i + 1) - mid(i)));
  for (std::size_t i = 0; i < m; ++i) s.h[i] = std::min(s.q[i], s.cap[i]);
}

}  // namespace

Vec2 point_at_arc(const Curve& curve, double s) {
  const int segments = curve.segment_count();
  if (s <= 0.0) return curve.points.front();
  if (s >= curve.length()) return curve.points.back();
  int k = static_cast<int>(std::upper_bound(curve.arc.begin(), curve.arc.end(), s) - curve.arc.begin()) - 1;
  k = std::clamp(k, 0, segments - 1);
  const auto i = static_cast<std::size_t>(k);
  const double t = (s - curve.arc[i]) / (curve.arc[i + 1] - curve.arc[i]);
  return curve.points[i] + t * (curve.points[i + 1] - curve.points[i]);
}

double chord_deviation(const Curve& curve, double arc_a, double arc_b) {
  const Vec2 a = point_at_arc(curve, arc_a), b = point_at_arc(curve, arc_b), d = b - a;
  const double len2 = norm2(d);
  double worst = 0.0;
  auto k = static_cast<std::size_t>(std::upper_bound(curve.arc.begin(), curve.arc.end(), arc_a) - curve.arc.begin());
  for (; k < curve.points.size() && curve.arc[k] < arc_b; ++k) {
    const Vec2 p = curve.points[k];
    const double t = len2 > 0.0 ? std::clamp(dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
    worst = std::max(worst, dist(p, a + t * d));
  }
  return worst;
}

CurveStations spacing_stations(const Geometry& geometry, const SpacingField& spacing, const PlacementOptions& options) {
  const auto refuse = [&](double count) {
    throw LimitError(
        fmt::format("the spacing field asks for about {:.0f} boundary nodes (estimate: the integral of "
                    "ds/q along the curves, boundary.nodes = \"spacing\"), more than --max-nodes {}; "
                    "coarsen the spacing or raise --max-nodes",
                    count, options.max_nodes));
  };
  // A first count from q at the segment midpoints, so that an absurd field is refused before the
  // curves are sampled finely.
  if (options.max_nodes > 0) {
    double coarse = 0.0;
    for (const Curve& curve : geometry.curves)
      for (int k = 0; k < curve.segment_count(); ++k) {
        const auto i = static_cast<std::size_t>(k);
        coarse += (curve.arc[i + 1] - curve.arc[i]) /
                  checked_q(spacing, curve, 0.5 * (curve.points[i] + curve.points[i + 1]));
      }
    if (coarse > 2.0 * static_cast<double>(options.max_nodes)) refuse(coarse);
  }
  // The sections of every curve, sampled; the node count is checked against the limit before any
  // node is placed.
  std::vector<std::vector<Section>> sections(geometry.curves.size());
  double count = 0.0;
  for (std::size_t c = 0; c < geometry.curves.size(); ++c) {
    const Curve& curve = geometry.curves[c];
    const int n = static_cast<int>(curve.points.size());
    int first = 0;
    for (int k = 1; k < n; ++k) {
      const bool critical =
          k == n - 1 || (static_cast<std::size_t>(k) < curve.critical.size() && curve.critical[k] != 0);
      if (!critical) continue;
      sections[c].push_back(sample_section(curve, spacing, first, k));
      count += std::max(1.0, std::round(section_integral(sections[c].back())));
      first = k;
    }
  }
  if (options.max_nodes > 0 && count > static_cast<double>(options.max_nodes)) refuse(count);

  CurveStations stations(geometry.curves.size());
  for (std::size_t c = 0; c < geometry.curves.size(); ++c) {
    const Curve& curve = geometry.curves[c];
    std::vector<BoundaryStation>& out = stations[c];
    out.push_back({curve.points[0], 0, 0.0});
    for (Section& s : sections[c]) {
      if (curve.fixed_points) {  // a layer front: its points are its nodes, none between them
        out.push_back(
            {curve.points[static_cast<std::size_t>(s.last)], s.last, curve.arc[static_cast<std::size_t>(s.last)]});
        continue;
      }
      std::vector<double> arcs;
      for (int round = 0;; ++round) {
        const int n = std::max(1, static_cast<int>(std::lround(section_integral(s))));
        arcs = equal_integral(s, n);
        arcs.insert(arcs.begin(), s.ends.front());
        arcs.push_back(s.ends.back());
        if (round == options.max_rounds) break;
        // The validity rule on every edge; a breach shortens h there, and the section is placed again.
        bool breached = false;
        for (std::size_t e = 0; e + 1 < arcs.size(); ++e) {
          const double dev = chord_deviation(curve, arcs[e], arcs[e + 1]);
          if (dev == 0.0) continue;
          const double sigma =
              0.5 * (spacing.at(point_at_arc(curve, arcs[e])) + spacing.at(point_at_arc(curve, arcs[e + 1])));
          const double allowed = options.max_deviation * sigma;
          if (dev <= allowed) continue;
          // The deviation falls at least linearly with the edge length (a corner between the nodes);
          // 0.9 leaves a margin for where the new nodes land.
          const double length = arcs[e + 1] - arcs[e];
          shorten(s, arcs[e], arcs[e + 1], 0.9 * length * allowed / dev, options.grading);
          breached = true;
        }
        if (!breached) break;
      }
      for (std::size_t j = 1; j + 1 < arcs.size(); ++j) out.push_back({point_at_arc(curve, arcs[j]), -1, arcs[j]});
      out.push_back(
          {curve.points[static_cast<std::size_t>(s.last)], s.last, curve.arc[static_cast<std::size_t>(s.last)]});
    }
  }
  return stations;
}

std::vector<double> station_resolution(const Geometry& geometry, const CurveStations& stations) {
  std::vector<double> resolution(geometry.segments.size(), INFINITY);
  for (std::size_t c = 0; c < geometry.curves.size(); ++c) {
    const Curve& curve = geometry.curves[c];
    const auto& st = stations[c];
    std::size_t k = 0;  // the segment holding the current edge's start
    for (std::size_t e = 0; e + 1 < st.size(); ++e) {
      const double length = dist(st[e].p, st[e + 1].p);
      while (k + 1 < curve.arc.size() - 1 && curve.arc[k + 1] <= st[e].arc) ++k;
      // Segments k, k+1, ... up to the one holding the edge's end.
      for (std::size_t j = k; j + 1 < curve.arc.size() && curve.arc[j] < st[e + 1].arc; ++j) {
        double& r = resolution[static_cast<std::size_t>(curve.first_segment) + j];
        r = std::min(r, length);
      }
    }
  }
  return resolution;
}

NodeSet place_boundary_nodes(const Geometry& node_geometry, const SpacingField& spacing, BoundaryNodeRule rule,
                             const std::vector<std::vector<int>>* input_vertices, const PlacementOptions& options) {
  if (rule == BoundaryNodeRule::Spacing)
    return assemble_boundary_nodes(node_geometry, spacing, spacing_stations(node_geometry, spacing, options));
  return assemble_boundary_nodes(node_geometry, spacing, vertex_stations(node_geometry, input_vertices));
}

}  // namespace pdmesh
