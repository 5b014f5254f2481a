// The gradation sweep against a plain reference: Dijkstra over explicit neighbour lists (every pair of
// a leaf's corners, repeats kept) with std::priority_queue, on quadtree-like leaf sets with hanging
// corners and many equal values. GradationGraph must give the same q and sources bit for bit.
#include <catch2/catch.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <queue>
#include <random>
#include <utility>
#include <vector>

#include "spacing/gradation.hpp"

using namespace pdmesh;

namespace {

// Leaves of a grid of side n, some split once or twice; corners numbered as first met.
struct Leaves {
  std::vector<Vec2> pos;
  std::vector<std::int32_t> leaf_corner;
};

Leaves random_leaves(std::mt19937_64& rng, int n) {
  Leaves out;
  std::map<std::pair<int, int>, std::int32_t> ids;  // lattice point (quarter units) -> corner
  auto corner = [&](int x, int y) {
    const auto [it, fresh] = ids.try_emplace({x, y}, static_cast<std::int32_t>(out.pos.size()));
    if (fresh) out.pos.push_back({x / 4.0, y / 4.0});
    return it->second;
  };
  std::function<void(int, int, int)> leaf = [&](int x, int y, int side) {
    if (side > 1 && rng() % 3 == 0) {
      const int h = side / 2;
      for (int k = 0; k < 4; ++k) leaf(x + (k & 1 ? h : 0), y + (k & 2 ? h : 0), h);
      return;
    }
    for (int k = 0; k < 4; ++k) out.leaf_corner.push_back(corner(x + (k & 1 ? side : 0), y + (k & 2 ? side : 0)));
  };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) leaf(4 * x, 4 * y, 4);
  return out;
}

// The reference sweep: from every corner (seeds null) or from the seeds only.
void reference_sweep(const Leaves& l, double g, const std::vector<double>& q0, std::vector<double>& q,
                     std::vector<std::int32_t>& source, const std::vector<std::int32_t>* seeds) {
  const std::size_t n = l.pos.size();
  std::vector<std::vector<std::int32_t>> neighbours(n);
  for (std::size_t k = 0; k < l.leaf_corner.size(); k += 4)
    for (std::size_t a = 0; a < 4; ++a)
      for (std::size_t b = 0; b < 4; ++b)
        if (a != b) neighbours[static_cast<std::size_t>(l.leaf_corner[k + a])].push_back(l.leaf_corner[k + b]);
  using Entry = std::pair<double, std::int32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
  std::vector<char> seeded(n, seeds ? 0 : 1);
  if (seeds)
    for (const std::int32_t s : *seeds) seeded[static_cast<std::size_t>(s)] = 1;
  for (std::size_t i = 0; i < n; ++i)
    if (seeded[i]) heap.push({q[i], static_cast<std::int32_t>(i)});
  while (!heap.empty()) {
    const auto [value, i] = heap.top();
    heap.pop();
    if (value > q[static_cast<std::size_t>(i)]) continue;
    const std::int32_t s = source[static_cast<std::size_t>(i)];
    for (const std::int32_t j : neighbours[static_cast<std::size_t>(i)]) {
      const auto ju = static_cast<std::size_t>(j);
      const double v = q0[static_cast<std::size_t>(s)] + g * dist(l.pos[ju], l.pos[static_cast<std::size_t>(s)]);
      if (v < q[ju]) {
        q[ju] = v;
        source[ju] = s;
        heap.push({v, j});
      }
    }
  }
}

// The graph's limit of q0 and the reference sweep's, with their sources.
struct LimitedBoth {
  std::vector<double> q, q_ref;
  std::vector<std::int32_t> source, source_ref;
};

LimitedBoth limit_both(const GradationGraph& graph, const Leaves& l, double g, const std::vector<double>& q0) {
  LimitedBoth r;
  graph.limit(g, q0, r.q, r.source);
  r.q_ref = q0;
  r.source_ref.resize(q0.size());
  for (std::size_t i = 0; i < q0.size(); ++i) r.source_ref[i] = static_cast<std::int32_t>(i);
  reference_sweep(l, g, q0, r.q_ref, r.source_ref, nullptr);
  return r;
}

}  // namespace

TEST_CASE("gradation: the sweep equals a binary-heap Dijkstra over explicit neighbour lists bit for bit", "[spacing]") {
  std::mt19937_64 rng(11);
  for (int round = 0; round < 12; ++round) {
    const Leaves l = random_leaves(rng, 4 + round);
    const std::size_t n = l.pos.size();
    const double g = round % 3 == 0 ? 0.25 : round % 3 == 1 ? 0.1 : 1.0;
    // Values on a coarse ladder (many ties, so the corner order decides) or continuous.
    std::vector<double> q0(n);
    for (double& v : q0)
      v = round % 2 == 0 ? 0.05 * static_cast<double>(1 + rng() % 8)
                         : 0.01 + std::ldexp(static_cast<double>(rng() >> 11), -53);
    INFO("round " << round << ", " << n << " corners, g " << g);

    const GradationGraph graph(l.pos, l.leaf_corner);
    LimitedBoth limited = limit_both(graph, l, g, q0);
    auto& [q, q_ref, source, source_ref] = limited;
    REQUIRE(q == q_ref);
    REQUIRE(source == source_ref);

    // Lower a few corners afterwards and continue from them (the refinement rounds' relimit).
    std::vector<double> q0_new = q0;
    std::vector<std::int32_t> seeds;
    for (int k = 0; k < 3; ++k) {
      const auto c = static_cast<std::size_t>(rng() % n);
      q0_new[c] = 0.5 * q[c];
      q[c] = q_ref[c] = q0_new[c];
      source[c] = source_ref[c] = static_cast<std::int32_t>(c);
      seeds.push_back(static_cast<std::int32_t>(c));
    }
    graph.relimit(g, q0_new, q, source, seeds);
    reference_sweep(l, g, q0_new, q_ref, source_ref, &seeds);
    REQUIRE(q == q_ref);
    REQUIRE(source == source_ref);
  }
}

TEST_CASE("gradation: a graph whose leaf lists are sorted in two parts sweeps as the reference does", "[spacing]") {
  // Enough leaves that the graph's corner -> leaf lists are built in two halves of the entries at
  // once (GradationGraph::kEntriesPerPart); the sweep must still equal the reference bit for bit.
  std::mt19937_64 rng(23);
  const Leaves l = random_leaves(rng, 160);
  REQUIRE(l.leaf_corner.size() >= 2 * GradationGraph::kEntriesPerPart);
  const std::size_t n = l.pos.size();
  const double g = 0.2;
  std::vector<double> q0(n);
  for (double& v : q0) v = 0.01 + std::ldexp(static_cast<double>(rng() >> 11), -53);
  const GradationGraph graph(l.pos, l.leaf_corner);
  const LimitedBoth limited = limit_both(graph, l, g, q0);
  REQUIRE(limited.q == limited.q_ref);
  REQUIRE(limited.source == limited.source_ref);
}
