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

// Shape of a built tree, for documentation, drawing and tests.
struct GeometryTreeStats {
  int nodes = 0;
  int leaves = 0;
  int max_depth = 0;        // deepest leaf (root = 0)
  int stored_segments = 0;  // sum over leaves; > segment count where segments straddle leaves
};

class GeometryTree {
 public:
  // A leaf is split when it holds more than kLeafCapacity segments, unless it is at kMaxDepth or
  // splitting would not reduce its count (many segments meeting at one vertex on a child corner).
  // 16 rather than 8: a level less to descend, and a leaf's segments are skipped by their bounding
  // boxes, cheaper than a level's four child bounds (eq. 3.6 on 30P30N: ~15 % less per point).
  static constexpr int kLeafCapacity = 16;
  static constexpr int kMaxDepth = 20;
  // What the tree and the geometry's derived arrays hold per segment at most, for the memory budget:
  // a circle of 1e6 segments peaks at 297 MB up to its refusal, reading included
  // (docs/robustness.md, "Memory").
  static constexpr double kBytesPerSegment = 512.0;

  // Keeps a reference to geometry: it must outlive the tree and not change.
  explicit GeometryTree(const Geometry& geometry);
  ~GeometryTree();
  GeometryTree(const GeometryTree&) = delete;
  GeometryTree& operator=(const GeometryTree&) = delete;

  const Geometry& geometry() const { return geometry_; }

  // All queries are const and thread-safe. A geometry without segments gives ClosestHit{} (segment
  // -1), inside() false and crosses_boundary() false.

  // Closest point over all segments. Ties are broken by the lowest segment index.
  ClosestHit closest(Vec2 p) const;
  // Closest point on one curve (ties: lowest segment index). Throws std::out_of_range on a bad curve.
  ClosestHit closest_on_curve(Vec2 p, int curve) const;
  // For every curve, its closest segment (out[c] for curve c), from the curve's own quadtree. Used by
  // the boundary spacing field.
  void closest_per_curve(Vec2 p, std::vector<ClosestHit>& out) const;
  // The same result, bit for bit, faster when out holds this tree's answer for a nearby point (the
  // previous query of a spatially ordered batch): each curve's search starts from that segment's
  // distance, which prunes most of the tree at once. Entries that are not such an answer (wrong size,
  // segment -1, a segment of another curve) are ignored.
  void closest_per_curve_near(Vec2 p, std::vector<ClosestHit>& out) const;
  // Curve `curve`'s closest segment to each of p[0 .. n) (its distance and index: distance[i],
  // segment[i], -1 when the curve has none), the same bits as closest_on_curve per point. *seed, a
  // segment of this curve or -1, seeds the first search; each later one starts from the previous
  // point's answer, and *seed is left at the last answer. One curve over many points keeps that
  // curve's tree in the first-level cache and its branches predictable (the boundary spacing field).
  void closest_on_curve_many(const Vec2* p, std::size_t n, int curve, double* distance, int* segment, int* seed) const;
  // The number of curves (the per-curve trees).
  int curve_count() const;
  // Closest point over the boundary curves' segments alone (embedded constraints left out): where a
  // node that left the domain is put back. The same as closest() for a geometry without constraints.
  ClosestHit closest_wall(Vec2 p) const;
  // Even-odd point-in-domain test. Points exactly on a segment count as inside. Embedded constraint
  // curves bound nothing: inside() and crosses_boundary() look at the boundary curves alone.
  bool inside(Vec2 p) const;
  // True when the move a->b touches or crosses any boundary segment at a point other than a
  // (a on the boundary is allowed; b on the boundary counts as touching).
  bool crosses_boundary(Vec2 a, Vec2 b) const;
  // Leaf boxes of the tree, for drawing.
  std::vector<Box> leaf_boxes() const;
  // Bounding box of one curve's points.
  Box curve_box(int curve) const;
  GeometryTreeStats stats() const;

 private:
  // The even-odd test by casting a ray through the tree (the fallback of inside()).
  bool ray_inside(Vec2 p) const;

  const Geometry& geometry_;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Per-segment primitives shared by the tree and the brute-force oracle, so that both compute
// bit-identical distances and the tie rule (lowest index) decides the same way.

// Closest point on segment s (index `index`) to p. When p lies exactly on s (exact predicate) the
// hit is p itself with distance 0.
ClosestHit closest_on_segment(Vec2 p, const Segment& s, int index);
// Exact: p lies on the closed segment ab.
bool point_on_segment(Vec2 p, Vec2 a, Vec2 b);
// Exact crossing-number contribution of segment ab for the horizontal ray from p, with the
// half-open rule (ab spans the ray's row when exactly one end is strictly above p.y), so a vertex
// on the ray is counted once. Returns 2 when p lies on ab, 1 when ab crosses the ray, 0 otherwise.
enum class RayDirection { PlusX, MinusX };
int ray_crossing(Vec2 p, Vec2 a, Vec2 b, RayDirection direction = RayDirection::PlusX);
// Exact: the move a->b shares a point other than a with the closed segment cd.
bool move_touches_segment(Vec2 a, Vec2 b, Vec2 c, Vec2 d);
// Exact: the closed segment ab shares a point with the closed box.
bool segment_touches_box(Vec2 a, Vec2 b, const Box& box);

}  // namespace pdmesh
