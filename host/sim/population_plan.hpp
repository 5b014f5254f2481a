// Finding what one population-control event changes (sim/population.hpp): the Delaunay triangulation
// of every node (no constraints: the tests below are point tests against the exact geometry), then
// boundary gaps, clusters, low-valence nodes and vacancies, each node in at most one operation.
#pragma once
#include <cstddef>
#include <optional>
#include <vector>

#include "geometry/geometry_tree.hpp"
#include "nodes/node_set.hpp"
#include "sim/population.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

class MetricField;

struct PopulationPlan {
  struct BoundaryInsert {
    int curve = 0;
    std::size_t gap = 0;  // between curve_nodes[curve][gap - 1] and [gap]
    double arc = 0.0;     // the gap's middle
  };
  std::vector<Vec2> interior_inserts;  // vacancy points, best first
  std::vector<BoundaryInsert> boundary_inserts;
  std::vector<std::pair<int, Vec2>> moves;  // merged pairs: the kept node and the pair's midpoint
  std::vector<char> remove;                 // per node: removed by this event
  PopulationCounts counts;                  // what the plan does (once applied)
};

// Plans one event for `nodes`, whose boundary handler holds the arc positions `arcs` (parallel to
// curve_nodes). Throws InputError / GeometryError when the nodes cannot be triangulated (coincident
// or all collinear nodes); the caller then skips the event. With `kept`, the Delaunay triangulation
// of the nodes the plan is made on goes there (as the Triangulation constructor made it).
PopulationPlan plan_population_event(const NodeSet& nodes, const std::vector<std::vector<double>>& arcs,
                                     const GeometryTree& tree, const SpacingField& spacing,
                                     const PopulationThresholds& thresholds,
                                     std::optional<Triangulation>* kept = nullptr);

// The same plan with every length measured in `metric` (sigma = 1 in metric units) on the nodes'
// Delaunay graph in the metric (mesh/metric_delaunay): boundary gaps by the metric length of their
// chord, clusters by the metric length of graph edges, the same valence rule, and vacancies where a
// triangle's circumradius in the mean metric of its corners exceeds thresholds.insert (the node at
// that circumcentre, else at the midpoint of its longest edge in the metric), kept insert from every
// node and kInitBoundaryClearance from the boundary in the metric there
// (sim/metric_population_plan.cpp). Throws as plan_population_event does.
PopulationPlan plan_metric_population_event(const NodeSet& nodes, const std::vector<std::vector<double>>& arcs,
                                            const GeometryTree& tree, const MetricField& metric,
                                            const PopulationThresholds& thresholds);

// The circumcentre and circumradius of triangle abc (radius 0 and centre a when degenerate).
void circumcircle(Vec2 a, Vec2 b, Vec2 c, Vec2& centre, double& radius);

}  // namespace pdmesh
