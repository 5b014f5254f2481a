// The initial nodes of a metric run (docs/metric-fields.md, "Particles in the metric"): boundary
// stations at unit metric length along each curve, and interior nodes on a hexagonal lattice of unit
// metric spacing, aligned with the metric's eigenvectors, grown from the boundary nodes inward.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry/geometry_tree.hpp"
#include "nodes/node_set.hpp"
#include "spacing/metric_field.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

// The boundary stations' spacing of a metric run: at a point on the geometry, 1 / |t|_M with t the unit
// direction of the segment closest to it, i.e. the length of a unit metric step along the curve there.
// spacing_stations over this field places a curve's nodes at equal integral of |t|_M ds: unit metric
// length apart. Meant for points on the curves (elsewhere it answers for the closest segment).
class CurveMetricSpacing final : public SpacingField {
 public:
  CurveMetricSpacing(const GeometryTree& tree, const MetricField& metric) : tree_(tree), metric_(metric) {}
  double at(Vec2 p) const override;

 private:
  const GeometryTree& tree_;
  const MetricField& metric_;
};

struct MetricFillOptions {
  // A candidate is a unit metric step (this many metric units) from the node it grows from.
  double step = 1.0;
  // A candidate closer than this, in its own metric, to a node already placed is not placed.
  double min_distance = 0.75;
  // A candidate closer than this, in its own metric, to a boundary curve is not placed.
  double boundary_clearance = 0.6;
  // LimitError once the fill would place more interior nodes than this; 0: no limit.
  std::uint64_t max_nodes = 0;
  // Grow from the interior nodes already in the set (a warm start's kept points), the boundary nodes
  // seeding only where they do not reach: fills the gaps a warm start leaves where the metric asks for
  // more nodes than it kept. Grown from every boundary node at once, fronts meet in rows of defects.
  bool grow_from_interior = false;
};

// Appends interior nodes (NodeKind::Interior, q from `q`) to `nodes`, which holds the boundary nodes
// (with curve_nodes). The lattice grows breadth first from one seed, the middle node of the curve with
// the most nodes, so that it stays coherent (seeds grown from several boundary nodes at once meet in
// rows of defects): from each node in turn, six candidates at one metric step in the directions of a
// hexagonal lattice of the metric there, one of them along the eigenvector of its larger size (so that
// rows run along a layer, parallel to a wall aligned with it). Where the lattice cannot reach (a region
// cut off from the seed), the other boundary nodes seed in turn. The step is measured in the metric at its midpoint, so
// that it stays a unit step where the metric grades. A candidate is placed when it is inside the domain and clears the
// nodes and the curves (MetricFillOptions). Deterministic. Returns the number of nodes added; the node density follows
// sqrt(det M): about 2 / sqrt(3) nodes per unit metric area.
std::size_t metric_fill(const GeometryTree& tree, const MetricField& metric, const SpacingField& q, NodeSet& nodes,
                        const MetricFillOptions& options = {});

// The warm start (init.file, docs/metric-fields.md "Adaptation to a solution"): appends the given points
// as interior nodes (q from `q`) to `nodes`, which holds the boundary nodes, in their order, keeping a
// point when it is inside the domain, clears the curves (options.boundary_clearance) and is not closer
// than options.min_distance to a node already kept, both measured in the point's metric: `metric`'s for a
// metric run, the isotropic metric I / q(p)^2 when `metric` is null. The relaxation's population control
// then fixes the density. Deterministic. Returns the number of nodes added; LimitError above
// options.max_nodes.
std::size_t warm_fill(const GeometryTree& tree, const MetricField* metric, const SpacingField& q, NodeSet& nodes,
                      const std::vector<Vec2>& points, const MetricFillOptions& options = {});

}  // namespace pdmesh
