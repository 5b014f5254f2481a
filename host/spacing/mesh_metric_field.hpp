// A metric field given at the points of a triangle mesh (metric data on a background mesh, or the
// Hessian metric of data on one): log-Euclidean interpolation of the corner metrics inside each
// triangle, and outside the mesh the interpolation along the nearest boundary edge, as MeshSpacing
// does for a scalar spacing (spacing/mesh_spacing.hpp).
#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/vec2.hpp"
#include "spacing/metric.hpp"
#include "spacing/metric_field.hpp"
#include "spacing/triangle_locator.hpp"

namespace pdmesh {

class MeshMetricField final : public MetricField {
 public:
  // Throws InputError naming `what` and the value: no triangles; a triangle index outside the
  // points; a triangle of zero or negative area (the triangles must be counter-clockwise); a metric
  // that is not finite and SPD (check_metric, naming the point); metrics.size() != points.size();
  // two triangles on the same side of a shared edge (folded or repeated), or an edge of three.
  MeshMetricField(std::vector<Vec2> points, std::vector<std::array<int, 3>> triangles, std::vector<Metric> metrics,
                  std::string what);
  MeshMetricField(const MeshMetricField&) = delete;
  MeshMetricField& operator=(const MeshMetricField&) = delete;

  // Inside a triangle exp(sum w_i log M_i) with the barycentric weights w_i; the corner's own metric
  // at a corner. Outside: the interpolation of the nearest boundary edge's two metrics at the
  // nearest point. Thread-safe.
  Metric at(Vec2 p) const override;
  // On every core; a guess is the triangle (locator position) that held the point last time, tried
  // first.
  void at_many(const std::vector<Vec2>& p, std::vector<Metric>& out, std::vector<int>& guesses) const override;

 private:
  std::vector<Vec2> points_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<Metric> metrics_;
  std::vector<Metric> logs_;  // log_metric of each point's metric
  std::string what_;
  Metric interpolated(const Located& l) const;
  Metric outside(Vec2 p) const;

  std::unique_ptr<TriangleLocator> locator_;  // refers to points_ and triangles_
};

}  // namespace pdmesh
