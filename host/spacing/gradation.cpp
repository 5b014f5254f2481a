// GradationGraph: the leaf-corner graph and the source-carrying Dijkstra sweep that limits the
// spacing field's gradient (Persson 2006; OceanMesh2D's limgrad and JIGSAW's marche do the same on grids).
#include "spacing/gradation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <queue>
#include <utility>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/parallel.hpp"

namespace pdmesh {

GradationGraph::GradationGraph(std::vector<Vec2> corners, const std::vector<std::int32_t>& leaf_corner)
    : corners_(std::move(corners)), leaf_corner_(leaf_corner) {
  const std::size_t n = corners_.size();
  if (leaf_corner.size() % 4 != 0)
    throw Error(fmt::format("gradation graph: {} leaf corners is not 4 per leaf", leaf_corner.size()));
  for (const std::int32_t c : leaf_corner)
    if (c < 0 || static_cast<std::size_t>(c) >= n) throw Error(fmt::format("gradation graph: corner {} of {}", c, n));
  // Each leaf joins its 4 corners pairwise (sides and diagonals): a corner's neighbours are the other
  // corners of its leaves, in the leaves' order. A corner shared by several leaves gets a neighbour
  // twice at most, which costs a repeated relaxation and nothing else.
  // A counting sort of the entries by corner, keeping k ascending within each corner. Large graphs
  // are sorted in two halves of the entries at once: each half counts its own entries per corner, the
  // first half's entries of a corner go before the second's, and each half then writes its own: the
  // same lists as one pass.
  const std::size_t m = leaf_corner.size();
  const std::size_t parts = m >= 2 * kEntriesPerPart ? 2 : 1;
  std::vector<std::vector<std::int32_t>> count(parts, std::vector<std::int32_t>(n, 0));
  auto part_range = [&](std::size_t part) {
    return std::pair<std::size_t, std::size_t>{part * m / parts, (part + 1) * m / parts};
  };
  parallel_for(
      parts,
      [&](std::size_t part) {
        const auto [begin, end] = part_range(part);
        std::vector<std::int32_t>& mine = count[part];
        for (std::size_t k = begin; k < end; ++k) ++mine[static_cast<std::size_t>(leaf_corner[k])];
      },
      1);
  // leaf_start_[c] is where corner c's list starts; count[part][c] becomes where part's entries of
  // corner c start in leaf_of_.
  leaf_start_.assign(n + 1, 0);
  std::int32_t at = 0;
  for (std::size_t c = 0; c < n; ++c) {
    leaf_start_[c] = at;
    for (std::size_t part = 0; part < parts; ++part) {
      const std::int32_t here = count[part][c];
      count[part][c] = at;
      at += here;
    }
  }
  leaf_start_[n] = at;
  leaf_of_.resize(m);
  parallel_for(
      parts,
      [&](std::size_t part) {
        const auto [begin, end] = part_range(part);
        std::vector<std::int32_t>& next = count[part];
        for (std::size_t k = begin; k < end; ++k)
          leaf_of_[static_cast<std::size_t>(next[static_cast<std::size_t>(leaf_corner[k])]++)] =
              static_cast<std::int32_t>(k);
      },
      1);
}

void GradationGraph::limit(double g, const std::vector<double>& q0, std::vector<double>& q,
                           std::vector<std::int32_t>& source, const std::vector<PointSource>& points,
                           const std::vector<std::vector<std::int32_t>>& point_corners) const {
  const std::size_t n = corners_.size();
  if (q0.size() != n) throw Error(fmt::format("gradation: {} values for {} corners", q0.size(), n));
  if (point_corners.size() != points.size())
    throw Error(fmt::format("gradation: {} point sources but {} corner lists", points.size(), point_corners.size()));
  q = q0;
  source.resize(n);
  for (std::size_t i = 0; i < n; ++i) source[i] = static_cast<std::int32_t>(i);
  if (!(g > 0.0)) return;
  // A point source's cone enters at the corners of the leaf that holds it.
  for (std::size_t k = 0; k < points.size(); ++k)
    for (const std::int32_t c : point_corners[k]) {
      const double v = points[k].q + g * dist(corners_[static_cast<std::size_t>(c)], points[k].p);
      if (v < q[static_cast<std::size_t>(c)]) {
        q[static_cast<std::size_t>(c)] = v;
        source[static_cast<std::size_t>(c)] = static_cast<std::int32_t>(n + k);
      }
    }
  sweep(g, q0, q, source, nullptr, points);
}

void GradationGraph::relimit(double g, const std::vector<double>& q0, std::vector<double>& q,
                             std::vector<std::int32_t>& source, const std::vector<std::int32_t>& seeds,
                             const std::vector<PointSource>& points) const {
  const std::size_t n = corners_.size();
  if (q0.size() != n || q.size() != n || source.size() != n)
    throw Error(fmt::format("gradation: {} / {} / {} values for {} corners", q0.size(), q.size(), source.size(), n));
  if (!(g > 0.0)) return;
  sweep(g, q0, q, source, &seeds, points);
}

namespace {
using Entry = std::pair<double, std::int32_t>;

}  // namespace

// Values that are all >= 0 (none -0.0 or NaN) order as their bit patterns do, so a stable LSD radix
// sort on those (11-bit digits, a pass skipped where all share the digit) keeps the corner order among
// equal values: std::sort's order, in a few linear passes (std::sort of round 1's 133k entries was
// 8 ms of 30P30N's spacing phase). Other values take std::sort.
void detail::sort_gradation_entries(std::vector<Entry>& entries) {
  constexpr int kBits = 11, kDigits = (64 + kBits - 1) / kBits;
  constexpr std::size_t kBuckets = std::size_t{1} << kBits;
  const std::size_t n = entries.size();
  std::vector<std::uint64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double v = entries[i].first;
    if (!(v >= 0.0) || std::signbit(v)) {
      std::sort(entries.begin(), entries.end());
      return;
    }
    std::memcpy(&key[i], &v, sizeof v);
  }
  std::vector<std::array<std::uint32_t, kBuckets>> count(kDigits);
  for (auto& c : count) c.fill(0);
  for (const std::uint64_t k : key)
    for (int d = 0; d < kDigits; ++d) ++count[static_cast<std::size_t>(d)][(k >> (kBits * d)) & (kBuckets - 1)];
  std::vector<Entry> other(n);
  std::vector<std::uint64_t> other_key(n);
  for (int d = 0; d < kDigits; ++d) {
    auto& c = count[static_cast<std::size_t>(d)];
    if (std::any_of(c.begin(), c.end(), [n](std::uint32_t x) { return x == n; })) continue;  // one digit for all
    std::uint32_t sum = 0;
    for (std::uint32_t& x : c) {
      const std::uint32_t here = x;
      x = sum;
      sum += here;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t slot = c[(key[i] >> (kBits * d)) & (kBuckets - 1)]++;
      other[slot] = entries[i];
      other_key[slot] = key[i];
    }
    entries.swap(other);
    key.swap(other_key);
  }
}

