// The background field's builder: refines the adaptive quadtree level by level, evaluating every exact
// sample a level needs in one SpacingField::at_many call, then writes the flat BackgroundFieldData.
// Internal to host/spacing (BackgroundSpacing and the spacing pipeline use it).
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "core/flat_key_map.hpp"
#include "spacing/background_field.hpp"

namespace pdmesh {

class BackgroundBuilder {
 public:
  // A cell of the tree. Cells 0 .. G*G-1 are the root cells (row-major, y outer); the children of a
  // split cell are four consecutive cells (x lo y lo, x hi y lo, x lo y hi, x hi y hi).
  struct Cell {
    std::uint32_t x = 0, y = 0;     // lattice coordinates of the low corner
    std::int32_t first_child = -1;  // -1: a leaf
    std::int32_t segments = -1;     // index into segment_lists_ (boundary leaves), or -1
    std::int32_t parent = -1;       // -1 for a root cell
    // Sample ids of the corners (x lo y lo, x hi y lo, x lo y hi, x hi y hi), set when the cell's level
    // is sampled: callers index their own per-sample arrays by them instead of hashing lattice keys.
    std::int32_t corner[4] = {-1, -1, -1, -1};
    std::int8_t level = 0;           // 0 = root cell
    std::int8_t tag = kTagBoundary;  // a DomainTag
  };
  enum class Decision { Leaf, Split, Test };

  // Keeps references to all three; they must outlive the builder.
  BackgroundBuilder(const SpacingField& exact, const GeometryTree& tree, const BackgroundOptions& options);

  // Chooses the top grid and refines by the exact field: the tree BackgroundSpacing always had.
  void build();

  // Refines the given cells (leaves) further, level by level, by a caller's rule: `decide` sees a cell
  // and its four corner values and says Leaf, Split or Test; for Test, `test` then sees the cell, its
  // corners and the exact field at its first `count` test points (5, then all 9 unless the 5 split
  // it) and says whether to split. Per level, the exact samples of all corners are taken first (one
  // batch), then `corner_value` gives each cell's corner values (cell, lattice x, y, the corner's
  // sample id). `sampled` (if set) sees the keys of every batch (corners, then test points) and their
  // sample ids as soon as the samples are in, so a caller can compute its own values at those points in
  // bulk. `test` also sees the sample ids of the test points. Returns the number of cells split.
  // `test` is called from several threads at once: it may only read (decide and corner_value are
  // called on the calling thread, in the cells' order).
  // The corner values are spacings: before a level is split, the nodes that the inside cells of this
  // call ask for are held to max_nodes (check_budget), so a caller that lowers q (the limited field)
  // is refused on a coarse level, before the fine levels are made. Cells not given to the call are not
  // counted, so the count stays below the whole field's.
  using DecideFn = std::function<Decision(const Cell&, const double q[4])>;
  using TestFn =
      std::function<bool(const Cell&, const double q[4], const double exact[9], const std::int32_t ids[9], int count)>;
  using CornerFn = std::function<double(const Cell&, std::uint32_t, std::uint32_t, std::int32_t)>;
  using SampledFn = std::function<void(const std::vector<std::uint64_t>& keys, const std::vector<std::int32_t>& ids)>;
  std::size_t refine(std::vector<int> cells, const DecideFn& decide, const TestFn& test, const CornerFn& corner_value,
                     const SampledFn& sampled = {});

  // The flat arrays, nodes and leaves numbered depth first. corner_q holds `corner_value` at each
  // distinct leaf corner, given its sample id (the exact sample when empty).
  using ValueFn = std::function<double(std::int32_t)>;
  BackgroundFieldData emit(const ValueFn& corner_value = {}) const;
  // The leaf holding p (points off the grid are clamped onto it), by the lookup's descent.
  int locate(Vec2 p) const;

  // The rules of BackgroundSpacing's own refinement (docs/spacing.md), for a caller to reuse.
  Decision default_decide(const Cell& c, const double q[4]) const;
  bool default_test(const double q[4], const double exact[9], int count) const;

