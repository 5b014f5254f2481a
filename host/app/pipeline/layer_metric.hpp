// Boundary layers under a metric field (docs/boundary-layers.md, "Under a metric field"): the wall
// nodes the layers grow from and the size at which their thickness stops, both from the metric, and
// the core's metric graded down to the layers' last heights at their fronts.
#pragma once

#include <algorithm>
#include <memory>
#include <vector>

#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "spacing/metric_field.hpp"

namespace pdmesh {

// The geometry with each of `walls` reduced to its wall_stations under `metric` (`offset`: the
// layer's thickness; the other curves as they are): what the layers of a table under a metric field grow from.
Geometry metric_wall_geometry(const Geometry& geometry, const std::vector<int>& walls, const GeometryTree& domain,
                              const MetricField& metric, double offset, const GeometryOptions& options);

// Under a metric field, what the layers stop at (CoreSpacing): the metric's size at p along the
// direction from the nearest point of the wall segments to p, i.e. along the ray for a point up a ray
// (a layer stops where growth x its height reaches the metric's length along its ray).
class MetricSizeAlongRay {
 public:
  MetricSizeAlongRay(const Geometry& geometry, const std::vector<int>& walls, const MetricField& metric)
      : metric_(metric) {
    for (const Segment& s : geometry.segments)
      if (std::find(walls.begin(), walls.end(), s.curve) != walls.end()) segments_.push_back(s);
  }
  double operator()(Vec2 p) const;

 private:
  const MetricField& metric_;
  std::vector<Segment> segments_;
};

// A layer's ray top for FrontGradedMetric: the top node `p`, the unit direction `u` across the
// front there (towards the core), the size the core's first row has along it (`across`: growth x
// the last layer's height along the ray) and, at a fan's top, along the front (`along`: the longest
// front edge there; 0 elsewhere, where the case's metric along the front stays).
struct FrontMetricSource {
  Vec2 p;
  Vec2 u;
  double across = 0.0;
  double along = 0.0;
};

// The core's metric under a metric field: the case's metric (`base`), and near the layers' fronts
// its intersection with the slab of half-width s = across_i + gradation x |p - p_i| along u_i (the
// unit ball made no wider than s across the front, its sizes along the front kept where the front is
// along the base's axes), for the source i whose s is the smallest at p; at a fan's top also with
// along_i + gradation x |p - p_i| across u_i. The height of a unit triangle on a front edge is the
// unit ball's width across the edge, so the core's first row continues the layer's growth from its
// last layer and grows by the gradation (as the isotropic core's field is lowered at the fronts, step
// 3 of the run), and around a fan, whose rays turn faster than the case's sizes along the wall allow,
// it has the fan's spacing. Where the base's unit ball is no wider than s, the base exactly. Keeps a
// reference to `base`: it must outlive this. Thread-safe where `base` is.
class FrontGradedMetric final : public MetricField {
 public:
  FrontGradedMetric(const MetricField& base, std::vector<FrontMetricSource> sources, double gradation);
  Metric at(Vec2 p) const override;

 private:
  const MetricField& base_;
  std::vector<FrontMetricSource> sources_;  // sorted by x
  double gradation_;
};

}  // namespace pdmesh
