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
// The argument is per node, so the stored states need not be of one step: nodes that break (a) or (b)
// (up to a quarter of them) are rebased: their states stored anew, the box search of metric_search.hpp
// rebuilt over the stored states (reach sqrt 2 R: the support of the ellipse |d0|_P <= R c along any
// axis is R c sqrt(e^T (A0_i + A0_j) e) <= sqrt 2 R max(E_i, E_j)) and searched from each of them (for
// up to kScanRebased of them, every stored state tested instead: the same pairs pass, without the
// search's rebuild), and their pairs that pass the bound added both ways, which keeps the invariant;
// candidates that no longer pass stay, costing only their exact test. More of them rebuild: every state stored and
// searched from. A rebuild whose candidates served fewer than 4 calls did not pay, and the calls after it build the
// exact list (1, 2, 4, ... up to 16 of them) before candidates are tried again.
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
// At most this fraction of the nodes is rebased in one call; more rebuild.
constexpr std::size_t kRebasedFraction = 4;
// A rebuild whose candidates served fewer calls than this did not pay (the nodes move too fast for
// the skin): the calls after it build exactly, 1, 2, 4, ... up to kMostPause calls in a row.
constexpr int kPaying = 4;
constexpr int kMostPause = 16;
// Up to this many rebased nodes scan every stored state for their candidates instead of rebuilding
// the box search (MetricNeighbourCache::rebase).
constexpr std::size_t kScanRebased = 32;

// The eigenvalues of the symmetric [[a, b], [b, c]], smallest first.
void eigenvalues(double a, double b, double c, double& low, double& high) {
  const double mean = 0.5 * (a + c), h = 0.5 * (a - c), r = std::sqrt(h * h + b * b);
  low = mean - r;
  high = mean + r;
}

// Node j's metric has a condition number within kMaxCondition.
bool well_conditioned(const SimParticles& p, std::size_t j) {
  double low = 0.0, high = 0.0;
  eigenvalues(p.m11[j], p.m12[j], p.m22[j], low, high);
  return high <= kMaxCondition * low;
}

bool well_conditioned(const SimParticles& p) {
  for (std::size_t j = 0; j < p.size(); ++j)
    if (!well_conditioned(p, j)) return false;
  return true;
}

}  // namespace

MetricNeighbourCache::MetricNeighbourCache(double skin, double growth) : skin_(skin), growth_(growth) {}

bool MetricNeighbourCache::same_structure(const SimParticles& p, double cutoff) const {
  return p.size() == kind0_.size() && cutoff == cutoff_ && p.kind == kind0_;
}

double MetricNeighbourCache::bound2() const {
  const double r = (1.0 + growth_) / std::sqrt(2.0) + 2.0 * skin_;
  return r * r * cutoff_ * cutoff_ * (1.0 + kMargin);
}

