// Mesh quality metrics of the thesis appendix, per triangle and summarised over a mesh.
#include "mesh/quality.hpp"

#include "mesh/quality_sum.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/parallel.hpp"

namespace pdmesh {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

// 2x2 matrix [[a, b], [c, d]] (row-major), just enough for K_W.
struct Mat2 {
  double a, b, c, d;
};

Mat2 mul(const Mat2& m, const Mat2& n) {
  return {m.a * n.a + m.b * n.c, m.a * n.b + m.b * n.d, m.c * n.a + m.d * n.c, m.c * n.b + m.d * n.d};
}
double det(const Mat2& m) { return m.a * m.d - m.b * m.c; }
Mat2 inverse(const Mat2& m) {
  const double dt = det(m);
  return {m.d / dt, -m.b / dt, -m.c / dt, m.a / dt};
}
// ||M|| = sqrt(tr(M^T M)), the Frobenius norm.
double frobenius(const Mat2& m) { return std::sqrt(m.a * m.a + m.b * m.b + m.c * m.c + m.d * m.d); }

// Included angle at `corner` in degrees; atan2 of |cross| and dot is accurate near 0 and 180.
double angle_deg(Vec2 corner, Vec2 p, Vec2 q) {
  const Vec2 u = p - corner, v = q - corner;
  return std::atan2(std::fabs(cross(u, v)), dot(u, v)) * 180.0 / kPi;
}

}  // namespace

double weighted_condition_number(Vec2 a, Vec2 b, Vec2 c) {
  const Vec2 u = b - a, v = c - a;
  const Mat2 A{u.x, v.x, u.y, v.y};
  if (det(A) == 0.0) return kInf;
  const Mat2 W{1.0, 0.5, 0.0, std::sqrt(3.0) / 2.0};
  return frobenius(mul(A, inverse(W))) * frobenius(mul(W, inverse(A))) / 2.0;
}

double corner_jacobian(Vec2 corner, Vec2 next, Vec2 prev) {
  const Vec2 u = next - corner, v = prev - corner;
  const double lu = norm(u), lv = norm(v);
  if (lu == 0.0 || lv == 0.0) return 0.0;
  return cross((1.0 / lu) * u, (1.0 / lv) * v);
}

namespace {

// The angles, edge lengths and aspect ratio of a triangle: one body for triangle_quality and
// triangle_shape, so that both give the same values bit for bit.
struct Shape {
  double angles[3];
  double la, lb, lc;  // la opposite a, and so on
  double aspect_ratio;
};

inline Shape shape_of(Vec2 a, Vec2 b, Vec2 c) {
  Shape s{{angle_deg(a, b, c), angle_deg(b, c, a), angle_deg(c, a, b)}, dist(b, c), dist(c, a), dist(a, b), 0.0};
  // R = la lb lc / (4 area), r = area / s with s the half perimeter, so
  // R / (2 r) = la lb lc s / (8 area^2).
  const double area = 0.5 * std::fabs(cross(b - a, c - a));
  const double half = 0.5 * (s.la + s.lb + s.lc);
  s.aspect_ratio = area > 0.0 ? s.la * s.lb * s.lc * half / (8.0 * area * area) : kInf;
  return s;
}

}  // namespace

TriangleQuality triangle_quality(Vec2 a, Vec2 b, Vec2 c) {
  TriangleQuality t;
  const Shape s = shape_of(a, b, c);
  t.min_angle = std::min({s.angles[0], s.angles[1], s.angles[2]});
  t.max_angle = std::max({s.angles[0], s.angles[1], s.angles[2]});
  const double lmin = std::min({s.la, s.lb, s.lc}), lmax = std::max({s.la, s.lb, s.lc});
  t.skewness = lmin > 0.0 ? lmax / lmin : kInf;
  t.aspect_ratio = s.aspect_ratio;
  t.condition_number = weighted_condition_number(a, b, c);
  t.min_jacobian = std::min({corner_jacobian(a, b, c), corner_jacobian(b, c, a), corner_jacobian(c, a, b)});
  return t;
}

