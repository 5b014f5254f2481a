// The 60-degree rhombus of a hexagonal lattice as a geometry: the domain of the population tests and of
// tools/bench/bench_population (which includes this header from tests/).
#pragma once
#include <utility>
#include <vector>

#include "geometry/geometry.hpp"

namespace pdmesh_test {

// The rhombus with corners lattice(0, 0), (m, 0), (m, m), (0, m), for `lattice(i, j)` the lattice's
// node (i, j): four straight curves with a point at every `step`-th lattice node along each side and at
// both corners, so that with step 1 every boundary lattice node is a curve point.
template <class Lattice>
pdmesh::Geometry lattice_rhombus(int m, const Lattice& lattice, int step = 1) {
  using pdmesh::Vec2;
  std::vector<pdmesh::RawCurve> raw;
  const auto side = [&](const char* name, Vec2 a, Vec2 b) {
    pdmesh::RawCurve c{name, {}, "rhombus", 1, {}};
    for (int k = 0; k <= m; k += step) c.points.push_back(a + (static_cast<double>(k) / m) * (b - a));
    c.points.front() = a;
    c.points.back() = b;
    raw.push_back(std::move(c));
  };
  const Vec2 a = lattice(0, 0), b = lattice(m, 0), c = lattice(m, m), d = lattice(0, m);
  side("ab", a, b);
  side("bc", b, c);
  side("cd", c, d);
  side("da", d, a);
  return pdmesh::build_geometry(std::move(raw));
}

}  // namespace pdmesh_test
