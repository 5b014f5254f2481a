// Node set -> boundary-conforming constrained Delaunay mesh of the domain.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "mesh/delaunay.hpp"
#include "mesh/mesh.hpp"
#include "mesh/metric_delaunay.hpp"
#include "spacing/metric_field.hpp"
#include "nodes/node_set.hpp"

namespace pdmesh {

// Triangulates the nodes; consecutive nodes of each NodeSet::curve_nodes list are constrained
// edges, which become Mesh::boundary_edges (with their curve index). Triangles outside the
// domain and in holes are removed (even-odd rule). Point indices and kinds are the node set's.
// With no curves at all, the Delaunay triangulation of the points is returned without boundary.
// Throws InputError (duplicate points, curve name count mismatch) and GeometryError (collinear
// points, a node inside a boundary edge, crossing boundary edges, an edge used by two curves).
Mesh triangulate(const NodeSet& nodes, const std::vector<std::string>& curve_names);

// triangulate in two halves, for a caller that may not need the Mesh (the stopping rule's
// measurement): its triangles, with the same errors (the triangulation's working arrays are freed on
// return), then, given them, the rest of its Mesh. mesh_of_triangles(nodes, names,
// triangulate_triangles(nodes, names)) is triangulate(nodes, names).
std::vector<std::array<int, 3>> triangulate_triangles(const NodeSet& nodes,
                                                      const std::vector<std::string>& curve_names);
// triangulate_triangles's triangles as a set (not in its order, nor each in its rotation), made from
// `tri`: the Delaunay triangulation of the nodes' first tri.input_count positions as the Triangulation
// constructor made it (a population event's, before the event appended nodes). The nodes after them
// are inserted into it (Triangulation::add_points), then the boundary edges recovered and the outside
// removed as triangulate_triangles does. Empty when that cannot be shown to give that set: the first
// positions are not the nodes' (bit for bit), the insertion cannot keep the super-triangle, another
// Delaunay triangulation, or after the recovery another constrained Delaunay triangulation, has other
// triangles (Triangulation::unique_inner_triangles), or an error arises (the caller's
// triangulate_triangles then meets it, or not, as it would anyway). `tri` is taken over either way.
std::optional<std::vector<std::array<int, 3>>> triangulate_triangles_from(Triangulation tri, const NodeSet& nodes,
                                                                          const std::vector<std::string>& curve_names);
Mesh mesh_of_triangles(const NodeSet& nodes, const std::vector<std::string>& curve_names,
                       std::vector<std::array<int, 3>> triangles);

// The same, then flipped to the constrained Delaunay triangulation in the metric field given by
// metrics[i] at node i (make_metric_delaunay; its counts in *stats when given). The boundary edges,
// the removal of the outside and the errors are triangulate's; a metric that is not SPD is an
// InputError naming the node.
Mesh triangulate_in_metric(const NodeSet& nodes, const std::vector<std::string>& curve_names,
                           const std::vector<Metric>& metrics, const MetricDelaunayOptions& options = {},
                           MetricDelaunayStats* stats = nullptr);
// The same with the metrics field.at(node) (one thread: an expression field is not thread-safe);
// the field's InputError names its source and the point.
Mesh triangulate_in_metric(const NodeSet& nodes, const std::vector<std::string>& curve_names, const MetricField& field,
                           const MetricDelaunayOptions& options = {}, MetricDelaunayStats* stats = nullptr);

// Whether `mesh` is what triangulate makes of `nodes` (whatever the curve names): it was made from the
// same positions, kinds and curve chains (triangulate is deterministic).
bool triangulates(const Mesh& mesh, const NodeSet& nodes);

}  // namespace pdmesh
