// The initial node distribution (thesis ch. 4, "Initial Node Distribution"): boundary nodes from
// the geometry, then interior nodes filled quad by quad over a 2:1-balanced initialization tree.
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "geometry/geometry_tree.hpp"
#include "init/boundary_placement.hpp"
// The leaf-pass estimate over a BackgroundSpacing: whoever sees the per-sample overload below sees it
// too, so a BackgroundSpacing argument never converts silently to SpacingField& (which would pick the
// per-sample estimate: 11605 against the leaf pass's 11634 on 30P30N).
#include "init/node_estimate.hpp"
#include "nodes/node_set.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

// How a leaf of the initialization tree is filled (docs/initialization.md): the thesis' structured
// patterns (1, 4, 5 or 9 nodes) and random points, rows of an equilateral lattice (thesis ch. 7), and
// the hybrid: the lattice away from the boundary where q is nearly flat, the patterns elsewhere.
enum class InitMethod { Structured, Random, Hexagonal, Hybrid };

// Where the hybrid fill's density (InitOptions::density) applies: every quad wholly inside the domain,
// or only those where q is flat around the quad (within kHybridSpread, the lattice test's default spread,
// without its clearance).
enum class DensityWhere { Inside, Flat };

// "structured", "random", "hexagonal" or "hybrid".
const char* to_string(InitMethod method);

// A quad is split into four while its area / (pi q_mid^2 / 4) exceeds this (thesis: 9.5).
inline constexpr double kInitSplitRatio = 9.5;
// An interior candidate closer than this times q(candidate) to the boundary is dropped.
inline constexpr double kInitBoundaryClearance = 0.5;
// The most levels per octave InitOptions::lattice_levels may ask (finer levels than 1.1 % apart hold no
// lattice across a graded field anyway).
inline constexpr int kMaxLatticeLevels = 64;
// The hybrid fill's spread of q around a quad (a factor 1 + this over its centre and its eight same-sized
// neighbours' centres) within which q counts as flat: for the lattice test unless InitOptions::hybrid_spread
// says otherwise, and for DensityWhere::Flat.
inline constexpr double kHybridSpread = 0.05;

struct InitOptions {
  InitMethod method = InitMethod::Structured;
  std::uint64_t seed = 1;
  // If set and larger than what the tree fill produced, the remainder is added as random
  // interior points (the thesis' "overloading").
  std::optional<std::size_t> total;
  // The hybrid fill only: 0 = its quads take the structured patterns' counts (its lattice quads as
  // dense as the pattern each replaces); d > 0 = every quad wholly inside starts at d times the
  // hexagonal-packing estimate of its part beyond the keep rule's clearance (docs/initialization.md,
  // "The hybrid fill's density").
  double density = 0.0;
  // Which quads the density applies to. Flat: where q spans at most a factor 1.05 over the quad's centre
  // and its eight same-sized neighbours' centres; the other quads keep the patterns, which on a graded
  // field already average about 1.21 times the estimate (their area ratios spread over the bands).
  DensityWhere density_where = DensityWhere::Inside;
  // With a density, the levels per octave of the lattice quads' levels of q / sqrt(d), which then apply
  // with either density_where; 0 = 8 with Inside, and with Flat the lattice quads keep the patterns'
  // density (docs/initialization.md, "The lattice's levels").
  int lattice_levels = 0;
  // The hybrid fill's lattice test: a quad clear of the boundary takes the lattice where q at its centre and
  // at its eight same-sized neighbours' centres spans at most a factor 1 + hybrid_spread
  // (docs/initialization.md, "The lattice test's spread").
  double hybrid_spread = kHybridSpread;
  // Compute InitialDistribution::estimate (it costs more than the fill itself: 4x4 spacing samples
  // per leaf and more near the boundary). The mesh command already has it from its limit check.
  bool with_estimate = true;
  // The boundary nodes to start from (boundary.nodes = "spacing", or the input points on a smooth
  // curve's dense polyline); null: make_boundary_nodes(tree.geometry()), the thesis' rule.
  const NodeSet* boundary = nullptr;
  // Per segment of tree.geometry(): the boundary resolution the initialization tree refines to
  // (InitTreeOptions::segment_resolution); null: the segment lengths.
  const std::vector<double>* segment_resolution = nullptr;
};

struct InitialDistribution {
  NodeSet nodes;
  std::vector<Box> tree_quads;     // leaves of the initialization tree that are not fully outside
  double estimate = 0.0;           // integral of 2 / (sqrt(3) q^2) dA over the domain (hexagonal packing);
                                   // NaN when InitOptions::with_estimate was false
  std::size_t tree_nodes = 0;      // interior nodes from the tree fill
  std::size_t overload_nodes = 0;  // interior nodes added to reach `total`
};

// Boundary nodes only: critical points as Fixed nodes, the other geometry points as Boundary nodes,
// with NodeSet::curve_nodes filled. q is set from `spacing`.
NodeSet make_boundary_nodes(const Geometry& geometry, const SpacingField& spacing);

InitialDistribution make_initial_distribution(const GeometryTree& tree, const SpacingField& spacing,
                                              const InitOptions& options);

// The hexagonal-packing node-count estimate alone, by sampling q (any field; for a BackgroundSpacing the
// overload in init/node_estimate.hpp integrates its leaves exactly and is the one pdmesh mesh uses).
double estimate_node_count(const GeometryTree& tree, const SpacingField& spacing,
                           const std::vector<double>* segment_resolution = nullptr);

}  // namespace pdmesh
