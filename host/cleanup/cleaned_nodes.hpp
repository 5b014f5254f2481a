// The mesh and node set a cleanup hands back from its editable mesh (both cleanups share it): the
// live triangles and vertices renumbered, the curve chains, and per node its q and curve, taken from
// the input nodes for the nodes that were there and from the spacing field and the chains for new ones.
#pragma once
#include "cleanup/editable_mesh.hpp"
#include "mesh/mesh.hpp"
#include "nodes/node_set.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh::cleanup {

// `mesh` and `nodes` are the cleanup's input (what `m` was built from).
void cleaned_mesh_and_nodes(const EditableMesh& m, const Mesh& mesh, const NodeSet& nodes, const SpacingField& spacing,
                            Mesh& out_mesh, NodeSet& out_nodes);

}  // namespace pdmesh::cleanup
