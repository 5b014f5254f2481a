// A small mixed mesh the writers' tests share: a unit square split into a quad (the left half, the
// layer) and two triangles (the right half); curves bottom (two edges), right, top (two edges), left.
#pragma once
#include "io/mixed_mesh.hpp"

namespace pdmesh_test {

inline pdmesh::MixedMesh mixed_square() {
  pdmesh::MixedMesh m;
  m.points = {{0, 0}, {0.5, 0}, {1, 0}, {1, 1}, {0.5, 1}, {0, 1}};
  m.cells = {{0, 1, 4, 5}, {1, 2, 3, -1}, {1, 3, 4, -1}};
  m.layer = {1, 0, 0};
  m.curve_names = {"bottom", "right", "top", "left"};
  m.boundary_edges = {{0, 1, 0}, {1, 2, 0}, {2, 3, 1}, {3, 4, 2}, {4, 5, 2}, {5, 0, 3}};
  return m;
}

}  // namespace pdmesh_test
