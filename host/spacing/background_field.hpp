// A background spacing field: an adaptive quadtree sampled from an exact SpacingField, with bilinear
// interpolation in each leaf and a per-leaf domain tag, in flat arrays that an OpenCL kernel can walk.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/memory_budget.hpp"
#include "core/vec2.hpp"
#include "geometry/geometry_tree.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

// Domain tags of a leaf: what a point in it is, as far as the leaf alone can tell.
enum DomainTag : std::int32_t {
  kTagInside = 0,    // no boundary segment touches the closed leaf box and its centre is inside
  kTagBoundary = 1,  // some boundary segment touches the leaf: ask the exact inside test
  kTagOutside = 2,   // no boundary segment touches the leaf and its centre is outside
};

// The flat, device-friendly form (kernels/spacing_field.cl walks exactly this).
// A G x G top grid of square root cells of side root_size starts at (origin_x, origin_y); each root
// is the root of a quadtree whose nodes are numbered in node_child. Lookup of p:
//   t = (p.x - origin_x) * inv_root_size, gx = clamp(floor(t), 0, G-1), u = clamp(t - gx, 0, 1)
//   (same for y), node = root_node[gy * G + gx]; while node_child[node] >= 0:
//   cx = u >= 0.5, cy = v >= 0.5, u = 2u - cx, v = 2v - cy, node = node_child[node] + cx + 2 cy.
// Every step is exact in floating point, so host and device choose the same leaf and the same (u, v).
struct BackgroundFieldData {
  double origin_x = 0.0;
  double origin_y = 0.0;
  double root_size = 1.0;               // side of one top-level cell
  double inv_root_size = 1.0;           // 1 / root_size, as multiplied by the lookup
  std::int32_t grid = 1;                // G
  std::int32_t max_depth = 0;           // deepest leaf below its root
  std::vector<std::int32_t> root_node;  // G * G, row-major (y outer): node index of each root cell
  // Per node: >= 0: index of the first of its 4 consecutive children, ordered (x lo, y lo),
  // (x hi, y lo), (x lo, y hi), (x hi, y hi); < 0: a leaf, leaf index -1 - value.
  std::vector<std::int32_t> node_child;
  std::vector<std::int32_t> leaf_corner;  // 4 per leaf, same order as children: indices into corner_q
  std::vector<std::int32_t> leaf_tag;     // per leaf: a DomainTag
  // 4 per leaf: top-grid cell (gy * G + gx), level L below the root, integer cell coordinates
  // (ix, iy) in [0, 2^L) of the leaf within its root cell. Lets a lookup test a guessed leaf without
  // descending (kernels/spacing_field.cl, bg_locate_cached).
  std::vector<std::int32_t> leaf_cell;
  std::vector<double> corner_q;  // exact q at every distinct leaf corner (shared corners once)

  std::size_t bytes() const;
  std::size_t leaves() const { return leaf_tag.size(); }
};