TriangleShape triangle_shape(Vec2 a, Vec2 b, Vec2 c) {
  const Shape s = shape_of(a, b, c);
  return {std::min({s.angles[0], s.angles[1], s.angles[2]}), s.aspect_ratio};
}

namespace {

// InputError naming the first triangle that refers to a point the mesh does not have.
void check_triangle_indices(const Mesh& mesh) {
  const auto n = static_cast<int>(mesh.points.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int v : mesh.triangles[t])
      if (v < 0 || v >= n)
        throw InputError(fmt::format("mesh triangle {} refers to point {} but the mesh has {} points", t, v, n));
}

double TriangleQuality::*metric_member(const std::string& metric) {
  if (metric == "min_angle") return &TriangleQuality::min_angle;
  if (metric == "max_angle") return &TriangleQuality::max_angle;
  if (metric == "aspect_ratio") return &TriangleQuality::aspect_ratio;
  if (metric == "skewness") return &TriangleQuality::skewness;
  if (metric == "condition_number") return &TriangleQuality::condition_number;
  if (metric == "min_jacobian") return &TriangleQuality::min_jacobian;
  throw InputError(
      fmt::format("unknown quality metric '{}' (choose min_angle, max_angle, aspect_ratio, skewness, "
                  "condition_number or min_jacobian)",
                  metric));
}

}  // namespace

std::vector<TriangleQuality> triangle_qualities(const Mesh& mesh) {
  check_triangle_indices(mesh);
  // On several threads, each triangle its own entry: the values of a loop on one thread.
  std::vector<TriangleQuality> out(mesh.triangles.size());
  parallel_for(
      out.size(),
      [&](std::size_t t) {
        const auto& tri = mesh.triangles[t];
        out[t] = triangle_quality(mesh.points[tri[0]], mesh.points[tri[1]], mesh.points[tri[2]]);
      },
      8192);
  return out;
}

std::vector<double> metric_values(const std::vector<TriangleQuality>& q, const std::string& metric) {
  double TriangleQuality::*member = metric_member(metric);
  std::vector<double> v;
  v.reserve(q.size());
  for (const TriangleQuality& t : q) v.push_back(t.*member);
  return v;
}

void Histogram::add(double value) {
  if (counts.empty()) return;
  const double k = std::floor((value - lo) / width);
  if (!(k < static_cast<double>(counts.size()))) {
    ++overflow;  // also NaN and +infinity
  } else {
    counts[k < 0.0 ? 0 : static_cast<std::size_t>(k)]++;
  }
}

double percentile_sorted(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) return 0.0;
  const double pos = std::clamp(p, 0.0, 1.0) * static_cast<double>(sorted.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  const double frac = pos - static_cast<double>(lo);
  return sorted[lo] + frac * (sorted[hi] - sorted[lo]);
}

QualityAccumulator::QualityAccumulator(const QualityOptions& options) : options_(options) {
  QualitySummary& s = s_;
  s.small_angle_deg = options.small_angle_deg;
  // Min angles never exceed 60 degrees; the 60-degree edge itself falls in the last bin.
  const auto angle_bins = static_cast<std::size_t>(std::ceil(60.0 / options.angle_bin_width));
  s.min_angle_histogram = Histogram{0.0, options.angle_bin_width, std::vector<std::size_t>(angle_bins, 0), 0};
  s.aspect_ratio_histogram = Histogram{1.0, options.aspect_bin_width,
                                       std::vector<std::size_t>(static_cast<std::size_t>(options.aspect_bins), 0), 0};
  s.min_angle = kInf;
  s.max_angle = -kInf;
  s.min_jacobian = kInf;
  s.aspect_ratio_max = s.skewness_max = s.condition_number_max = -kInf;
}

