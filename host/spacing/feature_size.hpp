// Local feature size: the width of the gap through a point, between the closest boundary point and the
// closest boundary point that faces it (docs/spacing.md, "Feature size").
#pragma once
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"

namespace pdmesh {

class FeatureSize {
 public:
  // Two boundary points of one loop face each other only when the shorter way between them along the
  // loop is longer than kArcRatio times their distance: a corner of interior angle alpha has
  // arc/chord = cot(alpha/2) for points at equal distance from it, so corners of 53 degrees and more
  // (cot 26.6 deg = 2) are never gaps, while a slot of width w, deeper than w/2, is.
  static constexpr double kArcRatio = 2.0;
  // Two facing points of one loop lie across a strait, not near a V tip, when the loop between their
  // two segments (the shorter way between the points less the parts of the two segments it runs
  // along) is longer than kStraitArcs times the longer of the two segments and than kStraitRatio
  // times the points' distance: the sides of a V that are single segments meet at a vertex (nothing
  // between them); between finely sampled sides of a V of angle alpha the loop is about
  // 1 / sin(alpha/2) times the distance (20 at 5.7 degrees), while a strait's sides connect only far
  // around the loop.
  static constexpr double kStraitArcs = 1.0;
  static constexpr double kStraitRatio = 20.0;

  // Needs the loops of build_geometry (the inward side of each segment and arc positions along loops).
  explicit FeatureSize(const Geometry& geometry);

  // The gap width W through x. nearest: the closest boundary point of x (GeometryTree::closest);
  // inside: x is in the domain. Inside, W = |x - p1| + |x - p2| with p1 = nearest.point and p2 the
  // closest boundary point ahead of x (on the far side of the line through x perpendicular to
  // x - p1) that faces p1. On the boundary or outside, x is replaced by p1 and "ahead" is along the
  // inward normal of p1's segment, so W = |p1 - p2|. Returns +inf when no such p2 makes W < max_width
  // (max_width bounds the search: wider gaps do not matter to the caller).
  // apart (optional): set to whether the gap cannot narrow to nothing near p1: p2 lies on a loop that
  // never meets p1's (another loop with no point in common with it; W is then at least the two loops'
  // distance), or on p1's own loop across a strait (kStraitArcs).
  double width(Vec2 x, const ClosestHit& nearest, bool inside, double max_width, bool* apart = nullptr) const;

  // One width() query.
  struct WidthQuery {
    Vec2 x;
    ClosestHit nearest;
    bool inside = false;
    double max_width = 0.0;
  };
  // width(q[i].x, q[i].nearest, q[i].inside, q[i].max_width, &apart[i]) for i in [0, n), the same
  // values bit for bit. Consecutive queries are searched in groups of kGroup when they lie close
  // together (see gap_group).
  void width_many(const WidthQuery* q, std::size_t n, double* width, bool* apart) const;

  // The closest boundary point to x (the least squared distance, then the lowest segment index), by
  // this hierarchy, which prunes far-away segments faster than the geometry quadtree for points far
  // from them. hint >= 0: a segment measured first, whose distance prunes most of the hierarchy at once
  // (the answer for a nearby point); the answer does not depend on it.
  ClosestHit closest(Vec2 x, int hint = -1) const;
  // A caller's state between closest_many calls: the last answer (the next search's seed) and how
  // many groups to search point by point before trying a group again.
  struct SearchSeed {
    int segment = -1;
    int skip = 0;
    int backoff = 0;
  };
  // closest(p[i], seed) for i in [0, n), each seeded by the previous answer (seed.segment first; left
  // at the last answer): the same hits bit for bit. Consecutive points are searched in groups of
  // kGroup (see closest_group); after groups that gathered too much, the next 1, 3, 7, then 15 groups
  // are searched point by point without trying (such groups come in runs: points seen from inside a
  // ring-like curve, where most segment boxes near the bound's circle lie within it), and each try
  // costs the seed's distances and a descent.
  void closest_many(const Vec2* p, std::size_t n, ClosestHit* hit, SearchSeed& seed) const;

  // Points per group of closest_many and width_many.
  static constexpr std::size_t kGroup = 16;

  // max over segments s of (fraction * length(s) - slope * distance(x, s)), or 0 if all are below: the
  // upper envelope of one cone per segment, so it is slope-Lipschitz (no jump where the closest
  // segment changes). The input-boundary floor of the spacing pipeline.
  // Values at or below `at_least` are not searched for (the result is then at_least).
  double segment_envelope(Vec2 x, double fraction, double slope, double at_least = 0.0) const;
  // min over segments s of (fraction * length(s) + slope * distance(x, s)): the lower envelope of
  // upward cones, also slope-Lipschitz; at most fraction * length on every segment.
  double segment_lower_envelope(Vec2 x, double fraction, double slope) const;

