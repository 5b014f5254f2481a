// The complexity C = ∫ sqrt(det M) of a metric field (Loseille-Alauzet): the continuous counterpart of
// the vertex count (a unit mesh has about 1.15 C vertices and 4C/√3 triangles).
#pragma once
#include <array>
#include <vector>

#include "core/vec2.hpp"
#include "spacing/metric.hpp"
#include "spacing/metric_field.hpp"

namespace pdmesh {

// ∫ sqrt(det M) over `box` by tensor Gauss-Legendre: panels x panels cells of order x order points
// (metric.py's complexity_square on the unit square).
double complexity_on_box(const MetricField& field, const Box& box, int panels = 400, int order = 4);

// ∫ sqrt(det M) over a triangle mesh with metrics at its points, by the P1 rule (the mean of the
// corners' sqrt(det) times the area).
double complexity_on_mesh(const std::vector<Vec2>& points, const std::vector<std::array<int, 3>>& triangles,
                          const std::vector<Metric>& metrics);

// The triangle count of the ideal unit mesh: 4C/√3 (a triangle of unit metric edges has metric area √3/4).
inline double ideal_triangles(double complexity) { return 4.0 * complexity / std::sqrt(3.0); }

}  // namespace pdmesh