void QualityAccumulator::add(const TriangleQuality& t) {
  QualitySummary& s = s_;
  ++s.triangles;
  s.min_angle = std::min(s.min_angle, t.min_angle);
  s.max_angle = std::max(s.max_angle, t.max_angle);
  s.min_jacobian = std::min(s.min_jacobian, t.min_jacobian);
  s.aspect_ratio_max = std::max(s.aspect_ratio_max, t.aspect_ratio);
  s.skewness_max = std::max(s.skewness_max, t.skewness);
  s.condition_number_max = std::max(s.condition_number_max, t.condition_number);
  ar_sum_ += t.aspect_ratio;
  skew_sum_ += t.skewness;
  k_sum_ += t.condition_number;
  s.small_angle_triangles += (t.min_angle < options_.small_angle_deg);
  // The 60-degree edge belongs to the last bin (an equilateral triangle is not "overflow").
  s.min_angle_histogram.add(std::min(t.min_angle, 60.0 - 0.5 * options_.angle_bin_width));
  s.aspect_ratio_histogram.add(t.aspect_ratio);
}

QualitySummary QualityAccumulator::summary() const {
  QualitySummary s = s_;
  if (s.triangles == 0) {
    // No triangle: zero values, as an empty mesh's summary has.
    s.min_angle = s.max_angle = s.min_jacobian = 0.0;
    s.aspect_ratio_max = s.skewness_max = s.condition_number_max = 0.0;
    return s;
  }
  const auto n = static_cast<double>(s.triangles);
  s.aspect_ratio_avg = ar_sum_ / n;
  s.skewness_avg = skew_sum_ / n;
  s.condition_number_avg = k_sum_ / n;
  s.small_angle_share = static_cast<double>(s.small_angle_triangles) / n;
  return s;
}

QualitySummary summarize_quality(const std::vector<TriangleQuality>& per_triangle, const QualityOptions& options) {
  QualityAccumulator sum(options);
  for (const TriangleQuality& t : per_triangle) sum.add(t);
  return sum.summary();
}

QualitySummary summarize_quality_of(const Mesh& mesh, const QualityOptions& options) {
  check_triangle_indices(mesh);
  QualityAccumulator sum(options);
  for (const auto& tri : mesh.triangles)
    sum.add(triangle_quality(mesh.points[tri[0]], mesh.points[tri[1]], mesh.points[tri[2]]));
  return sum.summary();
}

std::vector<double> mesh_metric_values(const Mesh& mesh, const std::string& metric) {
  double TriangleQuality::*member = metric_member(metric);
  check_triangle_indices(mesh);
  std::vector<double> v;
  v.reserve(mesh.triangles.size());
  for (const auto& tri : mesh.triangles)
    v.push_back(triangle_quality(mesh.points[tri[0]], mesh.points[tri[1]], mesh.points[tri[2]]).*member);
  return v;
}

std::vector<std::pair<int, int>> unique_edges(const Mesh& mesh) {
  const auto n = static_cast<int>(mesh.points.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int v : mesh.triangles[t])
      if (v < 0 || v >= n)
        throw InputError(fmt::format("mesh triangle {} refers to point {} but the mesh has {} points", t, v, n));
  // Targets of the directed edges out of each point.
  std::vector<int> first(mesh.points.size() + 1, 0), target(3 * mesh.triangles.size());
  for (const auto& tri : mesh.triangles)
    for (int v : tri) ++first[static_cast<std::size_t>(v) + 1];
  for (std::size_t i = 1; i < first.size(); ++i) first[i] += first[i - 1];
  std::vector<int> fill(first.begin(), first.end() - 1);
  for (const auto& tri : mesh.triangles)
    for (int e = 0; e < 3; ++e)
      target[static_cast<std::size_t>(fill[static_cast<std::size_t>(tri[e])]++)] = tri[(e + 1) % 3];
  const auto has_edge = [&](int a, int b) {
    for (int k = first[static_cast<std::size_t>(a)]; k < first[static_cast<std::size_t>(a) + 1]; ++k)
      if (target[static_cast<std::size_t>(k)] == b) return true;
    return false;
  };
  std::vector<std::pair<int, int>> edges;
  edges.reserve(mesh.triangles.size() * 3 / 2 + 8);
  for (const auto& tri : mesh.triangles) {
    for (int e = 0; e < 3; ++e) {
      const int i = tri[e], j = tri[(e + 1) % 3];
      if (i < j || !has_edge(j, i)) edges.emplace_back(i, j);
    }
  }
  return edges;
}