  // Lattice and geometry of the tree.
  const std::vector<Cell>& cells() const { return cells_; }
  std::vector<int> leaves() const;
  // The boundary segments that touch a leaf (empty for inside and outside leaves).
  const std::vector<int>& segments(const Cell& c) const;
  int grid() const { return grid_; }
  const Geometry& geometry() const { return tree_.geometry(); }
  const BackgroundOptions& options() const { return opt_; }
  int resolution() const { return resolution_; }
  std::uint32_t span(int level) const { return std::uint32_t{1} << (resolution_ - level); }
  Vec2 point(std::uint32_t x, std::uint32_t y) const { return {coord(origin_x_, x), coord(origin_y_, y)}; }
  double side(int level) const;
  static std::uint64_t key(std::uint32_t x, std::uint32_t y) { return (std::uint64_t{x} << 32) | y; }
  // The exact sample at a lattice point already evaluated (every corner and test point of the tree).
  double sample(std::uint32_t x, std::uint32_t y) const;
  // Samples are numbered 0, 1, ... in the order they are first asked for; each was one evaluation of
  // the field (the exact one, or sample_from's).
  double sample_value(std::int32_t id) const { return values_[static_cast<std::size_t>(id)]; }
  std::size_t samples() const { return values_.size(); }
  // Evaluates the exact field at all the given lattice points not yet sampled, in one at_many call,
  // and gives every key's sample id (ids[i] for keys[i]).
  void sample_all(const std::vector<std::uint64_t>& keys, std::vector<std::int32_t>& ids);
  // Takes later samples from `field` instead (kept by reference): the pipeline refines for the
  // limited field with the base tree's own interpolation, not new exact evaluations.
  void sample_from(const SpacingField& field) { exact_ = &field; }
  // The 9 test points of a cell in lattice quarters: centre, edge midpoints, quarter points.
  static constexpr int kTests[9][2] = {{2, 2}, {2, 0}, {2, 4}, {0, 2}, {4, 2}, {1, 1}, {3, 1}, {1, 3}, {3, 3}};
  static constexpr int kFirstQuarterTest = 5;  // tests 0-4 are the children's corners

  std::size_t batches() const { return batches_; }

  // What the tree holds per cell at its peak, for the memory budget: the cell, its share of the
  // samples (key table, values, closest segments; up to 8 per leaf where every cell is tested), the
  // level's work arrays, the flat arrays emit() writes and the limited field's per-sample arrays.
  // Measured 620-680 bytes per cell on uniform fields of 0.26-1.3 M cells, the case with the most
  // samples per cell (docs/robustness.md, "Memory").
  static constexpr double kBytesPerCell = 768.0;
  // refine() (and so build()) refuses once the nodes that its inside cells ask for pass max_nodes
  // times this. The count grows level by level toward the finished field's estimate: on the 14 case files in both
  // presets it stayed below it at every level (at most 0.996 of it), so the margin only covers fields whose coarse
  // bilinear q overestimates; the exact estimate is checked against max_nodes itself.
  static constexpr double kEarlyNodeMargin = 1.25;

 private:
  double coord(double origin, std::uint32_t lattice) const;
  // Sets root_size_ and the table of cell sides by level (side()).
  void set_root_size(double root_size);
  void choose_grid();
  void make_roots();
  // Sets a new cell's tag from its segment list (exact inside test of the centre when empty).
  void set_tag(Cell& c, std::vector<int> segments);
  // The same with the inside test of its centre done (used when segments is empty).
  void set_tag(Cell& c, std::vector<int> segments, bool inside);
  // The budgets before a level's children are made (BackgroundOptions::max_nodes, memory); `corners`
  // holds the level's corner values, 4 per cell.
  void check_budget(const std::vector<int>& level_cells, const std::vector<Decision>& decision,
                    const std::vector<double>& corners);
  // The steps of refine() on one level (background_builder.cpp says what each does).
  struct Level;
  void sample_corners(Level& level, const SampledFn& sampled);
  void decide_level(Level& level, const DecideFn& decide, const CornerFn& corner_value);
  void quarter_point_keys(Level& level, std::vector<std::size_t>& first_key) const;
  void test_level(Level& level, const TestFn& test, const SampledFn& sampled);
  std::vector<int> split_cell(const Level& level, std::size_t n, std::int32_t m, std::vector<int>& next);
  std::size_t split_level(const Level& level, std::vector<int>& next, std::vector<std::vector<int>>& parent_lists);
  void tag_children(const std::vector<int>& next, const std::vector<std::vector<int>>& parent_lists);

  const SpacingField* exact_;
  const GeometryTree& tree_;
  const BackgroundOptions& opt_;
  const int resolution_;
  // 2^-resolution_: a lattice coordinate times it is ldexp's value exactly (a power of two), without its
  // library call per sample point.
  const double lattice_unit_;
  int grid_ = 1;
  double origin_x_ = 0.0, origin_y_ = 0.0, root_size_ = 1.0;
  std::vector<double> sides_;  // side(level) for levels 0 .. resolution_, once root_size_ is set
  std::vector<Cell> cells_;
  std::vector<std::vector<int>> segment_lists_;
  FlatKeyMap<std::int32_t> samples_;  // lattice key -> sample id
  std::vector<double> values_;        // by sample id
  std::size_t batches_ = 0;
  double finished_nodes_ = 0.0;      // nodes in the inside leaves the running refine() has finished
  bool decide_in_parallel_ = false;  // set by build(): its decide and corner_value only read
};

}  // namespace pdmesh
