// Point location in a triangle mesh, for fields given on a background mesh (spacing.field = "mesh"):
// which triangle holds a point (a quadtree over the triangles' bounding boxes, exact orient2d tests),
// and for points outside the mesh the nearest point on its boundary edges (a second quadtree).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/vec2.hpp"

namespace pdmesh {

// A quadtree over axis-aligned boxes in flat arrays: node_child[n] >= 0 is the first of 4 children
// (x lo y lo, x hi y lo, x lo y hi, x hi y hi), < 0 a leaf -1 - l whose items are
// items[leaf_start[l] .. leaf_start[l + 1]), in increasing item index. An item is stored in every
// leaf whose closed box meets its closed box. Child boxes split at the midpoint mid = (lo + hi) / 2,
// computed the same way in building and lookup, and a point goes to the high child when p >= mid,
// so the leaf holding p holds every item whose box contains p.
struct BoxTree {
  static constexpr int kLeafCapacity = 8;
  static constexpr int kMaxDepth = 24;

  Box root;
  std::vector<std::int32_t> node_child;
  std::vector<std::int32_t> leaf_start;
  std::vector<std::int32_t> items;
  int depth = 0;

  void build(const std::vector<Box>& boxes);
  // The leaf holding p, or -1 when p is outside the root box.
  int leaf_of(Vec2 p) const;
  std::size_t bytes() const;
};

struct LocatorStats {
  std::size_t nodes = 0;
  std::size_t leaves = 0;
  std::size_t references = 0;  // triangle references over all leaves (each triangle is in >= 1 leaf)
  std::size_t boundary_edges = 0;
  int depth = 0;
  std::size_t bytes = 0;
};

// Barycentric weights of a point in a triangle (a, b, c): the three orient2d values
// (b, c, p), (c, a, p), (a, b, p), all >= 0 inside; their sum is twice the triangle's area.
struct Located {
  int triangle = -1;
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
  int a = -1, b = -1;              // the edge's points
  int first = -1, second = -1;     // two of the triangles using it
  bool same_side = false;          // true: same direction; false: more than two triangles
};

class TriangleLocator {
 public:
  // `triangles` counter-clockwise with positive area (MeshSpacing checks this first). Keeps references
  // to both vectors. Finds the boundary edges and the first EdgeConflict (edge order), if any.
  TriangleLocator(const std::vector<Vec2>& points, const std::vector<std::array<int, 3>>& triangles);

  // The lowest-index triangle whose closed area holds p (exact tests), with its weights; triangle -1
  // when none does. Deterministic: points on shared edges and vertices always get the same triangle.
  Located locate(Vec2 p) const;
  // True when p is strictly inside triangle t (all three weights > 0); fills the weights. A point
  // strictly inside one triangle of a valid mesh is in no other, so locate(p) would give t too.
  bool strictly_inside(int t, Vec2 p, double w[3]) const;
  // The point of the boundary edges nearest to p (ties: the lowest edge index). Edge -1 when the
  // mesh has no boundary edges (an empty mesh).
  BoundaryHit nearest_boundary(Vec2 p) const;

  // Edges used by one triangle, as (point a, point b) in the triangle's counter-clockwise order.
  const std::vector<std::array<int, 2>>& boundary_edges() const { return boundary_edges_; }
  // The first shared edge that a valid mesh cannot have (conflict.first < 0: none).
  const EdgeConflict& edge_conflict() const { return conflict_; }
  // The leaf of the triangle tree holding p and its triangles (for the overlap check).
  std::pair<const std::int32_t*, const std::int32_t*> triangles_near(Vec2 p) const;
  LocatorStats stats() const;

 private:
  bool contains(int t, Vec2 p, double w[3]) const;
  void nearest_in(int node, const Box& box, Vec2 p, BoundaryHit& best) const;

  const std::vector<Vec2>& points_;
  const std::vector<std::array<int, 3>>& triangles_;
  BoxTree triangle_tree_;
  std::vector<std::array<int, 2>> boundary_edges_;
  BoxTree edge_tree_;
  EdgeConflict conflict_;
};

}  // namespace pdmesh
