// Test helper: meshes built directly (no triangulation), for the writers' and pictures' tests.
#pragma once
#include "mesh/mesh.hpp"

namespace pdmesh::fixtures {

// An n x n grid of points, point (i, j) at position(i, j), its cells split along their rising
// diagonals; the outer points are boundary nodes and the outline one curve, "outline"; every point's
// q is the grid step (plus 1e-12 i, so that no two lines of a node file are equal).
template <class Position>
Mesh grid_mesh_of(int n, Position position) {
  Mesh m;
  const auto id = [n](int i, int j) { return j * n + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const bool side = i == 0 || j == 0 || i == n - 1 || j == n - 1;
      m.points.push_back(position(i, j, side));
      m.kind.push_back(side ? NodeKind::Boundary : NodeKind::Interior);
      m.spacing.push_back(1.0 / (n - 1.0) + 1e-12 * i);
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  m.curve_names = {"outline"};
  for (int i = 0; i + 1 < n; ++i) m.boundary_edges.push_back({id(i, 0), id(i + 1, 0), 0});
  for (int j = 0; j + 1 < n; ++j) m.boundary_edges.push_back({id(n - 1, j), id(n - 1, j + 1), 0});
  for (int i = n - 1; i > 0; --i) m.boundary_edges.push_back({id(i, n - 1), id(i - 1, n - 1), 0});
  for (int j = n - 1; j > 0; --j) m.boundary_edges.push_back({id(0, j), id(0, j - 1), 0});
  return m;
}

}  // namespace pdmesh::fixtures
