// Boundary layers under a metric field (docs/boundary-layers.md, "Under a metric field"): the wall
// nodes the layers grow from and the size at which their thickness stops, both from the metric.
#pragma once

#include <algorithm>
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

}  // namespace pdmesh
