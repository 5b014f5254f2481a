// The top grid of the spacing mesh's point locator stays proportional to the mesh: a fuzzer found a
// 25-node background mesh with one node at x = 2.3e14 that got a row of 4 million empty cells
// (seconds to build). Kept as tests/fuzz/regressions/fuzz_mesh_reader_msh/spacing_mesh_with_one_far_node.msh.
#include <catch2/catch.hpp>

#include <vector>

#include "spacing/triangle_locator.hpp"

TEST_CASE("a long thin set of boxes gets at most 64 + 4 per box top-grid cells", "[locator][fuzz]") {
  std::vector<pdmesh::Box> boxes;
  for (int i = 0; i < 24; ++i) {
    const double x = i / 24.0;
    boxes.push_back(pdmesh::Box{{x, 0.0}, {x + 1.0 / 24.0, 1.0}});
  }
  boxes.push_back(pdmesh::Box{{0.9, 0.0}, {2.26e14, 1.0}});  // a triangle reaching the far node
  pdmesh::BoxTree tree;
  tree.build(boxes, true);
  CHECK_FALSE(tree.single_root);
  CHECK(static_cast<double>(tree.gx) * tree.gy <= 64.0 + 4.0 * static_cast<double>(boxes.size()));
  // Every box is still found where it is.
  CHECK(tree.leaf_of({0.5, 0.5}) >= 0);
  CHECK(tree.leaf_of({1.0e14, 0.5}) >= 0);
}

TEST_CASE("a square mesh's top grid is the one it always had", "[locator]") {
  std::vector<pdmesh::Box> boxes;
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 32; ++i) boxes.push_back(pdmesh::Box{{i / 32.0, j / 32.0}, {(i + 1) / 32.0, (j + 1) / 32.0}});
  pdmesh::BoxTree tree;
  tree.build(boxes, true);
  // 1024 boxes at 4 per cell: cells of side 1/16, 17 x 17 (the top edge is a cell of its own).
  CHECK(tree.cell == 1.0 / 16.0);
  CHECK(tree.gx == 17);
  CHECK(tree.gy == 17);
}