  // Inward unit normal of a segment (the domain's side).
  Vec2 inward_normal(int segment) const { return normal_[static_cast<std::size_t>(segment)]; }
  // Position of a point of a segment along its loop (arc length from the loop's start).
  double loop_arc(int segment, double t) const;

 private:
  struct Node {
    Box box;
    std::int32_t first = 0;   // leaf: first index into order_; inner: first child (second is first + 1)
    std::int32_t count = 0;   // leaf: number of segments; inner: 0
    double max_length = 0.0;  // longest segment below
    double min_length = 0.0;  // shortest segment below
  };
  void build(std::int32_t node, std::int32_t begin, std::int32_t end);
  // The pruning margin of closest() and of the grouped searches at x: far more than the rounding of
  // any distance they compare (see closest()).
  double margin(Vec2 x) const;
  bool closest_group(const Vec2* p, std::size_t m, ClosestHit* hit, int seed) const;
  // The leaves whose boxes lie within sqrt(reach2) of the box `group` (box_box_distance2), into
  // leaves[0 .. capacity); the count, or -1 where there are more than capacity. The descent of the
  // grouped searches.
  int leaves_near(const Box& group, double reach2, std::int32_t* leaves, int capacity) const;

  // A width() search once its start is known: from, the direction ahead, the radius searched, p1 and
  // its segment, loop and arc position.
  struct GapSearch {
    Vec2 from, ahead, p1;
    double d1 = 0.0, radius = 0.0, arc1 = 0.0, length1 = 0.0;
    // p1's segment: its length, and the loop arc from p1 to its end of higher and of lower arc.
    double segment_length1 = 0.0, rest_up1 = 0.0, rest_down1 = 0.0;
    std::int32_t segment = -1, loop1 = -1;
  };
  // Fills g for width()'s arguments; false where W is +inf without a search.
  bool gap_setup(Vec2 x, const ClosestHit& nearest, bool inside, double max_width, GapSearch& g) const;
  // The search of width() through the hierarchy: the least squared distance ahead that faces p1
  // (best2, below radius^2), its loop and whether it lies across a strait from p1 (faces' strait),
  // both of the first found in the traversal's order; or false.
  bool gap_search(const GapSearch& g, double& best2, std::int32_t& loop, bool& strait) const;
  // Whether p2, at t along segment si, faces g's p1 (another loop, or far enough along p1's); strait:
  // set to whether p2 is on p1's loop across a strait from it (kStraitArcs).
  bool faces(const GapSearch& g, std::int32_t si, Vec2 p2, double t, bool& strait) const;
  // gap_search for the m searches g[0 .. m) at once (see the definition); false (nothing written)
  // where the group gathers too much. exact[i] false: that search must be done by gap_search.
  bool gap_group(const GapSearch* g, std::size_t m, double* best2, std::int32_t* loop, bool* strait, bool* found,
                 bool* exact) const;
  template <class Skip, class Visit>
  void traverse(Vec2 x, const Skip& skip, const Visit& segment) const;

  const Geometry& geometry_;
  std::vector<Vec2> normal_;         // per segment: inward unit normal
  std::vector<std::int32_t> loop_;   // per segment: its loop
  std::vector<double> arc_a_;        // per segment: loop arc at its point a ...
  std::vector<double> arc_sign_;     // ... and +1 / -1 as the loop runs a->b / b->a
  std::vector<double> loop_length_;  // per loop (an open embedded constraint: +inf, it does not wrap)
  // Embedded constraints (docs/geometry-input.md): each constraint curve is a loop of its own here
  // (after the geometry's loops), and where curves of two such loops meet, the meeting point, by
  // the pair of loops (lower index first). Two points of loops that meet at J face each other only
  // when |p1 - J| + |J - p2| > kArcRatio |p1 - p2|: a junction is a corner, not a gap.
  std::vector<std::pair<std::pair<std::int32_t, std::int32_t>, Vec2>> junctions_;
  bool junction_corner(std::int32_t loop1, std::int32_t loop2, Vec2 p1, Vec2 p2, double chord) const;
  // Pairs of loops (lower index first) with a critical point in common, of any kind of loop: a gap
  // between two loops that meet can narrow to nothing at the meeting point.
  std::vector<std::pair<std::int32_t, std::int32_t>> touching_;
  bool touch(std::int32_t loop1, std::int32_t loop2) const;
  double scale_ = 0.0;               // coordinate_magnitude of the segments
  std::vector<Node> nodes_;          // bounding-volume hierarchy over segments; root is nodes_[0]
  std::vector<std::int32_t> order_;  // segment indices, leaf by leaf
  std::vector<Box> segment_box_;     // per segment: its bounding box (closest() skips most segments by it)
};

}  // namespace pdmesh
