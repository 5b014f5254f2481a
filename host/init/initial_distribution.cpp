// The initial distribution driver: boundary nodes, tree fill of the interior, overloading to a
// requested total, and the hexagonal-packing node-count estimate over the initialization tree.
#include "init/initial_distribution.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "core/interrupt.hpp"
#include "core/errors.hpp"
#include "fmt/format.h"
#include "init/init_tree.hpp"
#include "init/quad_fill.hpp"

namespace pdmesh {

namespace {

// Nodes per unit area in hexagonal packing at spacing q: one node per equilateral-triangle pair.
double hex_density(double q) { return 2.0 / (std::sqrt(3.0) * q * q); }

// A quad is sub-divided for the estimate while it would hold more than this many nodes, so that
// each of its 4x4 samples stands for a handful of nodes at most.
constexpr double kEstimateNodesPerQuad = 64.0;
constexpr int kEstimateSamples = 4;
constexpr int kEstimateMaxDepth = 30;

// Extra levels a leaf that segments touch is split for the estimate, so that its samples resolve
// the boundary within 1/32 of the leaf side instead of 1/4.
constexpr int kEstimateCutDepth = 3;

// Integral of the hexagonal density over the inside part of quad b. Leaf-sized quads take 4x4
// spacing samples (q may vary over a large leaf); the sub-quads of a cut leaf, which are at most
// a fraction of the local spacing wide, take q once at their centre and 4x4 inside samples.
// A quad whose centre sits in a coarse region can still hold a narrow band of fine spacing (the
// shock field of eq. 7.2): it is split while it would hold many nodes at the smallest spacing of its
// centre and 4x4 samples, or while that spacing varies by more than kEstimateSpread over it and
// it would hold more than a few nodes.
constexpr double kEstimateSpread = 1.5;
constexpr double kEstimateSpreadNodes = 4.0;

using EstimateSamples = std::array<double, kEstimateSamples * kEstimateSamples>;

// The k-th (row-major) of the 4x4 sample points of b.
Vec2 estimate_sample(const Box& b, int k) {
  const int i = k % kEstimateSamples, j = k / kEstimateSamples;
  return {b.lo.x + (i + 0.5) / kEstimateSamples * b.width(), b.lo.y + (j + 0.5) / kEstimateSamples * b.height()};
}

// Also returns the 4x4 samples in `samples`, which an unsplit quad reuses (the same points).
bool estimate_needs_split(const SpacingField& spacing, const Box& b, double q_mid, EstimateSamples& samples) {
  double q_min = q_mid, q_max = q_mid;
  for (int k = 0; k < kEstimateSamples * kEstimateSamples; ++k) {
    const double q = spacing.at(estimate_sample(b, k));
    samples[k] = q;
    if (!(q > 0.0) || !std::isfinite(q)) continue;
    q_min = std::fmin(q_min, q);
    q_max = std::fmax(q_max, q);
  }
  const double nodes = b.width() * b.height() * hex_density(q_min);
  return nodes > kEstimateNodesPerQuad || (q_max > kEstimateSpread * q_min && nodes > kEstimateSpreadNodes);
}

double estimate_quad(const GeometryTree& tree, const SpacingField& spacing, const Box& b,
                     const std::vector<int>& segments, bool known_inside, int depth) {
  const double q_mid = spacing.at(b.centre());
  const double area = b.width() * b.height();
  EstimateSamples samples;
  const bool sampled = q_mid > 0.0;
  const bool crowded = sampled && estimate_needs_split(spacing, b, q_mid, samples);
  const bool cut = !known_inside && !segments.empty() && depth < kEstimateCutDepth;
  if ((crowded || cut) && depth < kEstimateMaxDepth) {
    const auto& segs = tree.geometry().segments;
    const Vec2 c = b.centre();
    const Box children[4] = {Box{b.lo, c}, Box{{c.x, b.lo.y}, {b.hi.x, c.y}}, Box{{b.lo.x, c.y}, {c.x, b.hi.y}},
                             Box{c, b.hi}};
    double sum = 0.0;
    for (const Box& child : children) {
      if (known_inside) {
        sum += estimate_quad(tree, spacing, child, segments, true, depth + 1);
        continue;
      }
      std::vector<int> touching;
      for (int s : segments)
        if (segment_touches_box(segs[s].a, segs[s].b, child)) touching.push_back(s);
      // No segment touches the child: it lies wholly on one side, which its centre tells.
      if (touching.empty()) {
        if (!tree.inside(child.centre())) continue;
        if (!crowded) {
          const double q = spacing.at(child.centre());
          if (q > 0.0 && std::isfinite(q)) sum += child.width() * child.height() * hex_density(q);
          continue;
        }
      }
      sum += estimate_quad(tree, spacing, child, touching, touching.empty(), depth + 1);
    }
    return sum;
  }
  const double cell = area / (kEstimateSamples * kEstimateSamples);
  const bool sub_quad = depth > 0 && !crowded;
  double sum = 0.0;
  for (int k = 0; k < kEstimateSamples * kEstimateSamples; ++k) {
    const Vec2 p = estimate_sample(b, k);
    if (!known_inside && !tree.inside(p)) continue;
    const double q = sub_quad ? q_mid : sampled ? samples[k] : spacing.at(p);
    if (q > 0.0 && std::isfinite(q)) sum += cell * hex_density(q);
  }
  return sum;
}

double estimate_over(const GeometryTree& tree, const SpacingField& spacing, const InitTree& init) {
  double sum = 0.0;
  InterruptPoll poll(1024);
  for (int k : init.kept()) {
    poll.tick();
    const InitLeaf& leaf = init.leaves()[k];
    sum += estimate_quad(tree, spacing, leaf.box, leaf.segments, leaf.segments.empty(), 0);
  }
  return sum;
}

// Adds `count` random interior points: a kept leaf drawn with probability proportional to its
// area, a uniform point in it, kept by the same rule as the tree fill (rejection sampling).
void overload(const GeometryTree& tree, const SpacingField& spacing, const InitTree& init, std::size_t count,
              UnitRandom& rng, NodeSet& nodes) {
  const auto& kept = init.kept();
  std::vector<double> cumulative;
  cumulative.reserve(kept.size());
  double total_area = 0.0;
  for (int k : kept) {
    const Box& b = init.leaves()[k].box;
    total_area += b.width() * b.height();
    cumulative.push_back(total_area);
  }
  // Generous, but finite: a domain where nearly every point is within the clearance of the
  // boundary must end in an error, not in an endless loop.
  const std::size_t max_attempts = 1000 * count + 1000000;
  std::size_t added = 0;
  for (std::size_t attempt = 0; added < count; ++attempt) {
    if (attempt >= max_attempts || kept.empty())
      throw LimitError(
          fmt::format("initial distribution: could only place {} of {} overloading nodes in {} attempts "
                      "(the domain leaves too little room away from the boundary)",
                      added, count, attempt));
    const double pick = rng.next() * total_area;
    const std::size_t idx = std::min<std::size_t>(
        static_cast<std::size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin()),
        kept.size() - 1);
    const InitLeaf& leaf = init.leaves()[kept[idx]];
    const double u = rng.next();
    const double v = rng.next();
    const Vec2 p{leaf.box.lo.x + u * leaf.box.width(), leaf.box.lo.y + v * leaf.box.height()};
    double q = 0.0;
    if (keep_interior_candidate(tree, spacing, p, leaf.segments.empty(), q)) {
      nodes.add(p, q, NodeKind::Interior, -1);
      ++added;
    }
  }
}

}  // namespace

