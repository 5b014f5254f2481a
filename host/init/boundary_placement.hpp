// Where the boundary nodes go (case key boundary.nodes): at the geometry points (the thesis' rule,
// "input"), or re-placed along each curve between its critical points at equal integral of ds/q
// ("spacing"), on the curve the node geometry describes. See docs/initialization.md.
#pragma once
#include <cstdint>
#include <vector>

#include "geometry/geometry.hpp"
#include "nodes/node_set.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

enum class BoundaryNodeRule { Input, Spacing };

// One boundary node position on a curve, in curve order. `vertex` is the index of the curve point it
// sits on, or -1 for a point between curve points; `arc` its arc-length position on the curve.
struct BoundaryStation {
  Vec2 p;
  int vertex = -1;
  double arc = 0.0;
};
// Per curve, its stations from its first point to its last; each list starts at vertex 0, ends at
// the last vertex and holds every critical vertex of the curve.
using CurveStations = std::vector<std::vector<BoundaryStation>>;

// The NodeSet of the boundary nodes at `stations`: every Geometry::critical entry becomes one Fixed
// node (in that order, shared by its curves), then each curve's other stations become Boundary nodes
// in curve order; curve_nodes lists each curve's nodes. q is spacing.at(x). (init/boundary_nodes.cpp)
NodeSet assemble_boundary_nodes(const Geometry& geometry, const SpacingField& spacing, const CurveStations& stations);

// Stations at the given vertices of each curve (vertices[c] ascending, the curve's ends and critical
// vertices among them), or at every vertex when `vertices` is null.
CurveStations vertex_stations(const Geometry& geometry, const std::vector<std::vector<int>>* vertices = nullptr);

struct PlacementOptions {
  // The validity rule: the curve between two consecutive boundary nodes a, b stays within
  // max_deviation x (q_a + q_b) / 2 of their chord. Where the equal-integral placement breaks it,
  // the target edge length there is shortened and the placement repeated.
  double max_deviation = 0.1;
  // Growth of the shortened target length away from where it was shortened, per unit arc length
  // (a 1-D gradation limit, so that edge lengths change gradually along the curve).
  double grading = 0.3;
  int max_rounds = 12;
  // Refuse (LimitError) when the curves would get more boundary nodes than this; 0 = no limit.
  std::uint64_t max_nodes = 0;
};

// Stations of boundary.nodes = "spacing": between consecutive critical vertices of each curve,
// n = max(1, round(N)) edges with N the integral of ds/q over that section of the polyline, the
// nodes at equal steps of that integral (then the validity rule). Throws LimitError on a
// non-positive or non-finite q and when max_nodes would be exceeded.
CurveStations spacing_stations(const Geometry& geometry, const SpacingField& spacing,
                               const PlacementOptions& options = {});

// The boundary nodes of a run: rule Input puts them at the geometry points (at `input_vertices` of
// each curve when given: the input points on a smooth curve's dense polyline; else every point),
// rule Spacing at spacing_stations().
NodeSet place_boundary_nodes(const Geometry& node_geometry, const SpacingField& spacing, BoundaryNodeRule rule,
                             const std::vector<std::vector<int>>* input_vertices, const PlacementOptions& options = {});

// Per segment of the geometry: the length of the shortest boundary edge (chord between consecutive
// stations) that covers part of it, i.e. the boundary-node spacing there, for the initialization
// tree (InitTreeOptions::segment_resolution).
std::vector<double> station_resolution(const Geometry& geometry, const CurveStations& stations);

// The largest distance from the chord between the curve's points at arc positions arc_a < arc_b to
// the curve between them (a polyline: the largest over its vertices strictly between).
double chord_deviation(const Curve& curve, double arc_a, double arc_b);
// The point of the polyline at arc position s (clamped to the curve).
Vec2 point_at_arc(const Curve& curve, double s);

}  // namespace pdmesh
