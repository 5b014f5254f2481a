// The nodes of a mesh made elsewhere, kept as they are: its boundary nodes matched to the geometry's
// curves (pdmesh smooth of a mesh that already meets the target, docs/smoothing.md).
#pragma once
#include <optional>
#include <vector>

#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/boundary_placement.hpp"
#include "mesh/mesh.hpp"
#include "nodes/node_set.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

// A mesh's nodes on a geometry: per curve, its boundary nodes in curve order with the curve's end
// points and critical vertices among them (assemble_boundary_nodes' stations, each at the mesh node's
// own position), and the other nodes of its triangles.
struct KeptNodes {
  CurveStations stations;
  std::vector<Vec2> interior;
};

// The mesh's nodes as KeptNodes, or nothing when they cannot be kept as they are: the geometry has
// embedded constraints or points, a critical point of the geometry (a curve end or corner) has no mesh
// node within `tolerance` of it, or two boundary nodes of a curve share an arc position. Each boundary
// node (on an edge of one triangle) goes to the curve of its closest segment (`tree`); one within
// `tolerance` of a critical point is that point.
std::optional<KeptNodes> keep_mesh_nodes(const Mesh& mesh, const Geometry& geometry, const GeometryTree& tree,
                                         double tolerance);

// The NodeSet of kept nodes: the boundary nodes by assemble_boundary_nodes, then the interior nodes;
// q from `spacing`. `geometry` must be the one keep_mesh_nodes matched them to.
NodeSet kept_node_set(const KeptNodes& kept, const Geometry& geometry, const SpacingField& spacing);

}  // namespace pdmesh
