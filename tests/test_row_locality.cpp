// The locality measure of a node set's neighbour rows (sim/row_locality.hpp).
#include <catch2/catch.hpp>

#include "sim/row_locality.hpp"

using namespace pdmesh;

namespace {

// A side x side grid of interior nodes, q = 1, node k at cell (k * stride) mod n.
NodeSet grid(int side, int stride) {
  const int n = side * side;
  NodeSet nodes;
  for (int k = 0; k < n; ++k) {
    const int cell = static_cast<int>((static_cast<long long>(k) * stride) % n);
    nodes.add({static_cast<double>(cell % side), static_cast<double>(cell / side)}, 1.0, NodeKind::Interior, -1);
  }
  return nodes;
}

}  // namespace

TEST_CASE("row locality: a row-major grid's rows are near, a shuffled grid's far", "[row_locality]") {
  const int side = 64, n = side * side;
  const RowLocality ordered = row_locality(grid(side, 1), 1.5);
  const RowLocality shuffled = row_locality(grid(side, 1237), 1.5);
  // The same pairs under either numbering: 8 neighbours within 1.5 of an inner node, fewer at the edges.
  CHECK(ordered.entries == shuffled.entries);
  CHECK(ordered.entries == 8u * (side - 2) * (side - 2) + 4u * 5u * (side - 2) + 4u * 3u);
  // Row-major: |i - j| is 1, side - 1, side or side + 1 (64 and 65 are beyond 64 only for the diagonal +1).
  CHECK(ordered.within_1024 == 1.0);
  CHECK(ordered.mean_distance < side + 1.0);
  CHECK(shuffled.within_64 < 0.1);
  CHECK(shuffled.mean_distance > 0.2 * n);
}
