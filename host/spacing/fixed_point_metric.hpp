// The metric at the geometry's fixed points (curve ends, corners, embedded points) taken from the
// field around them. A fixed node samples the field at one place for the whole run; where that place
// is singular in the field, every pair, gap and triangle at the node is measured by a value the field
// has nowhere else. The case: a Hessian metric's inflection line (u'' = 0, the metric isotropic at
// hmax) through an airfoil's leading edge, with sizes across the line far smaller just beside it.
// The node's metric is then graded from the field around it, as mesh adapters grade a metric along
// the edges at a vertex (Alauzet's gradation, mmg's -hgrad): the field at the point intersected with
// the span that the field at each point around it lets the node have.
#pragma once
#include <memory>
#include <utility>
#include <vector>

#include "core/vec2.hpp"
#include "geometry/geometry_tree.hpp"
#include "spacing/metric.hpp"
#include "spacing/metric_field.hpp"

namespace pdmesh {

// The gradation of the grading at the fixed points when the case sets no spacing.metric_gradation:
// mmg's default -hgrad.
constexpr double kFixedPointGradation = 1.3;

// The metric at p graded from the field around it, where the field is not continuous at p: where the
// log-Euclidean mean of the field on the innermost ring below (about 1e-7 of the largest size from p)
// asks for sizes smaller than 1/beta of field.at(p)'s in some direction, field.at(p) intersected, in
// turn, with span_metric(field.at(q), p - q, beta, 0) for the points q on 16 rays from p at distances
// R 2^(-k/2), k = 0 .. 47 (R the largest size of field.at(p)), that lie in the domain and are seen
// from p (tree.inside, not crosses_boundary), each taken where it asks for sizes at least 1 % smaller
// than the metric so far. Elsewhere field.at(p) bit for bit, however steep the field around p: the
// grading mends a value the field has nowhere around p, not the field's own gradation.
Metric graded_from_around(const MetricField& field, const GeometryTree& tree, Vec2 p, double beta);

// A metric field whose value at a few exact points is given; elsewhere the field's own.
class PointMetricField final : public MetricField {
 public:
  PointMetricField(std::unique_ptr<MetricField> field, std::vector<std::pair<Vec2, Metric>> points);
  Metric at(Vec2 p) const override;
  // The field's at_many (its threads and guesses), then the given points' metrics.
  void at_many(const std::vector<Vec2>& p, std::vector<Metric>& out, std::vector<int>& guesses) const override;
  const std::vector<std::pair<Vec2, Metric>>& points() const { return points_; }

 private:
  const Metric* given(Vec2 p) const;  // the metric given at exactly p, or null

  std::unique_ptr<MetricField> field_;
  std::vector<std::pair<Vec2, Metric>> points_;  // sorted by x, then y
};

// `field` with the metric at each of the tree's geometry's critical points (those of curves that are
// not fixed_points curves: layer fronts and periodic curves are placed by their own rules) and
// embedded points graded from around it (graded_from_around); `field` itself when no such point's
// metric changes.
std::unique_ptr<MetricField> with_fixed_point_metrics(std::unique_ptr<MetricField> field, const GeometryTree& tree,
                                                      double beta);

}  // namespace pdmesh