std::vector<std::size_t> MetricNeighbourCache::outgrown(const SimParticles& p, double cutoff, std::size_t limit) const {
  std::vector<std::size_t> out;
  const double move = skin_ * cutoff, move2 = move * move * (1.0 - kMargin);
  const double shrink = (1.0 + kMargin) / ((1.0 + growth_) * (1.0 + growth_));
  for (std::size_t j = 0; j < p.size() && out.size() <= limit; ++j) {
    const double dx = p.x[j] - stored_.x[j], dy = p.y[j] - stored_.y[j];
    bool keep = metric_norm2(stored_.m11[j], stored_.m12[j], stored_.m22[j], dx, dy) <= move2;
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
  stored_.x[j] = p.x[j];
  stored_.y[j] = p.y[j];
  stored_.m11[j] = m11;
  stored_.m12[j] = m12;
  stored_.m22[j] = m22;
  a11_[j] = m22 / det;
  a12_[j] = -m12 / det;
  a22_[j] = m11 / det;
  s0_[j] = size_tensor(m11, m12, m22);
}

// d0^T (A0_i + A0_j)^-1 d0 <= bound2, as d0^T adj(S) d0 <= bound2 det(S), S = A0_i + A0_j.
bool MetricNeighbourCache::candidate(std::size_t i, std::size_t j, double bound2) const {
  const double s11 = a11_[i] + a11_[j], s12 = a12_[i] + a12_[j], s22 = a22_[i] + a22_[j];
  const double dx = stored_.x[j] - stored_.x[i], dy = stored_.y[j] - stored_.y[i];
  return metric_norm2(s22, -s12, s11, dx, dy) <= bound2 * (s11 * s22 - s12 * s12);
}

void MetricNeighbourCache::index() {
  const double reach = std::sqrt(2.0 * bound2()) / cutoff_ * (1.0 + kMargin);
  search_.build(stored_, MetricFrame::of(stored_, pair_factors(stored_)), cutoff_, reach);
}

void MetricNeighbourCache::rebuild(const SimParticles& p, NeighbourFlags& flags) {
  ++rebuilds_;
  served_ = 0;
  const std::size_t n = p.size();
  for (auto* v : {&stored_.x, &stored_.y, &stored_.m11, &stored_.m12, &stored_.m22, &a11_, &a12_, &a22_}) v->resize(n);
  s0_.resize(n);
  for (std::size_t j = 0; j < n; ++j) store_state(p, j);
  index();
  const double b2 = bound2();
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
  // The box search over the states as they are now finds every node that passes the bound with a
  // rebased one (the bound and the box are symmetric in the two nodes). Building it costs as much as
  // testing the bound against every stored state for a few dozen nodes, so a few rebased nodes scan
  // the states instead: the same nodes pass, and the search is built again by the next call that uses it.
  const bool scan = nodes.size() <= kScanRebased;
  if (!scan) index();
  const double b2 = bound2();
  const std::size_t n = p.size();
  for (const std::size_t k : nodes) {
    check_interrupt();
    const bool interior = p.kind[k] == kSimInterior;
    if (interior) rows_[k].clear();
    const auto visit = [&](std::int32_t j) {
      const auto uj = static_cast<std::size_t>(j);
      if (!candidate(k, uj, b2)) return;
      if (interior) rows_[k].push_back(j);
      if (p.kind[uj] != kSimInterior) return;
      std::vector<std::int32_t>& row = rows_[uj];
      const auto at = std::lower_bound(row.begin(), row.end(), static_cast<std::int32_t>(k));
      if (at == row.end() || *at != static_cast<std::int32_t>(k)) row.insert(at, static_cast<std::int32_t>(k));
    };
    if (scan) {
      for (std::size_t j = 0; j < n; ++j)
        if (j != k) visit(static_cast<std::int32_t>(j));
      flags.pairs_examined += n - 1;
    } else {
      flags.pairs_examined += search_.for_each_in_box(k, visit);
    }
    if (interior) std::sort(rows_[k].begin(), rows_[k].end());
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
  if (pause_ > 0) {
    --pause_;
    build_neighbours_metric(p, cutoff, list, flags);
    return;
  }
  if (!valid_) {
    if (!well_conditioned(p)) {
      build_neighbours_metric(p, cutoff, list, flags);
      return;
    }
    rebuild(p, flags);
    valid_ = true;
  } else {
    const std::size_t most = std::max<std::size_t>(1, n / kRebasedFraction);
    const std::vector<std::size_t> out = outgrown(p, cutoff, most);
    // The states about to be stored must be well conditioned: every node's for a rebuild, the
    // rebased ones' otherwise (the others keep theirs).
    const bool stored_well =
        out.size() > most ? well_conditioned(p)
                          : std::all_of(out.begin(), out.end(), [&p](std::size_t j) { return well_conditioned(p, j); });
    if (!stored_well) {
      valid_ = false;
      build_neighbours_metric(p, cutoff, list, flags);
      return;
    }
    if (out.size() > most) {
      if (served_ < kPaying) {
        // The nodes outran the skin before the candidates paid: build exactly for a while.
        valid_ = false;
        pause_ = next_pause_ - 1;
        next_pause_ = std::min(2 * next_pause_, kMostPause);
        build_neighbours_metric(p, cutoff, list, flags);
        return;
      }
      next_pause_ = 1;
      rebuild(p, flags);
    } else if (!out.empty()) {
      rebase(p, out, flags);
    }
  }
  ++served_;
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
