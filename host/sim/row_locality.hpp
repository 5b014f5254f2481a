// How local the step's gathers are under the node set's numbering. The step's force loop gathers the
// positions and q of each node's list entries; the nearer those entries are to the node's own index,
// the more of them lie in lines that nearby nodes already brought into the cache.
#pragma once
#include <cstdint>
#include <optional>

#include "nodes/node_set.hpp"

namespace pdmesh {

// How far apart in index the nodes of each interior node's neighbour rows are: every pair (i, j),
// i interior, j != i, with |x_j - x_i| <= radius_factor * q_i (the rows of a Verlet list of that
// radius). For the trace below; not part of any output.
struct RowLocality {
  std::uint64_t entries = 0;
  double mean_distance = 0.0;  // mean |i - j|
  double within_64 = 0.0;      // share of entries with |i - j| <= 64
  double within_1024 = 0.0;    // share with |i - j| <= 1024
};
RowLocality row_locality(const NodeSet& nodes, double radius_factor);

// PDMESH_ROW_LOCALITY's radius factor: nothing when unset, 2.25 (the best preset's cut-off 1.5 times
// 1 + skin 0.5, the skin of a run with momentum) when set but empty; a value that is not a positive finite number
// throws InputError naming the variable and the value.
std::optional<double> row_locality_factor();

// With PDMESH_ROW_LOCALITY set: one line on stderr with row_locality at row_locality_factor(),
// labelled `when`. Costs a neighbour search over every node, so it is a diagnosis only.
void trace_row_locality(const char* when, const NodeSet& nodes);

}  // namespace pdmesh
