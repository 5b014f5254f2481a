// Shared fixtures of the simulation tests: appending a particle to SimParticles, setting its metric, and the thesis'
// circle-in-circle geometry (outer radius 10, inner 0.5, four semicircles of 31 equally spaced points).
#pragma once
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "geometry/geometry.hpp"
#include "sim/step_backend.hpp"

namespace pdmesh_test {

// A double in [0, 1) from the top 53 bits (reproducible across standard libraries).
inline double uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

inline void add(pdmesh::SimParticles& p, double x, double y, double q, std::uint8_t kind = pdmesh::kSimInterior) {
  p.x.push_back(x);
  p.y.push_back(y);
  p.q.push_back(q);
  p.kind.push_back(kind);
  p.prev.push_back(-1);
  p.next.push_back(-1);
  p.tx.push_back(0.0);
  p.ty.push_back(0.0);
}

// Node i's metric (metric mode): the arrays are first extended to the nodes added since.
inline void set_metric(pdmesh::SimParticles& p, std::size_t i, double m11, double m12, double m22) {
  p.m11.resize(p.size(), 0.0);
  p.m12.resize(p.size(), 0.0);
  p.m22.resize(p.size(), 0.0);
  p.m11[i] = m11;
  p.m12[i] = m12;
  p.m22[i] = m22;
}

// Node i's metric M = R(a) diag(1/h1^2, 1/h2^2) R(a)^T: size h1 along the direction at angle a, h2 across.
inline void set_sizes(pdmesh::SimParticles& p, std::size_t i, double h1, double h2, double a) {
  const double c = std::cos(a), s = std::sin(a), l1 = 1.0 / (h1 * h1), l2 = 1.0 / (h2 * h2);
  set_metric(p, i, l1 * c * c + l2 * s * s, (l1 - l2) * c * s, l1 * s * s + l2 * c * c);
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

// Rings of 24 nodes, radius and spacing growing geometrically from 0.001 to 1 (an airfoil's
// leading edge in miniature), jittered: spacing graded 1000x.
inline pdmesh::SimParticles graded_rings(std::mt19937_64& rng) {
  pdmesh::SimParticles p;
  const int per_ring = 24;
  const double growth = 1.0 + 2.0 * M_PI / per_ring;
  for (double rho = 0.001 / (2.0 * M_PI / per_ring); rho < 1.3 / (2.0 * M_PI / per_ring); rho *= growth) {
    const double q = rho * 2.0 * M_PI / per_ring;
    for (int k = 0; k < per_ring; ++k) {
      const double t = 2.0 * M_PI * (k + 0.2 * uniform(rng)) / per_ring;
      const double rr = rho * (1.0 + 0.1 * (uniform(rng) - 0.5));
      add(p, rr * std::cos(t), rr * std::sin(t), q);
    }
  }
  return p;
}

}  // namespace pdmesh_test
