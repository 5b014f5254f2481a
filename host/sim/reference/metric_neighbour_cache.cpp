// Verlet candidate lists for the metric neighbour search (see metric_neighbour_cache.hpp).
//
// Why the cached candidates are complete. Write A = M^-1 for a node's metric M. The pair metric
// M_i # M_j is at least the harmonic mean 2 (A_i + A_j)^-1, so a pair within the cut-off c has
// d^T (A_i + A_j)^-1 d <= c^2 / 2. Every node has a stored state, its position x0 and metric M0
// (A0 = M0^-1), and the invariant is: j is a candidate of interior node i whenever the stored states
// satisfy d0^T (A0_i + A0_j)^-1 d0 <= (R c)^2, R = (1 + growth) / sqrt 2 + 2 skin. A call uses the
// candidates when n, cutoff and every kind are unchanged and every node (any kind: a candidate's metric
// and position enter the bound) has
// (a) moved by at most skin * c in its M0: |x - x0|_M0 <= skin c, and
// (b) a bubble grown by at most 1 + growth in every direction: M >= M0 / (1 + growth)^2, checked as the
//     smallest eigenvalue of S0 M S0 (S0 = M0^(-1/2)).
// Then for a pair within the cut-off now: by (b), A_i + A_j <= (1 + growth)^2 (A0_i + A0_j), so with
// |v|_P^2 = v^T (A0_i + A0_j)^-1 v, |d|_P <= (1 + growth) c / sqrt 2; P <= M0_i and P <= M0_j, so by (a)
// each node's move is at most skin c in |.|_P, and |d0|_P <= |d|_P + 2 skin c <= R c: j is a candidate.
// The argument is per node, so the stored states need not be of one step: a few nodes that break (a)
// or (b) are rebased (their state stored anew, their pairs with every node tested again, both ways),
// which keeps the invariant; candidates that no longer pass stay, costing only their exact test. More
// of them rebuild: every state stored, and the candidates found by metric_search.hpp's box search at
// reach sqrt 2 R (the support of the ellipse |d0|_P <= R c along any axis is
// R c sqrt(e^T (A0_i + A0_j) e) <= sqrt 2 R max(E_i, E_j)).
//
// Rounding. Each test is a quadratic form or a 2x2 determinant of the metrics, whose relative error is
// at most a few ulps times the metric's condition number; every test carries a relative margin of
// 1e-5. Stored metrics have condition numbers up to 1e9 (aspect ratios up to 3e4), and a node whose
// bubble shrank to less than half its stored size in some direction is rebased, so current metrics
// stay within 5e9. Particles with a metric worse conditioned keep no candidates: each call then builds
// the exact list.
#include "sim/reference/metric_neighbour_cache.hpp"

#include <algorithm>
#include <cmath>

#include "core/interrupt.hpp"
#include "core/parallel.hpp"
#include "sim/reference/metric_pair.hpp"
#include "sim/reference/reference_backend.hpp"

