// The geometry quadtree over boundary segments (thesis figs 4.1-4.3) and the queries the rest of
// pdmesh asks of the geometry: closest segment/point, point in domain, does a move cross the boundary.
#pragma once
#include <memory>
#include <vector>

#include "geometry/geometry.hpp"

namespace pdmesh {

struct ClosestHit {
  int segment = -1;     // index into Geometry::segments; -1 when nothing was found
  Vec2 point;           // closest point on that segment
  double distance = 0;  // |query - point|
  double t = 0;         // parameter along the segment, 0 at a, 1 at b
};

class GeometryTree {
 public:
  explicit GeometryTree(const Geometry& geometry);
  ~GeometryTree();
  GeometryTree(const GeometryTree&) = delete;
  GeometryTree& operator=(const GeometryTree&) = delete;

  const Geometry& geometry() const { return geometry_; }

  // Closest point over all segments. Ties are broken by the lowest segment index.
  ClosestHit closest(Vec2 p) const;
  // Closest point on one curve.
  ClosestHit closest_on_curve(Vec2 p, int curve) const;
  // For every curve, its closest segment (out[c] for curve c). Used by the boundary spacing field.
  void closest_per_curve(Vec2 p, std::vector<ClosestHit>& out) const;
  // Even-odd point-in-domain test. Points exactly on a segment count as inside.
  bool inside(Vec2 p) const;
  // True when the open move a->b touches or crosses any boundary segment (a on the boundary is allowed).
  bool crosses_boundary(Vec2 a, Vec2 b) const;
  // Leaf boxes of the tree, for drawing.
  std::vector<Box> leaf_boxes() const;

 private:
  const Geometry& geometry_;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pdmesh
