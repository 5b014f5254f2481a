// Shared fixtures of the simulation tests: appending a particle to SimParticles, and the thesis'
// circle-in-circle geometry (outer radius 10, inner 0.5, four semicircles of 31 equally spaced points).
#pragma once
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "geometry/geometry.hpp"
#include "sim/step_backend.hpp"

namespace pdmesh_test {

inline void add(pdmesh::SimParticles& p, double x, double y, double q,
                std::uint8_t kind = pdmesh::kSimInterior) {
  p.x.push_back(x);
  p.y.push_back(y);
  p.q.push_back(q);
  p.kind.push_back(kind);
  p.prev.push_back(-1);
  p.next.push_back(-1);
  p.tx.push_back(0.0);
  p.ty.push_back(0.0);
}

// Two semicircle curves (upper, lower) of `points` equally spaced points, end points exactly on the x axis.
inline void add_circle(std::vector<pdmesh::RawCurve>& raw, double r, int points, const std::string& name) {
  const int n = points - 1;
  for (int half = 0; half < 2; ++half) {
    pdmesh::RawCurve curve{name + (half == 0 ? "_upper" : "_lower"), {}, "circles", 0, {}};
    for (int i = 0; i <= n; ++i) {
      const double t = M_PI * (half + static_cast<double>(i) / n);
      pdmesh::Vec2 p{r * std::cos(t), r * std::sin(t)};
      if (i == 0) p = {half == 0 ? r : -r, 0.0};
      if (i == n) p = {half == 0 ? -r : r, 0.0};
      curve.points.push_back(p);
    }
    raw.push_back(std::move(curve));
  }
}

inline pdmesh::Geometry circle_circle() {
  std::vector<pdmesh::RawCurve> raw;
  add_circle(raw, 10.0, 31, "outer");
  add_circle(raw, 0.5, 31, "inner");
  return pdmesh::build_geometry(std::move(raw));
}

}  // namespace pdmesh_test
