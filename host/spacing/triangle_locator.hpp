// Point location in a triangle mesh, for fields given on a background mesh (spacing.field = "mesh"):
// which triangle holds a point (a grid of quadtrees over the triangles' bounding boxes, exact orient2d
// tests) with linear interpolation of per-point values there, and for points outside the mesh the
// nearest point on its boundary edges (a second quadtree).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/vec2.hpp"

namespace pdmesh {

// Quadtrees over axis-aligned boxes in flat arrays. The roots are the cells of a top grid, or one
// root, the items' bounding box (single_root). node_child[n] >= 0 is the first of 4 children
// (x lo y lo, x hi y lo, x lo y hi, x hi y hi), < 0 a leaf -1 - l whose items are
// items[leaf_start[l] .. leaf_start[l + 1]), in increasing item index. An item is in every leaf whose
// closed box meets its closed box. Lookup is exact: the grid's cells are [i c, (i + 1) c) with c a
// power of two, so the cell of p is floor(p.x / c) without rounding, an item is binned to the cells
// from that of its box's low corner to that of its high corner (floor is monotonic), and below a
// cell every midpoint is exact too; p goes to the high child when p >= mid. So the leaf holding p
// holds every item whose box contains p.
struct BoxTree {
  static constexpr int kLeafCapacity = 8;
  static constexpr int kMaxDepth = 24;
  // A cell with more than kLeafCapacity items is split unless its children would hold more than
  // this many times its items between them.
  static constexpr double kMaxDuplication = 2.0;
  // The top grid aims at this many items per cell and has at most kMaxCells cells.
  static constexpr double kItemsPerCell = 4.0;
  static constexpr std::size_t kMaxCells = std::size_t{1} << 22;

  Box root;  // single root: the items' bounding box; grid: the union of the cells
  bool single_root = true;
  int gx = 1, gy = 1;                   // grid cells in x and y
  double cell = 0.0, inv_cell = 0.0;    // cell side (a power of two) and its inverse
  double i0 = 0.0, j0 = 0.0;            // index of the first cell: its low corner is (i0 cell, j0 cell)
  std::vector<std::int32_t> root_node;  // per cell, row-major (y outer)
  std::vector<std::int32_t> node_child;
  std::vector<std::int32_t> leaf_start;
  std::vector<std::int32_t> items;
  int depth = 0;  // deepest leaf below its root

  // With a grid (the triangles) or one root (the boundary edges, searched by nearest distance).
  void build(const std::vector<Box>& boxes, bool grid);
  // The leaf holding p, or -1 when p is outside every root.
  int leaf_of(Vec2 p) const;
  std::size_t bytes() const;
};

struct LocatorStats {
  std::size_t cells = 0;  // top-grid cells
  std::size_t nodes = 0;
  std::size_t leaves = 0;
  std::size_t references = 0;  // triangle references over all leaves (each triangle is in >= 1 leaf)
  std::size_t boundary_edges = 0;
  int depth = 0;
  std::size_t bytes = 0;
};

// A located point: its triangle and the barycentric weights of the triangle's corners (a, b, c): the
// orient2d values of (b, c, p), (c, a, p), (a, b, p), all >= 0, summing to twice the area.
struct Located {
  int triangle = -1;  // -1: outside the mesh
  int position = -1;  // the triangle's place in the locator's own (Hilbert) order
  double w[3] = {0.0, 0.0, 0.0};
};

// The closest point of the mesh's boundary to a point outside the mesh.
struct BoundaryHit {
  int edge = -1;  // index into boundary_edges()
  double t = 0;   // position along the edge, 0 at its first point, 1 at its second
  double distance = 0;
};

// Two triangles that cannot both belong to a valid mesh: they use the same edge in the same
// direction (so lie on the same side of it: one is folded over the other), or a third triangle uses
// the edge too.
struct EdgeConflict {
  int a = -1, b = -1;           // the edge's points
  int first = -1, second = -1;  // two of the triangles using it
  bool same_side = false;       // true: same direction; false: more than two triangles
};

class TriangleLocator {
 public:
  // `triangles` counter-clockwise with positive area (MeshSpacing checks this first); `values` one
  // per point (or empty: interpolate() gives 0). Keeps references to points and triangles. Finds the
  // boundary edges and the first EdgeConflict (in edge order), if any.
  TriangleLocator(const std::vector<Vec2>& points, const std::vector<std::array<int, 3>>& triangles,
                  const std::vector<double>& values = {});

  // A triangle whose closed area holds p (the first in the locator's order, so the same one every
  // time for a point on a shared edge or vertex), with its weights; triangle -1 when none does.
  Located locate(Vec2 p) const;
  // True when p is strictly inside the triangle at `position` (all three weights > 0); fills the
  // weights. A point strictly inside one triangle of a valid mesh is in no other, so locate(p) would
  // return that triangle with the same weights.
  bool strictly_inside(int position, Vec2 p, Located& out) const;
  // The value at a located point: the weighted mean of the corner values (within their range).
  double interpolate(const Located& l) const;
  // The point of the boundary edges nearest to p (ties: the lowest edge index). Edge -1 when the
  // mesh has no boundary edges (an empty mesh).
  BoundaryHit nearest_boundary(Vec2 p) const;

  // Edges used by one triangle, as (point a, point b) in the triangle's counter-clockwise order.
  const std::vector<std::array<int, 2>>& boundary_edges() const { return boundary_edges_; }
  // The first shared edge that a valid mesh cannot have (conflict.first < 0: none).
  const EdgeConflict& edge_conflict() const { return conflict_; }
  int position_of(int triangle) const { return position_of_[static_cast<std::size_t>(triangle)]; }
  // Calls f(triangle) for every triangle stored in the leaf that holds p (for the overlap check).
  template <class F>
  void for_each_triangle_near(Vec2 p, F f) const {
    const int leaf = triangle_tree_.leaf_of(p);
    if (leaf < 0) return;
    for (auto i = static_cast<std::size_t>(triangle_tree_.leaf_start[static_cast<std::size_t>(leaf)]);
         i < static_cast<std::size_t>(triangle_tree_.leaf_start[static_cast<std::size_t>(leaf) + 1]); ++i) {
      f(order_[static_cast<std::size_t>(triangle_tree_.items[i])]);
    }
  }
  LocatorStats stats() const;

 private:
  static constexpr std::size_t kStride = 9;  // per position: x, y, value of each corner
  bool contains(std::size_t position, Vec2 p, double w[3]) const;
  void nearest_in(int node, const Box& box, Vec2 p, BoundaryHit& best) const;

  const std::vector<Vec2>& points_;
  // The triangles in Hilbert order of their centroids, with their corners (and the values there)
  // copied in that order: the triangles of one leaf lie together in memory, so a lookup touches a
  // few cache lines instead of a dozen scattered points. The tree's items are these positions.
  std::vector<int> order_;        // position -> triangle index
  std::vector<int> position_of_;  // triangle index -> position
  std::vector<double> corners_;   // kStride per position
  BoxTree triangle_tree_;
  std::vector<std::array<int, 2>> boundary_edges_;
  BoxTree edge_tree_;
  EdgeConflict conflict_;
};

}  // namespace pdmesh