void GradationGraph::sweep(double g, const std::vector<double>& q0, std::vector<double>& q,
                           std::vector<std::int32_t>& source, const std::vector<std::int32_t>* seeds,
                           const std::vector<PointSource>& points) const {
  const std::size_t n = corners_.size();
  auto source_point = [&](std::int32_t s) {
    return static_cast<std::size_t>(s) < n ? corners_[static_cast<std::size_t>(s)]
                                           : points[static_cast<std::size_t>(s) - n].p;
  };
  auto source_q = [&](std::int32_t s) {
    return static_cast<std::size_t>(s) < n ? q0[static_cast<std::size_t>(s)]
                                           : points[static_cast<std::size_t>(s) - n].q;
  };
  // Min-heap on (value, corner); stale entries (value above the corner's current q) are skipped.
  std::vector<Entry> start;
  if (seeds) {
    // Each seed once (a corner of several fresh leaves comes several times): a repeated entry would
    // be popped again at its own value and relax its neighbours to the values they already hold.
    std::vector<std::uint8_t> seeded(n, 0);
    for (const std::int32_t i : *seeds) seeded[static_cast<std::size_t>(i)] = 1;
    for (std::size_t i = 0; i < n; ++i)
      if (seeded[i]) start.push_back({q[i], static_cast<std::int32_t>(i)});
  } else {
    start.resize(n);
    for (std::size_t i = 0; i < n; ++i) start[i] = {q[i], static_cast<std::int32_t>(i)};
  }
  // The start entries are sorted once and read in order; only the values lowered since go through the
  // heap, and each step takes the smaller of the two fronts. (value, corner) pairs are totally ordered
  // and an entry is pushed only below its corner's value, so the steps are those of one heap holding
  // every entry (any exact min-queue gives the same sequence): the same q and sources, bit for bit,
  // without sifting the n start entries through a heap of n.
  detail::sort_gradation_entries(start);  // given in corner order
  std::size_t next = 0;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
  while (next < start.size() || !heap.empty()) {
    Entry top;
    if (heap.empty() || (next < start.size() && start[next] < heap.top())) {
      top = start[next++];
    } else {
      top = heap.top();
      heap.pop();
    }
    const auto [value, i] = top;
    if (value > q[static_cast<std::size_t>(i)]) continue;
    const std::int32_t s = source[static_cast<std::size_t>(i)];
    const Vec2 sp = source_point(s);
    const double sq = source_q(s);
    for (std::int32_t e = leaf_start_[static_cast<std::size_t>(i)]; e < leaf_start_[static_cast<std::size_t>(i) + 1];
         ++e) {
      const auto at = static_cast<std::size_t>(leaf_of_[static_cast<std::size_t>(e)]);
      const std::size_t first = at & ~std::size_t{3};
      for (std::size_t k = first; k < first + 4; ++k) {
        if (k == at) continue;
        const auto j = static_cast<std::size_t>(leaf_corner_[k]);
        const double v = sq + g * dist(corners_[j], sp);
        if (v < q[j]) {
          q[j] = v;
          source[j] = s;
          heap.push({v, static_cast<std::int32_t>(j)});
        }
      }
    }
  }
}

}  // namespace pdmesh
