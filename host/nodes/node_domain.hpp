// The domain that a node set's boundary nodes enclose. Boundary nodes slide along their curves, so
// the polygon through them cuts the curves' corners: its area, not the geometry's, is what a
// boundary-conforming mesh of the nodes must cover.
#pragma once
#include "geometry/geometry.hpp"
#include "nodes/node_set.hpp"

namespace pdmesh {

// Even-odd area of the loops formed by each geometry loop's curves' node chains (curve_nodes),
// with each loop counted + or - by its nesting depth in the geometry.
double node_domain_area(const NodeSet& nodes, const Geometry& geometry);

}  // namespace pdmesh
