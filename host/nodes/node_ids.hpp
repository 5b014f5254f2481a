// Persistent node ids of a moving-geometry run (NodeSet::id, docs/motion.md): numbering the new nodes
// and counting the ids two steps share.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "nodes/node_set.hpp"

namespace pdmesh {

// Gives every node without an id (no id column yet, or -1) the next id from `next`, in node order.
void number_new_nodes(NodeSet& nodes, std::int64_t& next);

// How many of `now`'s ids are in `before` (each id at most once in each list).
std::size_t ids_kept(const std::vector<std::int64_t>& before, const std::vector<std::int64_t>& now);

}  // namespace pdmesh
