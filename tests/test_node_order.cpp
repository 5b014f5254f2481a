// The node numbering of a run (sim/node_order.hpp): the renumbering of a node set, and what it does
// to the locality of its neighbour rows.
#include <catch2/catch.hpp>

#include <vector>

#include "core/errors.hpp"
#include "sim/node_order.hpp"
#include "sim/row_locality.hpp"

using namespace pdmesh;

namespace {

// A row of nodes 0..n-1 along x, q = 1, with a two-node curve list at the ends.
NodeSet row(int n) {
  NodeSet nodes;
  for (int i = 0; i < n; ++i)
    nodes.add({static_cast<double>(i), 0.0}, 1.0, i == 0 || i == n - 1 ? NodeKind::Fixed : NodeKind::Interior, -1);
  nodes.curve[0] = nodes.curve[static_cast<std::size_t>(n - 1)] = 0;
  nodes.curve_nodes = {{0, n - 1}};
  return nodes;
}

}  // namespace

TEST_CASE("node order: permute_nodes moves every column and renames the curve lists", "[node_order]") {
  NodeSet nodes = row(5);
  nodes.id = {10, 11, 12, 13, 14};
  nodes.q[3] = 2.0;
  const std::vector<int> old_of_new{4, 3, 2, 1, 0};
  permute_nodes(nodes, old_of_new);
  CHECK(nodes.x[0].x == 4.0);
  CHECK(nodes.x[4].x == 0.0);
  CHECK(nodes.q[1] == 2.0);
  CHECK(nodes.id == std::vector<std::int64_t>{14, 13, 12, 11, 10});
  CHECK(nodes.kind[0] == NodeKind::Fixed);
  CHECK(nodes.kind[2] == NodeKind::Interior);
  // The curve list keeps its order along the curve: old node 0 (now 4) first.
  CHECK(nodes.curve_nodes[0] == std::vector<int>{4, 0});
}

TEST_CASE("node order: a renumbering that is not a permutation is refused", "[node_order]") {
  NodeSet nodes = row(3);
  CHECK_THROWS_AS(permute_nodes(nodes, {0, 1}), SimulationError);
  CHECK_THROWS_AS(permute_nodes(nodes, {0, 1, 1}), SimulationError);
  CHECK_THROWS_AS(permute_nodes(nodes, {0, 1, 3}), SimulationError);
}

TEST_CASE("node order: the Hilbert order makes a shuffled grid's rows local", "[node_order]") {
  // A 64 x 64 grid numbered by a stride coprime to its size (neighbours far apart in index).
  const int side = 64, n = side * side;
  NodeSet nodes;
  for (int k = 0; k < n; ++k) {
    const int cell = static_cast<int>((static_cast<long long>(k) * 1237) % n);
    nodes.add({static_cast<double>(cell % side), static_cast<double>(cell / side)}, 1.0, NodeKind::Interior, -1);
  }
  const RowLocality shuffled = row_locality(nodes, 1.5);
  permute_nodes(nodes, spatial_order(nodes));
  const RowLocality ordered = row_locality(nodes, 1.5);
  // The same pairs (8 neighbours within 1.5 of an inner grid node) under either numbering.
  CHECK(ordered.entries == shuffled.entries);
  CHECK(ordered.entries > 7u * static_cast<unsigned>(n));
  CHECK(shuffled.within_64 < 0.1);
  CHECK(ordered.within_64 > 0.5);
  CHECK(ordered.mean_distance < 0.1 * shuffled.mean_distance);
}

TEST_CASE("node order: auto renumbers from kNodeOrderMinNodes nodes, hilbert always, input never", "[node_order]") {
  CHECK_FALSE(renumbers(NodeOrder::Auto, kNodeOrderMinNodes - 1));
  CHECK(renumbers(NodeOrder::Auto, kNodeOrderMinNodes));
  CHECK(renumbers(NodeOrder::Hilbert, 3));
  CHECK_FALSE(renumbers(NodeOrder::Input, 10 * kNodeOrderMinNodes));
}
