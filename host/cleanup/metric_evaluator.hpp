// The metric measures the cleanup in a metric decides with (docs/metric-fields.md, "Cleanup in the
// metric"): the metric at each vertex of an editable mesh, taken from the MetricField at the
// vertex's position (so a moved or new vertex gets the field's metric there, not one interpolated
// from its neighbours), the metric length of an edge (spacing/metric.hpp's edge_length) and the
// mean-ratio quality Q of a triangle as mesh/metric_quality measures it (the corner metric of
// largest det; 1 for a triangle equilateral in the metric, <= 0 for an inverted one). As a
// TriangleScore it makes EditableMesh::quality() and the journal's before/after minima Q.
#pragma once
#include <vector>

#include "cleanup/editable_mesh.hpp"
#include "spacing/metric.hpp"
#include "spacing/metric_field.hpp"

namespace pdmesh::cleanup {

// Q of (a, b, c) with the metric m (the caller picks the corner metric).
double metric_mean_ratio(Vec2 a, Vec2 b, Vec2 c, const Metric& m);

class MetricEvaluator final : public TriangleScore {
 public:
  // `field` must outlive the evaluator; it is called from one thread only.
  MetricEvaluator(const EditableMesh& mesh, const MetricField& field);

  // The metric at vertex a where it is now (cached per vertex slot and position).
  const Metric& at(int a) const;
  // The field's metric at any point.
  Metric at(Vec2 p) const { return field_.at(p); }
  const MetricField& field() const { return field_; }
  // The metric length of edge a-b.
  double length(int a, int b) const;
  double length(Vec2 pa, const Metric& ma, Vec2 pb, const Metric& mb) const;
  // Q of triangle (x, y, z) with metrics mx, my, mz at its corners.
  static double quality(Vec2 x, Vec2 y, Vec2 z, const Metric& mx, const Metric& my, const Metric& mz);
  // The point of edge a-b at half its metric length, with the length element varying geometrically
  // along the edge as edge_length assumes.
  Vec2 midpoint(int a, int b) const;
  // The fraction of the way from a to b at which the edge is split in half by metric length.
  double half_fraction(int a, int b) const;

  double score(const EditableMesh& mesh, int t) const override;

 private:
  const EditableMesh& mesh_;
  const MetricField& field_;
  mutable std::vector<Metric> metric_;
  mutable std::vector<Vec2> where_;
  mutable std::vector<unsigned char> known_;
};

}  // namespace pdmesh::cleanup
