// Arc positions of a node set's boundary nodes along their curves: where boundary handling
// (sim/boundary_handling) starts from, and what the cleanup (cleanup/) slides boundary nodes by.
#pragma once
#include <vector>

#include "core/vec2.hpp"
#include "geometry/geometry.hpp"
#include "nodes/node_set.hpp"

namespace pdmesh {

// The arc position of every nodes.curve_nodes entry, parallel to it: the first and last entries at
// their curve's ends, each inner one the closest point of its curve at or beyond the previous entry's
// position (geometry/curve_projection). When `tangents` is given (sized to the nodes), it receives
// the unit tangent there of every Boundary node. Throws SimulationError when the lists do not match
// the geometry's curves or a curve has fewer than its two end points.
std::vector<std::vector<double>> boundary_arcs(const Geometry& geometry, const NodeSet& nodes,
                                               std::vector<Vec2>* tangents = nullptr);

}  // namespace pdmesh