namespace pdmesh::reference {
namespace {

constexpr double kMargin = 1e-5;
constexpr double kMaxCondition = 1e9;
// S0 M S0 larger than this (a bubble shrunk to less than half its stored size in some direction) also
// rebases the node: the current metrics' condition numbers stay within 5x the stored ones (rounding).
constexpr double kMaxRelativeGrowth = 4.0;
// At most this many nodes are rebased in one call (each tests its pairs with every node); more rebuild.
constexpr std::size_t kMaxRebased = 32;

// The eigenvalues of the symmetric [[a, b], [b, c]], smallest first.
void eigenvalues(double a, double b, double c, double& low, double& high) {
  const double mean = 0.5 * (a + c), h = 0.5 * (a - c), r = std::sqrt(h * h + b * b);
  low = mean - r;
  high = mean + r;
}

bool well_conditioned(const SimParticles& p) {
  for (std::size_t j = 0; j < p.size(); ++j) {
    double low = 0.0, high = 0.0;
    eigenvalues(p.m11[j], p.m12[j], p.m22[j], low, high);
    if (!(high <= kMaxCondition * low)) return false;
  }
  return true;
}

}  // namespace

MetricNeighbourCache::MetricNeighbourCache(double skin, double growth) : skin_(skin), growth_(growth) {}

bool MetricNeighbourCache::same_structure(const SimParticles& p, double cutoff) const {
  return p.size() == kind0_.size() && cutoff == cutoff_ && p.kind == kind0_;
}

double MetricNeighbourCache::bound2(double cutoff) const {
  const double r = (1.0 + growth_) / std::sqrt(2.0) + 2.0 * skin_;
  return r * r * cutoff * cutoff * (1.0 + kMargin);
}

std::vector<std::size_t> MetricNeighbourCache::outgrown(const SimParticles& p, double cutoff, std::size_t limit) const {
  std::vector<std::size_t> out;
  const double move = skin_ * cutoff, move2 = move * move * (1.0 - kMargin);
  const double shrink = (1.0 + kMargin) / ((1.0 + growth_) * (1.0 + growth_));
  for (std::size_t j = 0; j < p.size() && out.size() <= limit; ++j) {
    const double dx = p.x[j] - x0_[j], dy = p.y[j] - y0_[j];
    bool keep = metric_norm2(m11_[j], m12_[j], m22_[j], dx, dy) <= move2;
    if (keep) {
      // K = S0 M S0, S0 = [[a, b], [b, c]].
      const SizeTensor& s = s0_[j];
      const double m11 = p.m11[j], m12 = p.m12[j], m22 = p.m22[j];
      const double t11 = m11 * s.a + m12 * s.b, t12 = m11 * s.b + m12 * s.c;  // (M S0), first row
      const double t21 = m12 * s.a + m22 * s.b, t22 = m12 * s.b + m22 * s.c;  // (M S0), second row
      double low = 0.0, high = 0.0;
      eigenvalues(s.a * t11 + s.b * t21, s.a * t12 + s.b * t22, s.b * t12 + s.c * t22, low, high);
      keep = low >= shrink && high <= kMaxRelativeGrowth;
    }
    if (!keep) out.push_back(j);
  }
  return out;
}

void MetricNeighbourCache::store_state(const SimParticles& p, std::size_t j) {
  const double m11 = p.m11[j], m12 = p.m12[j], m22 = p.m22[j], det = m11 * m22 - m12 * m12;
  x0_[j] = p.x[j];
  y0_[j] = p.y[j];
  m11_[j] = m11;
  m12_[j] = m12;
  m22_[j] = m22;
  a11_[j] = m22 / det;
  a12_[j] = -m12 / det;
  a22_[j] = m11 / det;
  s0_[j] = size_tensor(m11, m12, m22);
}

// d0^T (A0_i + A0_j)^-1 d0 <= bound2, as d0^T adj(S) d0 <= bound2 det(S), S = A0_i + A0_j.
bool MetricNeighbourCache::candidate(std::size_t i, std::size_t j, double bound2) const {
  const double s11 = a11_[i] + a11_[j], s12 = a12_[i] + a12_[j], s22 = a22_[i] + a22_[j];
  const double dx = x0_[j] - x0_[i], dy = y0_[j] - y0_[i];
  return metric_norm2(s22, -s12, s11, dx, dy) <= bound2 * (s11 * s22 - s12 * s12);
}

void MetricNeighbourCache::rebuild(const SimParticles& p, double cutoff, NeighbourFlags& flags) {
  ++rebuilds_;
  const std::size_t n = p.size();
  for (auto* v : {&x0_, &y0_, &m11_, &m12_, &m22_, &a11_, &a12_, &a22_}) v->resize(n);
  s0_.resize(n);
  for (std::size_t j = 0; j < n; ++j) store_state(p, j);
  const double b2 = bound2(cutoff);
  const double reach = std::sqrt(2.0 * b2) / cutoff * (1.0 + kMargin);
  search_.build(p, MetricFrame::of(p, pair_factors(p)), cutoff, reach);
  rows_.assign(n, {});
  std::vector<std::uint64_t> examined(n, 0);
  parallel_for(
      n,
      [&](std::size_t i) {
        if (p.kind[i] != kSimInterior) return;
        std::vector<std::int32_t>& row = rows_[i];
        examined[i] = search_.for_each_in_box(i, [&](std::int32_t j) {
          if (candidate(i, static_cast<std::size_t>(j), b2)) row.push_back(j);
        });
        std::sort(row.begin(), row.end());
      },
      256);
  for (std::size_t i = 0; i < n; ++i) flags.pairs_examined += examined[i];
}

void MetricNeighbourCache::rebase(const SimParticles& p, const std::vector<std::size_t>& nodes, NeighbourFlags& flags) {
  rebased_ += nodes.size();
  for (const std::size_t k : nodes) store_state(p, k);
  const double b2 = bound2(cutoff_);
  const std::size_t n = p.size();
  for (const std::size_t k : nodes) {
    check_interrupt();
    const bool interior = p.kind[k] == kSimInterior;
    if (interior) rows_[k].clear();
    for (std::size_t j = 0; j < n; ++j) {
      if (j == k || !candidate(k, j, b2)) continue;
      if (interior) rows_[k].push_back(static_cast<std::int32_t>(j));
      if (p.kind[j] != kSimInterior) continue;
      std::vector<std::int32_t>& row = rows_[j];
      const auto at = std::lower_bound(row.begin(), row.end(), static_cast<std::int32_t>(k));
      if (at == row.end() || *at != static_cast<std::int32_t>(k)) row.insert(at, static_cast<std::int32_t>(k));
    }
    flags.pairs_examined += n;
  }
}

void MetricNeighbourCache::build(const SimParticles& p, double cutoff, NeighbourList& list, NeighbourFlags& flags) {
  start_list(p, list, flags);
  const std::size_t n = p.size();
  if (n == 0 || flags.first_invalid >= 0) {
    valid_ = false;
    return;
  }
  if (!same_structure(p, cutoff)) {
    // A new particle set (count, kinds or cutoff changed, or the first call): the candidates pay
    // only when reused, so this call builds the exact list and the next one, if the structure
    // stays, builds candidates.
    valid_ = false;
    kind0_ = p.kind;
    cutoff_ = cutoff;
    build_neighbours_metric(p, cutoff, list, flags);
    return;
  }
  if (!valid_) {
    if (!well_conditioned(p)) {
      build_neighbours_metric(p, cutoff, list, flags);
      return;
    }
    rebuild(p, cutoff, flags);
    valid_ = true;
  } else {
    const std::vector<std::size_t> out = outgrown(p, cutoff, kMaxRebased);
    if (!out.empty() && !well_conditioned(p)) {
      valid_ = false;
      build_neighbours_metric(p, cutoff, list, flags);
      return;
    }
    if (out.size() > kMaxRebased) {
      rebuild(p, cutoff, flags);
    } else if (!out.empty()) {
      rebase(p, out, flags);
    }
  }
  // The exact filter, written as reference::build_neighbours_metric writes it (same rounding); the
  // candidates are ascending, so each row is too.
  const std::vector<Sym2> s = pair_factors(p);
  const double c2 = cutoff * cutoff;
  const auto stride = static_cast<std::size_t>(list.stride);
  parallel_for(
      n,
      [&](std::size_t i) {
        if (p.kind[i] != kSimInterior) return;
        const std::size_t base = i * stride;
        std::size_t count = 0;
        for (const std::int32_t j : rows_[i]) {
          const auto uj = static_cast<std::size_t>(j);
          if (pair_distance2(s[i], s[uj], p.x[uj] - p.x[i], p.y[uj] - p.y[i]) <= c2) {
            if (count < stride) list.index[base + count] = j;
            ++count;
          }
        }
        list.count[i] = static_cast<std::int32_t>(count);
      },
      1024);
  for (std::size_t i = 0; i < n; ++i) {
    if (p.kind[i] != kSimInterior) continue;
    flags.pairs_examined += rows_[i].size();
    add_row_flags(list.count[i], list, flags);
  }
}

}  // namespace pdmesh::reference
