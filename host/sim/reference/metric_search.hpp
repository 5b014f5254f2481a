// The candidate search behind the metric neighbour lists (binning_metric.cpp builds the exact list
// with it, metric_neighbour_cache.cpp its Verlet candidates).
//
// The bound: M_i # M_j is at least the harmonic mean 2 (M_i^-1 + M_j^-1)^-1, so rho_ij <= cutoff puts d
// in the ellipse of (M_i^-1 + M_j^-1) / 2 scaled by the cutoff, whose extent along any unit vector e is
// cutoff sqrt((e^T M_i^-1 e + e^T M_j^-1 e) / 2) <= max(E_i, E_j), E = cutoff sqrt(e^T M^-1 e) the
// bubble's half-extent along e. Along the two axes (u, v) of one frame for all nodes this is a box:
// |d_u| <= max(U_i, U_j) and |d_v| <= max(V_i, V_j). The frame's u is the direction in which the
// nodes' shapes N = M / sqrt(det M) are thinnest on the whole (the leading eigenvector of their sum),
// so that the bubbles of a layer are thin along u and a stretched bubble searches a strip along the
// layer, not the square of its long axis; any frame gives the same pairs, only the candidates differ.
//
// The search: node j gets a level L(j) = floor(log2(U_j / U_min)); per occupied level a cumulative grid
// C_L (the levels <= L) and an exact grid E_L (level L only), each with cells of its largest U by its
// largest V over the (u, v) coordinates. Node i of level l searches C_l and every E_M with M > l out to
// max(U_i, U_max) along u and max(V_i, V_max) along v, the maxima of the grid searched, so every node is
// visited at most once, and keeps the nodes inside the box.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/reference/level_grids.hpp"
#include "sim/reference/metric_pair.hpp"
#include "sim/step_backend.hpp"

namespace pdmesh::reference {

// The frame (u, v) = (cs x + sn y, cs y - sn x) and the widening of the half-extents: a relative 1e-9
// against their rounding and the exact filter's (a relative 1e-15), and an absolute `slack` against the
// rounding of the rotated coordinates. The margins only add candidates, which the exact filter drops.
struct MetricFrame {
  double cs = 1.0, sn = 0.0, slack = 0.0;

  // The frame of the shapes (see above) of the nodes of p, whose pair factors are s; slack 1e-12 of the
  // coordinates' size.
  static MetricFrame of(const SimParticles& p, const std::vector<Sym2>& s);
  double u(double x, double y) const { return cs * x + sn * y; }
  double v(double x, double y) const { return cs * y - sn * x; }
  // cutoff sqrt(e^T M^-1 e) along u and v, widened.
  void half_extents(double m11, double m12, double m22, double cutoff, double& hu, double& hv) const;
};

// The box search over the nodes of p in one frame, every half-extent multiplied by `reach` >= 1.
class MetricBoxSearch {
 public:
  void build(const SimParticles& p, const MetricFrame& frame, double cutoff, double reach);
  // visit(j) for every node j != i with |u_j - u_i| <= max(U_i, U_j) and |v_j - v_i| <= max(V_i, V_j),
  // in no particular order; returns the number of nodes looked at (the search's cost).
  template <class Visit>
  std::uint64_t for_each_in_box(std::size_t i, Visit&& visit) const;

 private:
  // The grids of one level: the largest half-extents of their nodes and the grid itself.
  struct FrameGrid {
    double u_max = 0.0, v_max = 0.0;
    LevelGrids::Grid grid;
  };
  std::vector<double> u_, v_, half_u_, half_v_;
  std::vector<int> level_;
  std::vector<FrameGrid> exact_, cumulative_;
};

template <class Visit>
std::uint64_t MetricBoxSearch::for_each_in_box(std::size_t i, Visit&& visit) const {
  const double ui = u_[i], vi = v_[i], hui = half_u_[i], hvi = half_v_[i];
  std::uint64_t visited = 0;
  auto test = [&](std::int32_t j) {
    const auto uj = static_cast<std::size_t>(j);
    if (uj == i) return;
    ++visited;
    if (std::abs(u_[uj] - ui) > std::max(hui, half_u_[uj]) || std::abs(v_[uj] - vi) > std::max(hvi, half_v_[uj]))
      return;
    visit(j);
  };
  auto search = [&](const FrameGrid& g) {
    g.grid.for_each_in_box_or_all(ui, vi, std::max(hui, g.u_max), std::max(hvi, g.v_max), test);
  };
  const auto li = static_cast<std::size_t>(level_[i]);
  search(cumulative_[li]);
  for (std::size_t m = li + 1; m < exact_.size(); ++m) search(exact_[m]);
  return visited;
}

}  // namespace pdmesh::reference