const char* to_string(InitMethod method) {
  switch (method) {
    case InitMethod::Random:
      return "random";
    case InitMethod::Hexagonal:
      return "hexagonal";
    case InitMethod::Hybrid:
      return "hybrid";
    default:
      return "structured";
  }
}

InitialDistribution make_initial_distribution(const GeometryTree& tree, const SpacingField& spacing,
                                              const InitOptions& options) {
  InitialDistribution out;
  out.nodes = options.boundary != nullptr ? *options.boundary : make_boundary_nodes(tree.geometry(), spacing);
  InitTreeOptions tree_options;
  tree_options.segment_resolution = options.segment_resolution;
  const InitTree init(tree, spacing, tree_options);
  out.estimate = options.with_estimate ? estimate_over(tree, spacing, init) : std::nan("");

  UnitRandom rng(options.seed);
  FillState fill;
  fill.density = options.method == InitMethod::Hybrid ? options.density : 0.0;
  fill.density_where = options.density_where;
  fill.lattice_levels = options.lattice_levels;
  fill.hybrid_spread = options.hybrid_spread;
  InterruptPoll poll(1024);
  for (int k : init.kept()) {
    poll.tick();
    const InitLeaf& leaf = init.leaves()[k];
    out.tree_quads.push_back(leaf.box);
    out.tree_nodes += fill_leaf(tree, spacing, leaf, options.method, rng, out.nodes, &fill);
  }
  if (options.total && *options.total > out.nodes.size()) {
    out.overload_nodes = *options.total - out.nodes.size();
    overload(tree, spacing, init, out.overload_nodes, rng, out.nodes);
  }
  return out;
}

double estimate_node_count(const GeometryTree& tree, const SpacingField& spacing,
                           const std::vector<double>* segment_resolution) {
  InitTreeOptions tree_options;
  tree_options.segment_resolution = segment_resolution;
  const InitTree init(tree, spacing, tree_options);
  return estimate_over(tree, spacing, init);
}

}  // namespace pdmesh
