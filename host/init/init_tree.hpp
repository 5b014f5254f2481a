// The initialization tree of thesis ch. 4 ("Interior Nodes", fig 4.5): a quadtree over a square
// root box, refined along the geometry, 2:1 balanced, with leaves fully outside the domain dropped.
#pragma once
#include <cstdint>
#include <vector>

#include "core/vec2.hpp"
#include "geometry/geometry_tree.hpp"  // also segment_touches_box (exact)
#include "spacing/spacing_field.hpp"

namespace pdmesh {

// One leaf of the initialization tree. Its box is root.lo + (ix, iy) * side(level) .. + side(level).
struct InitLeaf {
  int level = 0;
  std::int64_t ix = 0;
  std::int64_t iy = 0;
  Box box;
  std::vector<int> segments;  // boundary segments touching the closed box; empty = fully in or out
  bool kept = false;          // not fully outside the domain
};

struct InitTreeOptions {
  // A leaf touching segments is split while its side exceeds
  // refine_factor * min(shortest touching segment, q at the leaf centre). The default 2 gives boundary leaves
  // of side in (h, 2h] for local resolution h, i.e. 1 to 5 nodes each (docs/initialization.md).
  double refine_factor = 2.0;
  // The boundary resolution per segment of the tree's geometry, used instead of the segment length
  // in the rule above (+inf: q alone). Null: the segment lengths, the thesis' rule (the input points
  // are the boundary nodes). Set when the boundary nodes are not the geometry's points: a dense
  // smooth-curve polyline, or nodes re-placed by the spacing field (docs/initialization.md).
  const std::vector<double>* segment_resolution = nullptr;
  // Deepest level the geometry refinement and the balancing may create (2^-40 of the root side).
  int max_level = 40;
};

class InitTree {
 public:
  InitTree(const GeometryTree& tree, const SpacingField& spacing, const InitTreeOptions& options = {});

  const Box& root() const { return root_; }
  double side(int level) const;
  // All leaves in depth-first order (children lower-left, lower-right, upper-left, upper-right).
  const std::vector<InitLeaf>& leaves() const { return leaves_; }
  // Indices into leaves() of the kept leaves, in the same order.
  const std::vector<int>& kept() const { return kept_; }

 private:
  struct Node {
    int level = 0;
    std::int64_t ix = 0, iy = 0;
    int child = -1;  // index of the first of four consecutive children; -1 for a leaf
    std::vector<int> segments;
  };

  Box box_of(int level, std::int64_t ix, std::int64_t iy) const;
  void split(int node);
  void refine(const SpacingField& spacing, const InitTreeOptions& options);
  void balance(int max_level);
  int leaf_at(int level, std::int64_t ix, std::int64_t iy) const;
  void collect(int node);

  const GeometryTree& tree_;
  Box root_;
  double root_side_ = 0.0;
  std::vector<Node> nodes_;
  std::vector<InitLeaf> leaves_;
  std::vector<int> kept_;
};

}  // namespace pdmesh
