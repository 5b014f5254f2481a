// Builds the initialization tree: geometry refinement, 2:1 balance (edges and corners), and the
// inside/outside classification of the leaves. See docs/initialization.md for the rules.
#include "init/init_tree.hpp"

#include <algorithm>
#include <cmath>

#include "core/interrupt.hpp"
#include "core/errors.hpp"
#include "fmt/format.h"

namespace pdmesh {

InitTree::InitTree(const GeometryTree& tree, const SpacingField& spacing, const InitTreeOptions& options)
    : tree_(tree) {
  const Geometry& g = tree.geometry();
  if (g.segments.empty()) throw GeometryError("initialization tree: the geometry has no segments");
  if (options.segment_resolution != nullptr && options.segment_resolution->size() != g.segments.size())
    throw GeometryError(fmt::format("initialization tree: {} segment resolutions for {} segments",
                                    options.segment_resolution->size(), g.segments.size()));
  const Box& e = g.extents;
  // A square root box, 1% larger than the extents so that no segment lies on its border.
  const double half = 0.5 * std::fmax(e.width(), e.height()) * 1.01;
  if (!(half > 0.0) || !std::isfinite(half))
    throw GeometryError(fmt::format("initialization tree: degenerate geometry extents (size {})", 2 * half));
  const Vec2 c = e.centre();
  root_.lo = {c.x - half, c.y - half};
  root_side_ = 2.0 * half;
  root_.hi = {root_.lo.x + root_side_, root_.lo.y + root_side_};

  Node root;
  root.segments.resize(g.segments.size());
  for (std::size_t s = 0; s < g.segments.size(); ++s) root.segments[s] = static_cast<int>(s);
  nodes_.push_back(std::move(root));

  refine(spacing, options);
  balance(options.max_level);
  collect(0);
  for (std::size_t i = 0; i < leaves_.size(); ++i) {
    if ((i & 4095) == 0) check_interrupt();
    InitLeaf& leaf = leaves_[i];
    // A leaf no segment touches lies wholly in one region, so its centre decides for all of it.
    leaf.kept = !leaf.segments.empty() || tree_.inside(leaf.box.centre());
    if (leaf.kept) kept_.push_back(static_cast<int>(i));
  }
}

double InitTree::side(int level) const { return std::ldexp(root_side_, -level); }

Box InitTree::box_of(int level, std::int64_t ix, std::int64_t iy) const {
  // Products of an integer and a power-of-two fraction are exact, so boxes that share an edge
  // get bit-identical coordinates for it.
  const double s = side(level);
  Box b;
  b.lo = {root_.lo.x + static_cast<double>(ix) * s, root_.lo.y + static_cast<double>(iy) * s};
  b.hi = {root_.lo.x + static_cast<double>(ix + 1) * s, root_.lo.y + static_cast<double>(iy + 1) * s};
  return b;
}

void InitTree::split(int node) {
  const int level = nodes_[node].level + 1;
  const std::int64_t ix = 2 * nodes_[node].ix, iy = 2 * nodes_[node].iy;
  const std::vector<int> parent_segments = std::move(nodes_[node].segments);
  nodes_[node].segments.clear();
  nodes_[node].child = static_cast<int>(nodes_.size());
  const auto& segs = tree_.geometry().segments;
  for (int k = 0; k < 4; ++k) {
    Node child;
    child.level = level;
    child.ix = ix + (k & 1);
    child.iy = iy + (k >> 1);
    const Box b = box_of(level, child.ix, child.iy);
    for (int s : parent_segments)
      if (segment_touches_box(segs[s].a, segs[s].b, b)) child.segments.push_back(s);
    nodes_.push_back(std::move(child));
  }
}

void InitTree::refine(const SpacingField& spacing, const InitTreeOptions& options) {
  const auto& segs = tree_.geometry().segments;
  // Nodes are appended as they are split, so one pass in index order visits every new node.
  for (std::size_t n = 0; n < nodes_.size(); ++n) {
    if (nodes_[n].segments.empty() || nodes_[n].level >= options.max_level) continue;
    double shortest = INFINITY;
    if (options.segment_resolution != nullptr) {
      for (int s : nodes_[n].segments) shortest = std::fmin(shortest, (*options.segment_resolution)[s]);
    } else {
      for (int s : nodes_[n].segments) shortest = std::fmin(shortest, segs[s].length);
    }
    const Box b = box_of(nodes_[n].level, nodes_[n].ix, nodes_[n].iy);
    const double q = spacing.at(b.centre());
    const double target = options.refine_factor * (std::isfinite(q) && q > 0 ? std::fmin(shortest, q) : shortest);
    if (side(nodes_[n].level) > target) split(static_cast<int>(n));
  }
}

int InitTree::leaf_at(int level, std::int64_t ix, std::int64_t iy) const {
  int n = 0;
  while (nodes_[n].child >= 0 && nodes_[n].level < level) {
    const int shift = level - nodes_[n].level - 1;
    const int k = static_cast<int>(((ix >> shift) & 1) | (((iy >> shift) & 1) << 1));
    n = nodes_[n].child + k;
  }
  return n;
}

void InitTree::balance(int max_level) {
  // Buckets of leaves per level, processed deepest first: a split made for a leaf at level l
  // only creates leaves at levels below l, which are still to be processed.
  std::vector<std::vector<int>> bucket(static_cast<std::size_t>(max_level) + 2);
  for (std::size_t n = 0; n < nodes_.size(); ++n)
    if (nodes_[n].child < 0) bucket[nodes_[n].level].push_back(static_cast<int>(n));
  for (int level = max_level + 1; level >= 2; --level) {
    const std::int64_t cells = std::int64_t{1} << level;
    for (std::size_t i = 0; i < bucket[level].size(); ++i) {
      const int leaf = bucket[level][i];
      if (nodes_[leaf].child >= 0) continue;  // already split for a deeper neighbour
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if (dx == 0 && dy == 0) continue;
          const std::int64_t jx = nodes_[leaf].ix + dx, jy = nodes_[leaf].iy + dy;
          if (jx < 0 || jy < 0 || jx >= cells || jy >= cells) continue;
          // Split the neighbour covering cell (jx, jy) until it is at most one level coarser.
          for (int n = leaf_at(level, jx, jy); nodes_[n].level < level - 1; n = leaf_at(level, jx, jy)) {
            split(n);
            const int first = nodes_[n].child;
            for (int k = 0; k < 4; ++k) bucket[nodes_[first + k].level].push_back(first + k);
          }
        }
      }
    }
  }
}

void InitTree::collect(int node) {
  // Depth-first, children in fixed order: a deterministic leaf order.
  std::vector<int> stack{node};
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    if (nodes_[n].child >= 0) {
      for (int k = 3; k >= 0; --k) stack.push_back(nodes_[n].child + k);
      continue;
    }
    InitLeaf leaf;
    leaf.level = nodes_[n].level;
    leaf.ix = nodes_[n].ix;
    leaf.iy = nodes_[n].iy;
    leaf.box = box_of(leaf.level, leaf.ix, leaf.iy);
    leaf.segments = std::move(nodes_[n].segments);
    leaves_.push_back(std::move(leaf));
  }
  nodes_.clear();
  nodes_.shrink_to_fit();
}

}  // namespace pdmesh
