// Log-Euclidean interpolation of metrics on a triangle mesh (mesh_metric_field.hpp).
#include "spacing/mesh_metric_field.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "core/predicates.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

MeshMetricField::MeshMetricField(std::vector<Vec2> points, std::vector<std::array<int, 3>> triangles,
                                 std::vector<Metric> metrics, std::string what)
    : points_(std::move(points)),
      triangles_(std::move(triangles)),
      metrics_(std::move(metrics)),
      what_(std::move(what)) {
  if (triangles_.empty()) throw InputError(fmt::format("{}: a metric mesh needs at least one triangle", what_));
  if (metrics_.size() != points_.size())
    throw InputError(fmt::format("{}: {} metrics for {} points", what_, metrics_.size(), points_.size()));
  for (std::size_t i = 0; i < points_.size(); ++i)
    check_metric(metrics_[i], fmt::format("{}: point {} ({}, {})", what_, i, points_[i].x, points_[i].y));
  const int n = static_cast<int>(points_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const auto& v = triangles_[t];
    for (int k = 0; k < 3; ++k)
      if (v[k] < 0 || v[k] >= n)
        throw InputError(
            fmt::format("{}: triangle {} uses point {}, which does not exist ({} points)", what_, t, v[k], n));
    if (!(orient2d(points_[v[0]], points_[v[1]], points_[v[2]]) > 0.0))
      throw InputError(fmt::format("{}: triangle {} ({}, {}, {}) has no positive area (counter-clockwise expected)",
                                   what_, t, v[0], v[1], v[2]));
  }
  logs_.reserve(metrics_.size());
  for (const Metric& m : metrics_) logs_.push_back(log_metric(m));
  locator_ = std::make_unique<TriangleLocator>(points_, triangles_);
  // Triangles over one another: at() would pick either, and the same triangle given twice leaves
  // no boundary edge for the points outside.
  const EdgeConflict& c = locator_->edge_conflict();
  if (c.first >= 0) {
    auto tri = [&](int t) {
      const auto& v = triangles_[static_cast<std::size_t>(t)];
      return fmt::format("{} ({}, {}, {})", t, v[0], v[1], v[2]);
    };
    const Vec2 pa = points_[static_cast<std::size_t>(c.a)], pb = points_[static_cast<std::size_t>(c.b)];
    const std::string edge = fmt::format("point {} ({}, {}) - point {} ({}, {})", c.a, pa.x, pa.y, c.b, pb.x, pb.y);
    throw InputError(c.same_side
                         ? fmt::format("{}: the triangles {} and {} lie on the same side of their shared edge {} "
                                       "(a folded or repeated triangle); a metric mesh must not overlap itself",
                                       what_, tri(c.first), tri(c.second), edge)
                         : fmt::format("{}: the edge {} belongs to more than two triangles, among them {} and {}",
                                       what_, edge, tri(c.first), tri(c.second)));
  }
}

Metric MeshMetricField::interpolated(const Located& l) const {
  const auto& v = triangles_[static_cast<std::size_t>(l.triangle)];
  const double sum = l.w[0] + l.w[1] + l.w[2];
  // At a corner (one weight holds everything) the corner's metric itself, without exp(log()).
  for (int k = 0; k < 3; ++k)
    if (l.w[k] == sum) return metrics_[static_cast<std::size_t>(v[k])];
  Metric s{0.0, 0.0, 0.0};
  for (int k = 0; k < 3; ++k) s = s + (l.w[k] / sum) * logs_[static_cast<std::size_t>(v[k])];
  return exp_metric(s);
}

Metric MeshMetricField::outside(Vec2 p) const {
  const BoundaryHit hit = locator_->nearest_boundary(p);
  const auto& e = locator_->boundary_edges()[static_cast<std::size_t>(hit.edge)];
  const double t = std::clamp(hit.t, 0.0, 1.0);
  if (t == 0.0) return metrics_[static_cast<std::size_t>(e[0])];
  if (t == 1.0) return metrics_[static_cast<std::size_t>(e[1])];
  return exp_metric((1.0 - t) * logs_[static_cast<std::size_t>(e[0])] + t * logs_[static_cast<std::size_t>(e[1])]);
}

Metric MeshMetricField::at(Vec2 p) const {
  const Located l = locator_->locate(p);
  return l.triangle >= 0 ? interpolated(l) : outside(p);
}

// The fewest lookups worth a thread in at_many: an interpolated metric (logarithms in, an exponential
// out) costs several spacing lookups, so a metric run of a few thousand nodes uses every core.
constexpr std::size_t kMetricPointsPerThread = 1024;

void MeshMetricField::at_many(const std::vector<Vec2>& p, std::vector<Metric>& out, std::vector<int>& guesses) const {
  out.resize(p.size());
  guesses.resize(p.size(), -1);
  parallel_for(
      p.size(),
      [&](std::size_t i) {
        // Strictly inside the guessed triangle: no other triangle holds the point, so at() would pick it
        // too, with the same weights.
        Located l;
        const int guess = guesses[i];
        if (guess >= 0 && static_cast<std::size_t>(guess) < triangles_.size() &&
            locator_->strictly_inside(guess, p[i], l)) {
          out[i] = interpolated(l);
          return;
        }
        l = locator_->locate(p[i]);
        guesses[i] = l.position;
        out[i] = l.triangle >= 0 ? interpolated(l) : outside(p[i]);
      },
      kMetricPointsPerThread);
}

}  // namespace pdmesh
