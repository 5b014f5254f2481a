// Verlet candidate lists for the reference neighbour search (see neighbour_cache.hpp).
//
// Why the cached candidates are complete. At a rebuild every node j stores its position x0_j, an
// allowed displacement a_j, and each interior node i a radius bound M_i >= cutoff * q_i. Node i's
// candidates are all j != i with |x0_j - x0_i| <= (M_i + a_i + a_j) k, k = 1 + 1e-9. A later call
// reuses them only when n, cutoff and every kind are unchanged, every node satisfies
// |x_j - x0_j| <= a_j, and every interior node cutoff * q_i <= M_i. Then for any j within the
// cut-off at the current positions, |x_j - x_i| <= cutoff * q_i <= M_i, and by the triangle
// inequality |x0_j - x0_i| <= |x_j - x_i| + |x_j - x0_j| + |x_i - x0_i| <= M_i + a_i + a_j: j is a
// candidate. Every quantity is a rounded difference or product of a few doubles (relative error a
// few ulps, ~1e-15), far inside the factor k, so the computed tests keep the implication. The
// argument uses only per-index positions, so it holds whatever the host did to the nodes
// (reordered, replaced) as long as n and kinds are unchanged; q_j of the other node plays no part
// in the criterion. Kinds decide which nodes get lists, so any kind change rebuilds.
#include "sim/reference/neighbour_cache.hpp"

#include <algorithm>
#include <cmath>

#include "core/interrupt.hpp"
#include "sim/reference/reference_backend.hpp"

namespace pdmesh::reference {
namespace {

constexpr double kRoundingMargin = 1.0 + 1e-9;

}  // namespace

NeighbourCache::NeighbourCache(double skin, double growth) : skin_(skin), growth_(growth) {}

bool NeighbourCache::same_structure(const SimParticles& p, double cutoff) const {
  return p.size() == kind0_.size() && cutoff == cutoff_ && p.kind == kind0_;
}

bool NeighbourCache::still_complete(const SimParticles& p, double cutoff) const {
  const std::size_t n = p.size();
  if (!valid_ || n != x0_.size() || n != kind0_.size() || cutoff != cutoff_) return false;
  for (std::size_t j = 0; j < n; ++j) {
    if (p.kind[j] != kind0_[j]) return false;
    const double dx = p.x[j] - x0_[j], dy = p.y[j] - y0_[j];
    if (!(dx * dx + dy * dy <= allowed2_[j])) return false;
    if (p.kind[j] == kSimInterior && !(cutoff * p.q[j] <= max_radius_[j])) return false;
  }
  return true;
}

void NeighbourCache::rebuild(const SimParticles& p, double cutoff, NeighbourFlags& flags) {
  ++rebuilds_;
  const std::size_t n = p.size();
  cutoff_ = cutoff;
  x0_ = p.x;
  y0_ = p.y;
  kind0_ = p.kind;
  radius_.resize(n);
  allowed_.resize(n);
  allowed2_.resize(n);
  max_radius_.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    radius_[j] = cutoff * p.q[j];
    allowed_[j] = skin_ * radius_[j];
    allowed2_[j] = allowed_[j] * allowed_[j];
    max_radius_[j] = radius_[j] * (1.0 + growth_);
  }
  grids_.build(p, radius_);
  // The largest allowed displacement per level, and over all levels up to each level (C_l).
  level_allowed_.assign(grids_.levels(), 0.0);
  for (std::size_t j = 0; j < n; ++j) {
    auto& a = level_allowed_[static_cast<std::size_t>(grids_.level(j))];
    a = std::max(a, allowed_[j]);
  }
  cumulative_allowed_ = level_allowed_;
  for (std::size_t l = 1; l < cumulative_allowed_.size(); ++l)
    cumulative_allowed_[l] = std::max(cumulative_allowed_[l], cumulative_allowed_[l - 1]);

  first_.assign(n + 1, 0);
  candidates_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    // A stop request ends the run with this cache half built: it is never read again.
    if ((i & 16383) == 0) check_interrupt();
    first_[i] = static_cast<std::int64_t>(candidates_.size());
    if (p.kind[i] != kSimInterior) continue;
    found_.clear();
    const double xi = p.x[i], yi = p.y[i], own = max_radius_[i] + allowed_[i];
    const auto l = static_cast<std::size_t>(grids_.level(i));
    auto reach = [&](std::size_t m) {
      return (own + (m == l ? cumulative_allowed_[l] : level_allowed_[m])) * kRoundingMargin;
    };
    auto test = [&](std::int32_t j) {
      const auto ju = static_cast<std::size_t>(j);
      if (ju == i) return;
      ++flags.pairs_examined;
      const double dx = p.x[ju] - xi, dy = p.y[ju] - yi;
      const double bound = (own + allowed_[ju]) * kRoundingMargin;
      if (dx * dx + dy * dy <= bound * bound) found_.push_back(j);
    };
    grids_.for_each_near(xi, yi, l, reach, test);
    std::sort(found_.begin(), found_.end());
    candidates_.insert(candidates_.end(), found_.begin(), found_.end());
  }
  first_[n] = static_cast<std::int64_t>(candidates_.size());
  valid_ = true;
}

void NeighbourCache::build(const SimParticles& p, double cutoff, NeighbourList& list, NeighbourFlags& flags) {
  if (p.has_metric()) {
    valid_ = false;
    metric_.build(p, cutoff, list, flags);
    return;
  }
  start_list(p, list, flags);
  const std::size_t n = p.size();
  if (n == 0 || flags.first_invalid >= 0) {
    valid_ = false;
    return;
  }
  if (!still_complete(p, cutoff)) {
    // A new particle set (count, kinds or cutoff changed, or the first call): the candidates pay
    // only when reused, so this call builds the exact list and the next one, if the structure
    // stays, builds candidates. Motion alone (the simulation's case) rebuilds at once.
    if (!same_structure(p, cutoff)) {
      valid_ = false;
      kind0_ = p.kind;
      cutoff_ = cutoff;
      build_neighbours(p, cutoff, list, flags);
      return;
    }
    rebuild(p, cutoff, flags);
  }
  // The exact filter, written as reference::build_neighbours writes it (same rounding).
  const auto stride = static_cast<std::size_t>(list.stride);
  for (std::size_t i = 0; i < n; ++i) {
    if ((i & 16383) == 0) check_interrupt();
    if (p.kind[i] != kSimInterior) continue;
    const double xi = p.x[i], yi = p.y[i], r = cutoff * p.q[i], r2 = r * r;
    const std::size_t base = i * stride;
    std::size_t count = 0;
    const auto begin = static_cast<std::size_t>(first_[i]), end = static_cast<std::size_t>(first_[i + 1]);
    for (std::size_t k = begin; k < end; ++k) {
      const std::int32_t j = candidates_[k];
      const double dx = p.x[static_cast<std::size_t>(j)] - xi, dy = p.y[static_cast<std::size_t>(j)] - yi;
      if (dx * dx + dy * dy <= r2) {
        if (count < stride) list.index[base + count] = j;
        ++count;
      }
    }
    flags.pairs_examined += end - begin;
    const auto c = static_cast<std::int32_t>(count);
    list.count[i] = c;
    flags.max_count = std::max(flags.max_count, c);
    flags.pairs_within += count;
    if (count > stride) flags.overflow = 1;
  }
}

}  // namespace pdmesh::reference
