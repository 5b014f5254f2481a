// Reference step 1 in metric mode (metric_pair.hpp): interior node i's neighbours are the j != i with
// rho_ij = |x_j - x_i| in the pair's metric <= cutoff. The criterion is symmetric, and a bubble is an
// ellipse up to aspect 1000s.
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
// visited at most once, and filters the candidates by the box and then exactly (pair_distance2). The
// rows are built on every core, each from its own node's search, so the list does not depend on the
// thread count. The Verlet cache is not used here.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/interrupt.hpp"
#include "core/parallel.hpp"
#include "sim/reference/level_grids.hpp"
#include "sim/reference/metric_pair.hpp"
#include "sim/reference/reference_backend.hpp"

namespace pdmesh::reference {

namespace {

// The grids of one level: the largest half-extents of their nodes and the grid itself.
struct FrameGrid {
  double u_max = 0.0, v_max = 0.0;
  LevelGrids::Grid grid;
};

}  // namespace

void build_neighbours_metric(const SimParticles& p, double cutoff, NeighbourList& list, NeighbourFlags& flags) {
  start_list(p, list, flags);
  const std::size_t n = p.size();
  if (n == 0 || flags.first_invalid >= 0) return;
  const std::vector<Sym2> s = pair_factors(p);
  // The frame: u along the leading eigenvector of the sum of the shapes N (a sum in node order).
  double sa = 0.0, sb = 0.0, sc = 0.0, extent = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    sa += s[j].a;
    sb += s[j].b;
    sc += s[j].c;
    extent = std::max({extent, std::abs(p.x[j]), std::abs(p.y[j])});
  }
  const double angle = 0.5 * std::atan2(2.0 * sb, sa - sc);
  const double cs = std::cos(angle), sn = std::sin(angle);
  // The half-extents are widened by a relative 1e-9 against their rounding and the exact filter's (a
  // relative 1e-15), and by an absolute 1e-12 of the coordinates' size against the rounding of the
  // rotated coordinates: the margins only add candidates, which the exact filter drops.
  constexpr double kWiden = 1.0 + 1e-9;
  const double slack = 1e-12 * (1.0 + extent);
  std::vector<double> u(n), v(n), half_u(n), half_v(n);
  for (std::size_t j = 0; j < n; ++j) {
    u[j] = cs * p.x[j] + sn * p.y[j];
    v[j] = cs * p.y[j] - sn * p.x[j];
    const double m11 = p.m11[j], m12 = p.m12[j], m22 = p.m22[j];
    const double det = m11 * m22 - m12 * m12;
    // e^T M^-1 e with M^-1 = [[m22, -m12], [-m12, m11]] / det, e = (cs, sn) and (-sn, cs).
    const double wu = (m22 * cs * cs - 2.0 * m12 * cs * sn + m11 * sn * sn) / det;
    const double wv = (m22 * sn * sn + 2.0 * m12 * cs * sn + m11 * cs * cs) / det;
    half_u[j] = kWiden * cutoff * std::sqrt(std::max(wu, 0.0)) + slack;
    half_v[j] = kWiden * cutoff * std::sqrt(std::max(wv, 0.0)) + slack;
  }
  double u_min = HUGE_VAL;
  for (std::size_t j = 0; j < n; ++j) u_min = std::min(u_min, half_u[j]);
  std::vector<int> level(n);
  int top = 0;
  for (std::size_t j = 0; j < n; ++j) {
    level[j] = size_level(half_u[j] / u_min);
    top = std::max(top, level[j]);
  }
  const auto levels = static_cast<std::size_t>(top) + 1;
  std::vector<std::vector<std::int32_t>> members(levels);
  for (std::size_t j = 0; j < n; ++j)
    members[static_cast<std::size_t>(level[j])].push_back(static_cast<std::int32_t>(j));
  std::vector<FrameGrid> exact(levels), cumulative(levels);
  std::vector<std::int32_t> upto;
  double upto_u = 0.0, upto_v = 0.0;
  for (std::size_t l = 0; l < levels; ++l) {
    FrameGrid& e = exact[l];
    for (const std::int32_t j : members[l]) {
      e.u_max = std::max(e.u_max, half_u[static_cast<std::size_t>(j)]);
      e.v_max = std::max(e.v_max, half_v[static_cast<std::size_t>(j)]);
    }
    upto_u = std::max(upto_u, e.u_max);
    upto_v = std::max(upto_v, e.v_max);
    upto.insert(upto.end(), members[l].begin(), members[l].end());
    if (members[l].empty()) continue;
    e.grid.build(u, v, members[l], e.u_max, e.v_max);
    FrameGrid& c = cumulative[l];
    c.u_max = upto_u;
    c.v_max = upto_v;
    c.grid.build(u, v, upto, c.u_max, c.v_max);
  }
  const double c2 = cutoff * cutoff;
  std::vector<std::uint64_t> examined(n, 0);
  struct Scratch {
    std::vector<std::int32_t> found;
  };
  parallel_for_scratch<Scratch>(
      n,
      [&](Scratch& scratch, std::size_t i) {
        if (p.kind[i] != kSimInterior) return;
        std::vector<std::int32_t>& found = scratch.found;
        found.clear();
        const double ui = u[i], vi = v[i], hui = half_u[i], hvi = half_v[i];
        std::uint64_t visited = 0;
        auto test = [&](std::int32_t j) {
          if (static_cast<std::size_t>(j) == i) return;
          ++visited;
          const auto uj = static_cast<std::size_t>(j);
          if (std::abs(u[uj] - ui) > std::max(hui, half_u[uj]) || std::abs(v[uj] - vi) > std::max(hvi, half_v[uj]))
            return;
          if (pair_distance2(s[i], s[uj], p.x[uj] - p.x[i], p.y[uj] - p.y[i]) <= c2) found.push_back(j);
        };
        auto search = [&](const FrameGrid& g) {
          g.grid.for_each_in_box_or_all(ui, vi, std::max(hui, g.u_max), std::max(hvi, g.v_max), test);
        };
        const auto li = static_cast<std::size_t>(level[i]);
        search(cumulative[li]);
        for (std::size_t m = li + 1; m < levels; ++m) search(exact[m]);
        std::sort(found.begin(), found.end());
        examined[i] = visited;
        // Each row has its own slots in the list; the flags are summed below, in node order.
        store_row(i, found, list);
      },
      256);
  for (std::size_t i = 0; i < n; ++i) {
    if (p.kind[i] != kSimInterior) continue;
    flags.pairs_examined += examined[i];
    add_row_flags(list.count[i], list, flags);
  }
}

void build_neighbours_metric_brute_force(const SimParticles& p, double cutoff, NeighbourList& list,
                                         NeighbourFlags& flags) {
  start_list(p, list, flags);
  if (flags.first_invalid >= 0) return;
  const std::size_t n = p.size();
  const std::vector<Sym2> s = pair_factors(p);
  const double c2 = cutoff * cutoff;
  std::vector<std::int32_t> found;
  for (std::size_t i = 0; i < n; ++i) {
    if (p.kind[i] != kSimInterior) continue;
    found.clear();
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      ++flags.pairs_examined;
      if (pair_distance2(s[i], s[j], p.x[j] - p.x[i], p.y[j] - p.y[i]) <= c2)
        found.push_back(static_cast<std::int32_t>(j));
    }
    store_sorted(i, found, list, flags);
  }
}

}  // namespace pdmesh::reference