SpacingConformance spacing_conformance(const Mesh& mesh, const SpacingBatch& q) {
  const std::vector<std::pair<int, int>> edges = unique_edges(mesh);
  std::vector<double> ratios(edges.size());
  // The midpoints and their q in batches of kBatch edges (q at a point does not depend on the batch
  // it is asked in): a million-node mesh's three million midpoints are never all held at once.
  constexpr std::size_t kBatch = std::size_t{1} << 16;
  std::vector<Vec2> mid;
  std::vector<double> qm;
  for (std::size_t first = 0; first < edges.size(); first += kBatch) {
    const std::size_t count = std::min(kBatch, edges.size() - first);
    mid.resize(count);
    for (std::size_t b = 0; b < count; ++b)
      mid[b] = 0.5 * (mesh.points[static_cast<std::size_t>(edges[first + b].first)] +
                      mesh.points[static_cast<std::size_t>(edges[first + b].second)]);
    q(mid, qm);
    for (std::size_t b = 0; b < count; ++b) {
      const std::size_t k = first + b;
      if (!(std::isfinite(qm[b]) && qm[b] > 0.0)) {
        throw InputError(
            fmt::format("spacing q({:.17g}, {:.17g}) = {} at the midpoint of edge {}-{} is not a "
                        "finite positive number",
                        mid[b].x, mid[b].y, qm[b], edges[k].first, edges[k].second));
      }
      const auto [i, j] = edges[k];
      ratios[k] = dist(mesh.points[static_cast<std::size_t>(i)], mesh.points[static_cast<std::size_t>(j)]) / qm[b];
    }
  }
  SpacingConformance c;
  c.edges = ratios.size();
  if (ratios.empty()) return c;
  double sum = 0.0;
  for (double r : ratios) sum += r;
  c.mean = sum / static_cast<double>(ratios.size());
  double sq = 0.0;
  for (double r : ratios) sq += (r - c.mean) * (r - c.mean);
  c.stddev = std::sqrt(sq / static_cast<double>(ratios.size()));
  // Only the 5th and 95th percentiles and the extremes are needed: selection, not a full sort.
  const auto at = [&ratios](double p) {
    const double pos = p * static_cast<double>(ratios.size() - 1);
    const auto lo = static_cast<std::size_t>(std::floor(pos));
    std::nth_element(ratios.begin(), ratios.begin() + static_cast<std::ptrdiff_t>(lo), ratios.end());
    const double a = ratios[lo];
    if (lo + 1 >= ratios.size()) return a;
    const double b = *std::min_element(ratios.begin() + static_cast<std::ptrdiff_t>(lo) + 1, ratios.end());
    return a + (pos - static_cast<double>(lo)) * (b - a);
  };
  c.p05 = at(0.05);
  c.p95 = at(0.95);
  c.min = *std::min_element(ratios.begin(), ratios.end());
  c.max = *std::max_element(ratios.begin(), ratios.end());
  return c;
}

SpacingConformance spacing_conformance(const Mesh& mesh, const SpacingCallback& q) {
  return spacing_conformance(mesh, [&q](const std::vector<Vec2>& p, std::vector<double>& out) {
    out.resize(p.size());
    for (std::size_t k = 0; k < p.size(); ++k) out[k] = q(p[k]);
  });
}

void list_constraints(const Mesh& mesh, QualitySummary& summary) {
  summary.constraints.clear();
  std::vector<std::size_t> edges(mesh.constraint_curves.size(), 0);
  for (const BoundaryEdge& e : mesh.boundary_edges)
    if (static_cast<std::size_t>(e.curve) < edges.size()) ++edges[static_cast<std::size_t>(e.curve)];
  for (std::size_t c = 0; c < mesh.constraint_curves.size() && c < mesh.curve_names.size(); ++c)
    if (mesh.constraint_curves[c]) summary.constraints.emplace_back(mesh.curve_names[c], edges[c]);
}

QualitySummary summarize_quality(const Mesh& mesh, const SpacingCallback& q, const QualityOptions& options) {
  QualitySummary s = summarize_quality_of(mesh, options);
  s.points = mesh.points.size();
  list_constraints(mesh, s);
  if (q) {
    s.has_spacing = true;
    s.spacing = spacing_conformance(mesh, q);
  }
  return s;
}

}  // namespace pdmesh
