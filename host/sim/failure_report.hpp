// Messages for a simulation that fails: the node, its last good position and its neighbourhood, so
// that a non-finite force or move can be traced to the nodes that caused it (both backends).
#pragma once
#include <cstddef>
#include <string>

#include "nodes/node_set.hpp"

namespace pdmesh {

// "node 12 (interior) at (0.5, 0.25), spacing 0.01; within 0.015: node 7 at (0.51, 0.25) distance
// 0.01, ... (3 more)" or "...; no other node within 0.015". Lists at most max_listed nodes, the
// closest first, found by brute force (it runs once, on failure). Coordinates to 17 digits.
std::string describe_neighbourhood(const NodeSet& nodes, std::size_t node, double radius, std::size_t max_listed = 6);

}  // namespace pdmesh
