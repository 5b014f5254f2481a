// The numbering of the node set during a run (docs/simulation.md, "Node order"). The step's force
// loop gathers the positions and q of each node's list entries; with the nodes numbered along a
// Hilbert curve those entries lie near the node's own index, so the gathers hit lines that nearby
// nodes already brought into the cache. Both simulation drivers renumber at the same points (the
// start of a fresh run and after each population event that changed the node set), so the host
// reference and the device run see the same order.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "nodes/node_set.hpp"

namespace pdmesh {

enum class NodeOrder : std::uint8_t {
  Input,    // the order the initial distribution and population events leave
  Hilbert,  // renumbered along a Hilbert curve through the positions
  Auto,     // Hilbert for a node set of at least kNodeOrderMinNodes nodes, else Input
};

const char* to_string(NodeOrder order);

// Auto's threshold: the step's gathers of a smaller run stay in the caches in any order (its positions
// and q take 24 B per node: 1.5 MB here), and a small run keeps its input-order result.
inline constexpr std::size_t kNodeOrderMinNodes = 65536;

// Whether `order` renumbers a node set of n nodes (at the start of a run or after an event).
inline bool renumbers(NodeOrder order, std::size_t n) {
  return order == NodeOrder::Hilbert || (order == NodeOrder::Auto && n >= kNodeOrderMinNodes);
}

// Renumbers the node set: new node k is old node old_of_new[k] (a permutation of 0..n-1). Moves
// x, q, kind, curve and id, and renames the entries of curve_nodes (their order along each curve stays).
void permute_nodes(NodeSet& nodes, const std::vector<int>& old_of_new);

// The permutation that numbers the nodes in Hilbert order of their positions (geometry/hilbert.hpp).
std::vector<int> spatial_order(const NodeSet& nodes);

}  // namespace pdmesh