struct BackgroundOptions {
  // Refine while the bilinear value at a test point differs from the exact field by more than this
  // (relative to the exact value). Test points: centre, edge midpoints and the 4 quarter points,
  // held to tolerance / 2 since the worst point of a cell is usually between them.
  // Default 1e-2: on 30P30N it builds in ~4 s into 3 MB (1e-3: 27 s, 17 MB) with a 99th-percentile
  // error of 0.75% inside the domain, far below eq. 3.6's own jumps (docs/spacing.md).
  double tolerance = 1e-2;
  // Refine while the cell side exceeds size_factor * (smallest corner q): the field is then resolved on
  // the node scale. Also sets the top grid: root side about size_factor * (largest sampled q).
  double size_factor = 2.0;
  // Never refine for accuracy below this fraction of the smallest corner q. Eq. 3.6 jumps across the
  // bisectors where a curve's closest segment changes; a cell straddling one would otherwise refine
  // to max_depth. Such cells keep an error up to the jump (see docs/spacing.md).
  double min_side_fraction = 1.0 / 4.0;
  // The same for leaves a boundary segment touches: eq. 3.6 has a kink on the boundary itself (the
  // distance is unsigned), so the bilinear error there falls only linearly with the side.
  double boundary_min_side_fraction = 1.0 / 16.0;
  // Inside the domain, a cell between this (when finer) and min_side_fraction of its smallest corner q
  // is tested (and split by the tolerance) only where its corner values differ by more than the factor
  // 1 + jump_tolerance: it may straddle a large jump (the edge of a refinement region), which is then
  // narrowed to this fraction, while eq. 3.6's small jumps stop at min_side_fraction without test
  // samples. Slopes up to the gradation limit's 0.2 change q by less than 15 % across such a cell's
  // diagonal. No band when min_side_fraction is not above this (the default).
  double jump_min_side_fraction = 1.0 / 4.0;
  double jump_tolerance = 0.25;
  int max_depth = 16;  // levels below a root cell, at most kMaxDepthLimit
  int max_grid = 512;  // top grid at most max_grid x max_grid, at most kMaxGridLimit
  static constexpr int kMaxDepthLimit = 20;
  static constexpr int kMaxGridLimit = 512;
  // The budgets, checked before each level's cells are made (docs/robustness.md, "Memory"): the
  // tree's estimated bytes against `memory`, and, while the tree of the exact field is built, the
  // nodes that the inside cells made so far ask for against max_nodes (0: no limit).
  double max_nodes = 0.0;
  MemoryLimit memory;
  // At most this many threads in the builder's and the limited field's loops (0: as many as
  // parallel_for takes). The result is the same for every count; tests compare 1 with the default.
  std::size_t threads = 0;
  std::size_t loop_threads() const { return threads > 0 ? threads : kParallelForThreads; }
  static constexpr std::size_t kParallelForThreads = 8;  // parallel_for's default max_threads
};

struct BackgroundStats {
  std::size_t nodes = 0;
  std::size_t leaves = 0;
  std::size_t corners = 0;
  std::size_t exact_evaluations = 0;  // distinct points where the exact field was evaluated
  std::size_t exact_batches = 0;      // SpacingField::at_many calls that evaluated them
  std::size_t bytes = 0;
  int grid = 0;
  int max_depth = 0;
};

// Throws InputError naming the first invalid option.
void check_background_options(const BackgroundOptions& options);

// Locates p: the leaf index and the local coordinates (u, v) in [0, 1]^2 within it.
int background_locate(const BackgroundFieldData& data, Vec2 p, double& u, double& v);
// background_locate, first trying the leaf `guess` (kernels/spacing_field.cl's bg_locate_cached): when p
// lies in that leaf's cell its (u, v) are computed directly, the same values as the descent's; otherwise
// the descent, and guess becomes the leaf found.
int background_locate_guessed(const BackgroundFieldData& data, Vec2 p, int& guess, double& u, double& v);
// The box of the leaf holding p (for tests and drawing; the same descent as background_locate).
Box background_leaf_box(const BackgroundFieldData& data, Vec2 p);
// Bilinear value in a leaf at (u, v), the same expression as the kernel's.
double background_interpolate(const BackgroundFieldData& data, int leaf, double u, double v);

// The background field as a SpacingField: build once (cost: a few exact evaluations per leaf), then
// at() is a top-grid index, a descent of at most max_depth levels and a bilinear interpolation.
// Keeps no reference to the exact field or the tree. at() and tag_at() are thread-safe.
class BackgroundSpacing final : public SpacingField {
 public:
  // Throws InputError on invalid options; the exact field's errors pass through.
  // The exact field is evaluated through at_many only, in a few batches per tree level.
  BackgroundSpacing(const SpacingField& exact, const GeometryTree& tree, const BackgroundOptions& options = {});
  // Wraps arrays built elsewhere (the spacing pipeline); stats' counts are recomputed from them.
  BackgroundSpacing(BackgroundFieldData data, const BackgroundStats& stats);
  double at(Vec2 p) const override;
  void at_many(const std::vector<Vec2>& p, std::vector<double>& q) const override;
  // A guess is the leaf that held the point last time.
  void at_many_guessed(const std::vector<Vec2>& p, std::vector<double>& q, std::vector<int>& guesses) const override;
  // The DomainTag of the leaf holding p. Points outside the top grid are clamped onto it; the grid
  // has a margin around the geometry, so they land in a boundary or outside leaf.
  int tag_at(Vec2 p) const;
  const BackgroundFieldData& data() const { return data_; }
  const BackgroundStats& stats() const { return stats_; }

 private:
  void fill_stats();
  BackgroundFieldData data_;
  BackgroundStats stats_;
};

}  // namespace pdmesh
