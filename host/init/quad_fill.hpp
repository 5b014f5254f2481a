// Filling one initialization-tree leaf with interior nodes (thesis ch. 4, "Structured Quad
// Distribution" and "Random Quad Distribution"; ch. 7's hexagonal packing), plus the keep rule and
// the seeded unit RNG.
#pragma once
#include <cstdint>
#include <random>
#include <unordered_set>
#include <vector>

#include "geometry/geometry_tree.hpp"
#include "init/init_tree.hpp"
#include "init/initial_distribution.hpp"
#include "nodes/node_set.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

// Uniform doubles in [0, 1) from the top 53 bits of mt19937_64: the same on every platform,
// unlike std::uniform_real_distribution.
class UnitRandom {
 public:
  explicit UnitRandom(std::uint64_t seed) : engine_(seed) {}
  double next() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

 private:
  std::mt19937_64 engine_;
};

// Nodes a structured fill puts in a quad with the given area ratio: 1 below 2.05, else the nearest
// of {4, 5, 9} (thresholds 4.5 and 7).
int structured_count(double ratio);
// Nodes a random fill puts in a quad: clamp(round(ratio), 1, 9).
int random_count(double ratio);

// The keep rule for an interior candidate p: inside the domain and at least
// kInitBoundaryClearance * q(p) from the closest boundary point. `known_inside` skips the
// point-in-domain test for quads that no segment touches; a `distance_lower_bound` that already
// clears the rule skips the closest-point query. q is set to q(p).
bool keep_interior_candidate(const GeometryTree& tree, const SpacingField& spacing, Vec2 p, bool known_inside,
                             double& q, double distance_lower_bound = -1.0);

// Lattice points the hexagonal fill has placed, by (level, row, column): shared by every leaf of
// one fill, so that a point on the edge between two quads is placed once.
using LatticePoints = std::unordered_set<std::uint64_t>;

// What one fill carries from leaf to leaf: the lattice points placed so far, and for the hybrid fill
// with a density (InitOptions::density; 0 = the patterns' counts) the nodes its pattern quads fell
// short of their targets by so far (negative: over).
struct FillState {
  LatticePoints lattice;
  double density = 0.0;
  DensityWhere density_where = DensityWhere::Inside;
  int lattice_levels = 0;                // InitOptions::lattice_levels
  double hybrid_spread = kHybridSpread;  // InitOptions::hybrid_spread
  double shortfall = 0.0;
};

// Fills one kept leaf, splitting it into four while its area ratio exceeds kInitSplitRatio.
// Kept nodes are appended to `nodes` as Interior nodes. Returns how many were added. The hexagonal
// and hybrid fills need `state` (the same for every leaf of the fill, in the fill's order).
std::size_t fill_leaf(const GeometryTree& tree, const SpacingField& spacing, const InitLeaf& leaf, InitMethod method,
                      UnitRandom& rng, NodeSet& nodes, FillState* state = nullptr);

}  // namespace pdmesh
