// The geometry quadtree (thesis ch. 4, figs 4.1-4.3): one region quadtree over all segments and one
// per curve, with closest-point, point-in-domain and move-crosses-boundary queries.
#include "geometry/geometry_tree.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/box_distance.hpp"
#include "core/errors.hpp"
#include "core/predicates.hpp"
#include "geometry/closest_on_segment.hpp"

namespace pdmesh {

// ---------------------------------------------------------------------------------------------
// Per-segment primitives (shared with the brute-force oracle).

bool point_on_segment(Vec2 p, Vec2 a, Vec2 b) {
  if (p.x < std::fmin(a.x, b.x) || p.x > std::fmax(a.x, b.x)) return false;
  if (p.y < std::fmin(a.y, b.y) || p.y > std::fmax(a.y, b.y)) return false;
  return orient2d(a, b, p) == 0.0;
}

ClosestHit closest_on_segment(Vec2 p, const Segment& s, int index) {
  return detail::closest_on_segment_inline(p, s, index);
}

int ray_crossing(Vec2 p, Vec2 a, Vec2 b, RayDirection direction) {
  if (point_on_segment(p, a, b)) return 2;
  const bool a_above = a.y > p.y;
  const bool b_above = b.y > p.y;
  if (a_above == b_above) return 0;
  // The segment spans p.y and p is not on it, so orient2d is non-zero. p left of an upward segment
  // (or right of a downward one) means the segment crosses the row to the right of p.
  const double o = orient2d(a, b, p);
  const bool crosses_right_of_p = b_above ? o > 0.0 : o < 0.0;
  return crosses_right_of_p == (direction == RayDirection::PlusX) ? 1 : 0;
}

bool move_touches_segment(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  if (!segments_intersect(a, b, c, d)) return false;
  if (!point_on_segment(a, c, d)) return true;  // they meet, and not at a
  if (a == b) return false;
  if (orient2d(c, d, b) != 0.0) return false;  // different lines through a: they meet only at a
  // Collinear and a lies on cd: cd goes on beyond a towards b iff one of its ends lies on b's side.
  // For collinear points the side is decided exactly by comparing one coordinate.
  const auto towards_b = [&](Vec2 e) {
    if (b.x != a.x) return e.x != a.x && (e.x > a.x) == (b.x > a.x);
    return e.y != a.y && (e.y > a.y) == (b.y > a.y);
  };
  return towards_b(c) || towards_b(d);
}

bool segment_touches_box(Vec2 a, Vec2 b, const Box& box) {
  if (std::fmax(a.x, b.x) < box.lo.x || std::fmin(a.x, b.x) > box.hi.x) return false;
  if (std::fmax(a.y, b.y) < box.lo.y || std::fmin(a.y, b.y) > box.hi.y) return false;
  // Bounding boxes overlap; the segment misses the box only if its line has all four corners
  // strictly on one side.
  const double o[4] = {orient2d(a, b, box.lo), orient2d(a, b, {box.hi.x, box.lo.y}), orient2d(a, b, box.hi),
                       orient2d(a, b, {box.lo.x, box.hi.y})};
  const bool all_pos = o[0] > 0 && o[1] > 0 && o[2] > 0 && o[3] > 0;
  const bool all_neg = o[0] < 0 && o[1] < 0 && o[2] < 0 && o[3] < 0;
  return !(all_pos || all_neg);
}

// ---------------------------------------------------------------------------------------------
// The quadtree.

namespace {

struct Node {
  Box box;      // the quadrant
  Box content;  // box ∩ bounding box of its segments: a tighter lower bound for closest()
  // The last four fields: a capsule around the node's segments, every point of which lies within
  // cap_r of the axis from cap_a, cap_len long along their principal direction. Its distance minus cap_r
  // bounds closest() from below far more tightly than the box where the segments follow a curve:
  // seen from afar, the box of an arc bulges towards the query point, and without this bound a
  // query on a finely segmented circle would visit O(sqrt(segments)) leaves.
  int first_child = -1;  // children are first_child .. first_child + 3; -1 for a leaf
  int begin = 0;         // leaf: its segment ids are items[begin, begin + count)
  int count = 0;
  int depth = 0;
  Vec2 cap_a{}, cap_u{};  // the axis: cap_a + t cap_u, t in [0, cap_len], cap_u a unit vector
  double cap_len = 0.0;
  double cap_r = -1.0;  // < 0: no capsule (no segments)
  // A sector seen from the tree's centre c (per-curve trees only): every point of the node's segments
  // lies at least sec_r from c, between the rays from c along sec_u1 and sec_u2 (counter-clockwise from
  // sec_u1, less than a half-turn apart). For a query nearer c than sec_r this bounds the distance
  // far more tightly than the box or the capsule where the curve surrounds the query (a far-field
  // circle seen from inside, where every arc's box and capsule lie nearer than the arc).
  Vec2 sec_u1{}, sec_u2{};
  double sec_r = -1.0;  // <= 0: no sector bound
};

// Distance from p to the node's capsule axis. Along the unit direction, without point_segment_
// distance's division: the axis distance is evaluated for most children a search looks at.
// The query's coordinates kept in two registers: without this barrier the vectorizer packed them into
// one register by two 8-byte stores and a 16-byte load, a store-forwarding stall in every search.
inline Vec2 in_registers(Vec2 q) {
  double x = q.x, y = q.y;
#if defined(__SSE2__) && defined(__GNUC__)
  asm("" : "+x"(x), "+x"(y));
#endif
  return {x, y};
}

inline double axis_distance(Vec2 p, const Node& n) {
  const double px = p.x - n.cap_a.x, py = p.y - n.cap_a.y;
  double t = px * n.cap_u.x + py * n.cap_u.y;
  t = t < 0.0 ? 0.0 : (t > n.cap_len ? n.cap_len : t);
  const double ex = px - t * n.cap_u.x, ey = py - t * n.cap_u.y;
  return std::sqrt(ex * ex + ey * ey);
}

// A lower bound on the distance from p to the node's segments by its sector (see Node::sec_r); 0
// when p is not nearer the centre than sec_r. The points at least sec_r from c within the sector are
// nearest to p (inside the disc of radius sec_r) on the arc of radius sec_r: at p's own direction when
// that lies in the sector (sec_r - |p - c|, the triangle inequality), else at the arc's nearer end.
inline double sector_distance(Vec2 p, Vec2 c, const Node& n) {
  const double vx = p.x - c.x, vy = p.y - c.y;
  const double rho2 = vx * vx + vy * vy;
  if (!(rho2 < n.sec_r * n.sec_r)) return 0.0;
  const double rho = std::sqrt(rho2);
  double d;
  if (n.sec_u1.x * vy - n.sec_u1.y * vx >= 0.0 && vx * n.sec_u2.y - vy * n.sec_u2.x >= 0.0) {
    d = n.sec_r - rho;
  } else {
    const double ax = c.x + n.sec_r * n.sec_u1.x - p.x, ay = c.y + n.sec_r * n.sec_u1.y - p.y;
    const double bx = c.x + n.sec_r * n.sec_u2.x - p.x, by = c.y + n.sec_r * n.sec_u2.y - p.y;
    d = std::sqrt(std::min(ax * ax + ay * ay, bx * bx + by * by));
  }
  // Rounded down (the arc's end points and rho carry a few ulps of the centre's magnitude): the bound
  // must never exceed a true distance.
  return d * (1.0 - 1e-9) - 1e-12 * (std::fabs(c.x) + std::fabs(c.y) + n.sec_r);
}

// The bounding box of a leaf's segment, stored beside the leaf's segment ids (item_boxes_): the leaf
// scan of closest() reads these 32 contiguous bytes per entry instead of the 48-byte segment and its
// min/max, and most entries are rejected by them.
Box item_box(const Segment& s) {
  Box b;
  b.lo = {std::min(s.a.x, s.b.x), std::min(s.a.y, s.b.y)};
  b.hi = {std::max(s.a.x, s.b.x), std::max(s.a.y, s.b.y)};
  return b;
}

// A square box around the given segments (square so that leaves stay square, whatever the
// aspect ratio of the geometry), never smaller than their bounding box despite rounding.
Box square_box(const std::vector<Segment>& segments, const std::vector<int>& ids) {
  Box b;
  for (const int id : ids) {
    b.add(segments[id].a);
    b.add(segments[id].b);
  }
  const Vec2 c = b.centre();
  const double half = 0.5 * std::fmax(b.width(), b.height());
  Box s;
  s.lo = {std::fmin(c.x - half, b.lo.x), std::fmin(c.y - half, b.lo.y)};
  s.hi = {std::fmax(c.x + half, b.hi.x), std::fmax(c.y + half, b.hi.y)};
  return s;
}

class Quadtree {
 public:
  // sectors: give the nodes sector bounds around the centre of the segments' bounding box where the
  // segments form a ring around it (the per-curve trees: a curve that surrounds its queries, such as
  // a far-field circle).
  Quadtree(const std::vector<Segment>& segments, std::vector<int> ids, bool sectors = false) : segments_(&segments) {
    if (ids.empty()) return;
    nodes_.push_back(Node{square_box(segments, ids), Box{}, -1, 0, 0, 0});
    bounds_ = Box{};
    for (const int id : ids) {
      bounds_.add(segments[id].a);
      bounds_.add(segments[id].b);
    }
    centre_ = bounds_.centre();
    // Only for a ring-like curve (every segment at least half as far from the centre as its farthest
    // point: a circle, an ellipse, a closed far field): elsewhere the bound rarely prunes and its test
    // in every child costs more than it saves (an airfoil's curves on 30P30N).
    if (sectors) {
      double r_min = HUGE_VAL, r_max = 0.0;
      for (const int id : ids) {
        const Segment& sg = segments[static_cast<std::size_t>(id)];
        r_min = std::min(r_min, detail::closest_on_segment_inline(centre_, sg, id).distance);
        r_max = std::max({r_max, dist(sg.a, centre_), dist(sg.b, centre_)});
      }
      sectors_ = r_min >= 0.5 * r_max;
    }
    build(0, std::move(ids));
    const Box& r = nodes_[0].box;
    slack_ = 1e-12 * std::fmax(r.width(), r.height());
  }

  bool empty() const { return nodes_.empty(); }
  const Box& root_box() const { return nodes_[0].box; }
  const Box& bounds() const { return bounds_; }

  // hint >= 0: a segment of this tree whose hit seeds the search. The result does not depend on it:
  // every segment at least as close as the seed is still examined (the bounds keep their margin and
  // ties go to the lowest index), so only the number of nodes visited changes.
  ClosestHit closest(Vec2 query, int hint = -1) const {
    const Vec2 p = in_registers(query);
    ClosestHit best;
    best.distance = std::numeric_limits<double>::infinity();
    if (nodes_.empty()) return ClosestHit{};
    if (hint >= 0) best = detail::closest_on_segment_inline(p, (*segments_)[static_cast<std::size_t>(hint)], hint);
    // Depth first, the nearer children first: with the seed's bound (or the first leaf's hit) most
    // subtrees are pruned at once, and a small stack on the frame costs less than a heap (this is the
    // inner loop of every eq. 3.6 evaluation: 15 searches per point on 30P30N). The nodes visited
    // are a superset of the best-first search's, so the result is the same: every segment that could
    // beat or tie the best hit is examined, ties going to the lowest index.
    // Plain arrays without initializers (zeroing them would cost more than most searches; only
    // entries below `top` are ever read), and two of them rather than one of {d, n} pairs: the
    // insertion sort below moves entries written a moment before, and a pair moved as one 16-byte
    // load would wait for its two field stores to retire (store forwarding fails).
    constexpr int kStack = 3 * GeometryTree::kMaxDepth + 8;
    double stack_d[kStack];
    int stack_n[kStack];
    int top = 0;
    // The root goes on without its bound (0 is a lower bound too): it is expanded whatever its
    // bound, since its children's bounds decide the same pruning (15 searches per eq. 3.6 point).
    stack_d[top] = 0.0;
    stack_n[top] = 0;
    ++top;
    while (top > 0) {
      --top;
      const double d = stack_d[top];
      const int n = stack_n[top];
      if (d > bound(best.distance)) continue;
      const Node& node = nodes_[n];
      if (node.first_child < 0) {
        // The segment's bounding box is a lower bound on its distance, with the same margin as the
        // node boxes: a segment skipped by it could neither beat nor tie the best hit. It skips most
        // of the divisions and square roots of closest_on_segment. Before any hit there is no bound
        // (limit2 is +inf, and a NaN query point's NaN limit2 skips nothing either).
        double limit2 = std::numeric_limits<double>::infinity();
        if (best.segment >= 0) {
          const double limit = bound(best.distance);
          limit2 = limit * limit;
        }
        // Local pointers: the loop reads nothing through `this` (kept in registers, not reloaded).
        const int* const ids = items_.data() + node.begin;
        const Box* const boxes = item_boxes_.data() + node.begin;
        const Segment* const segments = segments_->data();
        // In blocks of 64 entries: first every entry's box distance and a bit mask of those within
        // the bound, without a branch per entry (whether an entry passes follows no pattern, and a
        // mispredicted branch costs more than the test); then the entries of the mask in order,
        // tested again against the bound of the moment, which a hit may have lowered. The entries
        // measured are the same as one test per entry in order would measure.
        for (int first = 0; first < node.count; first += 64) {
          const int block = std::min(64, node.count - first);
          double d2[64];
          std::uint64_t within = 0;
          for (int i = 0; i < block; ++i) {
            d2[i] = box_distance2(p, boxes[first + i]);
            within |= static_cast<std::uint64_t>(!(d2[i] > limit2)) << i;
          }
          while (within != 0) {
            const int i = std::countr_zero(within);
            within &= within - 1;
            if (d2[i] > limit2) continue;
            const int id = ids[first + i];
            // The seed was measured first, and measuring it again cannot change the best hit (a
            // tie goes to the lower index either way). It is the answer in 93% of the searches of
            // 30P30N's eq. 3.6 and lies in several of the leaves visited: skipping it saves two of
            // every three closest_on_segment calls there (9.2M -> 3.0M).
            if (id == hint) continue;
            const ClosestHit h = detail::closest_on_segment_inline(p, segments[id], id);
            if (h.distance < best.distance || (h.distance == best.distance && id < best.segment)) {
              best = h;
              const double limit = bound(best.distance);
              limit2 = limit * limit;
            }
          }
        }
        continue;
      }
      // The surviving children go straight onto the stack above `base`, insertion-sorted farthest
      // first so that the nearest is popped next: sorted in place, with no copy from a separate array.
      const int base = top;
      const double limit = bound(best.distance);
      const double limit2 = limit * limit;
      for (int c = node.first_child; c < node.first_child + 4; ++c) {
        const Node& kid = nodes_[c];
        // The content box first, squared: most children are pruned by it without the capsule's
        // division and square roots (the same children are pruned as by the larger of the two bounds).
        // An empty leaf needs no test of its own (whether a child is one follows no pattern, so a branch
        // on it would be mispredicted often): its content box is the empty Box{}
        // (lo 1e300, hi -1e300), at a squared distance of +inf, so it is pruned here once any segment
        // has been measured, and if pushed before that it is popped with nothing to measure.
        const double box2 = box_distance2(p, kid.content);
        if (box2 > limit2) continue;
        double kd = std::sqrt(box2);
        if (kid.cap_r >= 0.0) kd = std::max(kd, axis_distance(p, kid) - kid.cap_r);
        if (kid.sec_r > 0.0) kd = std::max(kd, sector_distance(p, centre_, kid));
        if (kd > limit) continue;
        int k = top++;
        while (k > base && stack_d[k - 1] < kd) {
          stack_d[k] = stack_d[k - 1];
          stack_n[k] = stack_n[k - 1];
          --k;
        }
        stack_d[k] = kd;
        stack_n[k] = c;
      }
    }
    return best;
  }

  // closest() at each of p[0 .. n), each search seeded by the previous answer (*seed first; left at
  // the last answer). A tree that is one leaf (a curve of at most kLeafCapacity segments: 8 of the 15
  // curves of 30P30N, half of eq. 3.6's searches) is scanned directly, without the search's stack; a
  // tree of kGroupMinEntries entries or more, not ring-like, is searched in groups of kGroup points
  // (closest_group).
  // Every way gives the lowest (distance, index) over the same closest_on_segment values, so the bits
  // are closest()'s.
  void closest_many(const Vec2* p, std::size_t n, double* distance, int* segment, int* seed) const {
    int s = *seed;
    if (nodes_.empty()) {
      for (std::size_t i = 0; i < n; ++i) {
        distance[i] = 0.0;
        segment[i] = -1;
      }
      if (n > 0) *seed = -1;
      return;
    }
    if (nodes_[0].first_child >= 0) {
      for (std::size_t first = 0; first < n; first += kGroup) {
        const std::size_t m = std::min(kGroup, n - first);
        if (s < 0 || items_.size() < kGroupMinEntries || sectors_ ||
            !closest_group(p + first, m, distance + first, segment + first, s)) {
          for (std::size_t i = first; i < first + m; ++i) {
            const ClosestHit h = closest(p[i], s);
            distance[i] = h.distance;
            segment[i] = h.segment;
            s = h.segment;
          }
        } else {
          s = segment[first + m - 1];
        }
      }
      *seed = s;
      return;
    }
    const Node& leaf = nodes_[0];
    const int* const ids = items_.data() + leaf.begin;
    const Box* const boxes = item_boxes_.data() + leaf.begin;
    const Segment* const segments = segments_->data();
    const int count = leaf.count;
    for (std::size_t k = 0; k < n; ++k) {
      const Vec2 q = in_registers(p[k]);
      // The seed's hit first, then every other entry whose box lies within the bound of the moment:
      // closest()'s leaf scan, whose entries skipped by the box could neither beat nor tie the best.
      ClosestHit best;
      best.distance = std::numeric_limits<double>::infinity();
      double limit2 = std::numeric_limits<double>::infinity();
      if (s >= 0) {
        best = detail::closest_on_segment_inline(q, segments[s], s);
        const double limit = bound(best.distance);
        limit2 = limit * limit;
      }
      for (int i = 0; i < count; ++i) {
        const int id = ids[i];
        if (id == s || box_distance2(q, boxes[i]) > limit2) continue;
        const ClosestHit h = detail::closest_on_segment_inline(q, segments[id], id);
        if (h.distance < best.distance || (h.distance == best.distance && id < best.segment)) {
          best = h;
          const double limit = bound(best.distance);
          limit2 = limit * limit;
        }
      }
      distance[k] = best.distance;
      segment[k] = best.segment;
      s = best.segment;
    }
    *seed = s;
  }

  // Points per group of closest_group.
  static constexpr std::size_t kGroup = 16;
  // Leaf entries a group may gather before it gives up (its points are searched one by one).
  static constexpr int kGroupCandidates = 32;
  // Trees with fewer leaf entries search point by point: their searches are short, and a group there
  // gathers most of the curve (clarky's and e387's airfoil curves of 30-66 segments, where the groups
  // cost more CPU than the searches they replace; 30P30N's curves of 110-441 segments gain). So do
  // ring-like curves (sectors_): seen from inside, a group's bound reaches much of the ring (the
  // annulus cases' circles, where the groups cost more CPU too).
  static constexpr std::size_t kGroupMinEntries = 100;

  // closest() at the m points p[0 .. m) of a small group at once: seg, a segment of this tree, bounds
  // every point's answer (its distance from p plus the margin, D the largest over the group); the leaf
  // entries whose boxes lie within D of the group's bounding box are gathered by one descent, and each
  // point scans those alone. An entry left out is farther than D from every point of the group, so it
  // could neither beat nor tie that point's bound: each answer is the lowest (distance, index) over the
  // same closest_on_segment values as closest()'s. Returns false (nothing written) where the group
  // gathers more than kGroupCandidates entries (a spread-out group, near a finely segmented curve).
  bool closest_group(const Vec2* p, std::size_t m, double* distance, int* segment, int seg) const {
    const Segment* const segments = segments_->data();
    ClosestHit hint[kGroup];
    Box group;
    double reach = 0.0;
    for (std::size_t i = 0; i < m; ++i) {
      hint[i] = detail::closest_on_segment_inline(p[i], segments[seg], seg);
      reach = std::max(reach, bound(hint[i].distance));
      group.add(p[i]);
    }
    if (!(reach < std::numeric_limits<double>::infinity())) return false;
    const double reach2 = reach * reach;
    // The capsules bound the nodes from the group's centre: a point of the group lies within `spread`
    // of it (rounded up), so its distance to a node's segments is at least the centre's capsule
    // distance less `spread`.
    const Vec2 centre = group.centre();
    const double spread =
        0.5 * std::sqrt(group.width() * group.width() + group.height() * group.height()) * (1.0 + 1e-12) + slack_;
    int candidates[kGroupCandidates];
    int found = 0;
    int stack[3 * GeometryTree::kMaxDepth + 8];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[static_cast<std::size_t>(stack[--top])];
      if (node.first_child >= 0) {
        for (int c = node.first_child; c < node.first_child + 4; ++c) {
          const Node& kid = nodes_[static_cast<std::size_t>(c)];
          if (box_box_distance2(group, kid.content) > reach2) continue;
          if (kid.cap_r >= 0.0 && axis_distance(centre, kid) - kid.cap_r - spread > reach) continue;
          stack[top++] = c;
        }
        continue;
      }
      for (int e = node.begin; e < node.begin + node.count; ++e) {
        if (items_[static_cast<std::size_t>(e)] == seg ||
            box_box_distance2(group, item_boxes_[static_cast<std::size_t>(e)]) > reach2)
          continue;
        if (found == kGroupCandidates) return false;
        candidates[found++] = e;
      }
    }
    for (std::size_t i = 0; i < m; ++i) {
      const Vec2 q = in_registers(p[i]);
      ClosestHit best = hint[i];
      double limit = bound(best.distance);
      double limit2 = limit * limit;
      for (int k = 0; k < found; ++k) {
        const auto e = static_cast<std::size_t>(candidates[k]);
        if (box_distance2(q, item_boxes_[e]) > limit2) continue;
        const int id = items_[e];
        const ClosestHit h = detail::closest_on_segment_inline(q, segments[id], id);
        if (h.distance < best.distance || (h.distance == best.distance && id < best.segment)) {
          best = h;
          limit = bound(best.distance);
          limit2 = limit * limit;
        }
      }
      distance[i] = best.distance;
      segment[i] = best.segment;
    }
    return true;
  }

  // Calls visit(node) for every leaf whose box satisfies wanted(box), stopping when visit returns true.
  template <class Wanted, class Visit>
  bool any_leaf(Wanted wanted, Visit visit) const {
    if (nodes_.empty()) return false;
    std::array<int, 3 * GeometryTree::kMaxDepth + 8> stack;
    int top = 0;
    if (!wanted(nodes_[0].box)) return false;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (node.first_child < 0) {
        if (visit(node)) return true;
        continue;
      }
      for (int k = 0; k < 4; ++k)
        if (wanted(nodes_[node.first_child + k].box)) stack[top++] = node.first_child + k;
    }
    return false;
  }

  const std::vector<int>& items() const { return items_; }
  const std::vector<Node>& nodes() const { return nodes_; }

  // The leaf whose closed box contains p (a point on a shared edge may go to either side), or -1
  // when p is outside the root box.
  int locate(Vec2 p) const {
    if (nodes_.empty() || !nodes_[0].box.contains(p)) return -1;
    int n = 0;
    while (nodes_[n].first_child >= 0) {
      const Vec2 c = nodes_[n].box.centre();
      n = nodes_[n].first_child + (p.x >= c.x ? 1 : 0) + (p.y >= c.y ? 2 : 0);
    }
    return n;
  }

  std::vector<Box> leaf_boxes() const {
    std::vector<Box> out;
    for (const Node& n : nodes_)
      if (n.first_child < 0) out.push_back(n.box);
    return out;
  }

  GeometryTreeStats stats() const {
    GeometryTreeStats s;
    s.nodes = static_cast<int>(nodes_.size());
    for (const Node& n : nodes_) {
      if (n.first_child >= 0) continue;
      ++s.leaves;
      s.max_depth = std::max(s.max_depth, n.depth);
      s.stored_segments += n.count;
    }
    return s;
  }

 private:
  // Candidates within a small relative and absolute slack of the best distance are still visited,
  // so that rounding in box_distance can never hide an exactly tied segment with a lower index.
  double bound(double best) const { return best * (1.0 + 1e-9) + slack_; }

  // The capsule of node n around the end points of its segments (see Node::cap_r).
  void set_capsule(int n, const std::vector<int>& ids) {
    if (ids.empty()) return;
    double mx = 0.0, my = 0.0;
    for (const int id : ids) {
      const Segment& s = (*segments_)[id];
      mx += s.a.x + s.b.x;
      my += s.a.y + s.b.y;
    }
    const double count = 2.0 * static_cast<double>(ids.size());
    mx /= count;
    my /= count;
    double sxx = 0.0, sxy = 0.0, syy = 0.0;
    for (const int id : ids) {
      for (const Vec2 e : {(*segments_)[id].a, (*segments_)[id].b}) {
        sxx += (e.x - mx) * (e.x - mx);
        sxy += (e.x - mx) * (e.y - my);
        syy += (e.y - my) * (e.y - my);
      }
    }
    const double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
    const double ux = std::cos(angle), uy = std::sin(angle);
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (const int id : ids) {
      for (const Vec2 e : {(*segments_)[id].a, (*segments_)[id].b}) {
        const double t = (e.x - mx) * ux + (e.y - my) * uy;
        lo = std::min(lo, t);
        hi = std::max(hi, t);
      }
    }
    Node& node = nodes_[n];
    node.cap_a = {mx + lo * ux, my + lo * uy};
    node.cap_u = {ux, uy};
    node.cap_len = hi - lo;
    // The distance to the axis is convex along a segment, so its end points bound it. Rounded up
    // generously: the bound must never exceed a true distance (closest() adds its own margin too).
    double r = 0.0;
    for (const int id : ids)
      for (const Vec2 e : {(*segments_)[id].a, (*segments_)[id].b}) r = std::max(r, axis_distance(e, node));
    const Box& b = node.box;
    node.cap_r = r * (1.0 + 1e-9) + 1e-12 * std::fmax(b.width(), b.height());
  }

  // The sector of node n around centre_ (see Node::sec_r), left off where the segments span half a
  // turn or more around it or pass near it.
  void set_sector(int n, const std::vector<int>& ids) {
    if (!sectors_ || ids.empty()) return;
    const Segment& first = (*segments_)[static_cast<std::size_t>(ids.front())];
    const double ref = std::atan2(first.a.y - centre_.y, first.a.x - centre_.x);
    double lo = 0.0, hi = 0.0;
    double r = HUGE_VAL;
    for (const int id : ids) {
      const Segment& sg = (*segments_)[static_cast<std::size_t>(id)];
      for (const Vec2 e : {sg.a, sg.b}) {
        double t = std::atan2(e.y - centre_.y, e.x - centre_.x) - ref;
        if (t > M_PI) t -= 2.0 * M_PI;
        if (t < -M_PI) t += 2.0 * M_PI;
        lo = std::min(lo, t);
        hi = std::max(hi, t);
      }
      r = std::min(r, detail::closest_on_segment_inline(centre_, sg, id).distance);
    }
    // Widened by a small angle and the radius lowered, for the rounding of atan2, cos and sin here.
    lo -= 1e-9;
    hi += 1e-9;
    if (!(hi - lo < 0.9 * M_PI)) return;
    const Box& b = nodes_[static_cast<std::size_t>(n)].box;
    r = r * (1.0 - 1e-9) - 1e-12 * (std::fabs(centre_.x) + std::fabs(centre_.y) + std::fmax(b.width(), b.height()));
    if (!(r > 0.0)) return;
    Node& node = nodes_[static_cast<std::size_t>(n)];
    node.sec_u1 = {std::cos(ref + lo), std::sin(ref + lo)};
    node.sec_u2 = {std::cos(ref + hi), std::sin(ref + hi)};
    node.sec_r = r;
  }

  void build(int n, std::vector<int> ids) {
    set_capsule(n, ids);
    set_sector(n, ids);
    const Box box = nodes_[n].box;
    const int depth = nodes_[n].depth;
    if (static_cast<int>(ids.size()) <= GeometryTree::kLeafCapacity || depth >= GeometryTree::kMaxDepth) {
      make_leaf(n, ids);
      return;
    }
    const Vec2 c = box.centre();
    const Box kid_boxes[4] = {Box{box.lo, c}, Box{{c.x, box.lo.y}, {box.hi.x, c.y}},
                              Box{{box.lo.x, c.y}, {c.x, box.hi.y}}, Box{c, box.hi}};
    std::vector<int> kid_ids[4];
    for (int k = 0; k < 4; ++k)
      for (const int id : ids)
        if (segment_touches_box((*segments_)[id].a, (*segments_)[id].b, kid_boxes[k])) kid_ids[k].push_back(id);
    // Many segments meeting at one vertex on the child corner go to every child: splitting then
    // never helps, so keep the node a leaf.
    bool reduces = false;
    for (const auto& k : kid_ids) reduces = reduces || k.size() < ids.size();
    if (!reduces) {
      make_leaf(n, ids);
      return;
    }
    const int first = static_cast<int>(nodes_.size());
    nodes_[n].first_child = first;
    for (int k = 0; k < 4; ++k) nodes_.push_back(Node{kid_boxes[k], Box{}, -1, 0, 0, depth + 1});
    for (int k = 0; k < 4; ++k) {
      // A child may hold all of its parent's segments and still split them further: a small curve
      // in a large quadrant (made a leaf here before, the inner circle of an annulus ended in leaves
      // of hundreds of segments). build() itself makes a leaf where no split helps.
      build(first + k, std::move(kid_ids[k]));
      const Box& kid = nodes_[first + k].content;
      if (kid.lo.x <= kid.hi.x) {
        nodes_[n].content.add(kid.lo);
        nodes_[n].content.add(kid.hi);
      }
    }
  }

  void make_leaf(int n, const std::vector<int>& ids) {
    nodes_[n].begin = static_cast<int>(items_.size());
    nodes_[n].count = static_cast<int>(ids.size());
    items_.insert(items_.end(), ids.begin(), ids.end());
    for (const int id : ids) item_boxes_.push_back(item_box((*segments_)[id]));
    Box bb;
    for (const int id : ids) {
      bb.add((*segments_)[id].a);
      bb.add((*segments_)[id].b);
    }
    const Box& q = nodes_[n].box;
    if (!ids.empty())
      nodes_[n].content = Box{{std::fmax(bb.lo.x, q.lo.x), std::fmax(bb.lo.y, q.lo.y)},
                              {std::fmin(bb.hi.x, q.hi.x), std::fmin(bb.hi.y, q.hi.y)}};
  }

  const std::vector<Segment>* segments_;
  bool sectors_ = false;
  Vec2 centre_{};  // the sectors' centre
  std::vector<Node> nodes_;
  std::vector<int> items_;
  std::vector<Box> item_boxes_;  // the bounding box of each items_ entry's segment (item_box)
  Box bounds_;
  double slack_ = 0.0;
};

}  // namespace

struct GeometryTree::Impl {
  Quadtree all;
  std::vector<Quadtree> per_curve;
  // Per node of `all` (leaves only): whether the leaf's centre is inside (1), outside (0), or on
  // the boundary (-1: the local test below cannot start from it).
  std::vector<signed char> centre_inside;
  // With embedded constraints: the tree over the boundary curves' segments alone and its
  // centre_inside, for inside(), crosses_boundary() and closest_wall(). Null without constraints
  // (`all` serves).
  std::unique_ptr<Quadtree> walls;
  std::vector<signed char> walls_centre_inside;
  const Quadtree& wall_tree() const { return walls ? *walls : all; }
  const std::vector<signed char>& wall_centres() const { return walls ? walls_centre_inside : centre_inside; }
};

namespace {

std::vector<int> all_ids(std::size_t n) {
  std::vector<int> ids(n);
  for (std::size_t i = 0; i < n; ++i) ids[i] = static_cast<int>(i);
  return ids;
}

}  // namespace

GeometryTree::GeometryTree(const Geometry& geometry) : geometry_(geometry) {
  const auto& segs = geometry.segments;
  const int curves = static_cast<int>(geometry.curves.size());
  std::vector<std::vector<int>> by_curve(curves);
  for (std::size_t i = 0; i < segs.size(); ++i) {
    const Segment& s = segs[i];
    if (s.curve < 0 || s.curve >= curves)
      throw GeometryError("geometry tree: segment " + std::to_string(i) + " names curve " + std::to_string(s.curve) +
                          " but the geometry has " + std::to_string(curves) + " curves");
    if (!std::isfinite(s.a.x) || !std::isfinite(s.a.y) || !std::isfinite(s.b.x) || !std::isfinite(s.b.y))
      throw GeometryError("geometry tree: segment " + std::to_string(i) + " of curve " + std::to_string(s.curve) +
                          " has a non-finite end point");
    by_curve[s.curve].push_back(static_cast<int>(i));
  }
  impl_ = std::make_unique<Impl>(Impl{Quadtree(segs, all_ids(segs.size())), {}, {}, {}, {}});
  impl_->per_curve.reserve(curves);
  for (int c = 0; c < curves; ++c) impl_->per_curve.emplace_back(segs, std::move(by_curve[c]), true);
  std::vector<int> wall_ids;
  for (std::size_t i = 0; i < segs.size(); ++i)
    if (!geometry.curves[static_cast<std::size_t>(segs[i].curve)].constraint) wall_ids.push_back(static_cast<int>(i));
  if (wall_ids.size() < segs.size()) impl_->walls = std::make_unique<Quadtree>(segs, std::move(wall_ids));
  const Quadtree& walls = impl_->wall_tree();
  std::vector<signed char>& centres = impl_->walls ? impl_->walls_centre_inside : impl_->centre_inside;
  const auto& nodes = walls.nodes();
  centres.assign(nodes.size(), -1);
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    if (nodes[n].first_child >= 0) continue;
    const Vec2 c = nodes[n].box.centre();
    bool on_boundary = false;
    for (int i = nodes[n].begin; i < nodes[n].begin + nodes[n].count; ++i) {
      const Segment& seg = segs[walls.items()[i]];
      on_boundary = on_boundary || point_on_segment(c, seg.a, seg.b);
    }
    if (!on_boundary) centres[n] = ray_inside(c) ? 1 : 0;
  }
}

GeometryTree::~GeometryTree() = default;

ClosestHit GeometryTree::closest(Vec2 p) const { return impl_->all.closest(p); }

ClosestHit GeometryTree::closest_wall(Vec2 p) const { return impl_->wall_tree().closest(p); }

ClosestHit GeometryTree::closest_on_curve(Vec2 p, int curve) const {
  if (curve < 0 || curve >= static_cast<int>(impl_->per_curve.size()))
    throw std::out_of_range("GeometryTree::closest_on_curve: no curve " + std::to_string(curve));
  return impl_->per_curve[curve].closest(p);
}

void GeometryTree::closest_per_curve(Vec2 p, std::vector<ClosestHit>& out) const {
  out.resize(impl_->per_curve.size());
  for (std::size_t c = 0; c < out.size(); ++c) out[c] = impl_->per_curve[c].closest(p);
}

void GeometryTree::closest_per_curve_near(Vec2 p, std::vector<ClosestHit>& out) const {
  const std::size_t curves = impl_->per_curve.size();
  const auto& segs = geometry_.segments;
  const bool hinted = out.size() == curves;
  out.resize(curves);
  for (std::size_t c = 0; c < curves; ++c) {
    const int s = hinted ? out[c].segment : -1;
    const bool valid = s >= 0 && static_cast<std::size_t>(s) < segs.size() &&
                       segs[static_cast<std::size_t>(s)].curve == static_cast<int>(c);
    out[c] = impl_->per_curve[c].closest(p, valid ? s : -1);
  }
}

int GeometryTree::curve_count() const { return static_cast<int>(impl_->per_curve.size()); }

void GeometryTree::closest_on_curve_many(const Vec2* p, std::size_t n, int curve, double* distance, int* segment,
                                         int* seed) const {
  if (curve < 0 || curve >= static_cast<int>(impl_->per_curve.size()))
    throw std::out_of_range("GeometryTree::closest_on_curve_many: no curve " + std::to_string(curve));
  const Quadtree& tree = impl_->per_curve[static_cast<std::size_t>(curve)];
  const auto& segs = geometry_.segments;
  int s = *seed;
  if (!(s >= 0 && static_cast<std::size_t>(s) < segs.size() && segs[static_cast<std::size_t>(s)].curve == curve))
    s = -1;
  tree.closest_many(p, n, distance, segment, &s);
  *seed = s;
}

bool GeometryTree::inside(Vec2 p) const {
  // Local test: p and its leaf's centre c lie in the same closed leaf box, so every boundary
  // segment that could cross the segment pc touches the leaf and is in its list. inside(p) is
  // inside(c) flipped once per proper crossing; anything degenerate (pc through a vertex or along
  // a segment) falls back to the ray cast. An empty leaf has no crossings: its centre decides.
  const Quadtree& tree = impl_->wall_tree();
  const int leaf = tree.locate(p);
  if (leaf < 0) return false;  // outside the root box, which holds every segment
  const signed char centre = impl_->wall_centres()[static_cast<std::size_t>(leaf)];
  if (centre >= 0) {
    const Node& node = tree.nodes()[static_cast<std::size_t>(leaf)];
    const Vec2 c = node.box.centre();
    bool in = centre == 1;
    bool degenerate = false;
    // A segment whose bounding box misses the bounding box of pc can neither hold p nor meet pc:
    // it changes nothing below, and skipping it spares the exact predicates.
    const double lo_x = std::min(p.x, c.x), hi_x = std::max(p.x, c.x);
    const double lo_y = std::min(p.y, c.y), hi_y = std::max(p.y, c.y);
    for (int i = node.begin; i < node.begin + node.count && !degenerate; ++i) {
      const Segment& s = geometry_.segments[tree.items()[i]];
      if (std::max(s.a.x, s.b.x) < lo_x || std::min(s.a.x, s.b.x) > hi_x || std::max(s.a.y, s.b.y) < lo_y ||
          std::min(s.a.y, s.b.y) > hi_y)
        continue;
      if (point_on_segment(p, s.a, s.b)) return true;  // on the boundary counts as inside
      if (orient2d(p, c, s.a) == 0.0 || orient2d(p, c, s.b) == 0.0) {
        // A vertex on the line through p and c: fine when it is off the segment pc.
        if (segments_intersect(p, c, s.a, s.b) && !segments_cross_properly(p, c, s.a, s.b)) degenerate = true;
        continue;
      }
      if (segments_cross_properly(p, c, s.a, s.b)) in = !in;
    }
    if (!degenerate) return in;
  }
  return ray_inside(p);
}

bool GeometryTree::ray_inside(Vec2 p) const {
  const Quadtree& tree = impl_->wall_tree();
  // Segments straddling several leaves along the ray must be counted once: gather, sort, unique.
  // A local, not a thread_local (see parallel_for_scratch): the ray cast is the rare fallback.
  std::vector<int> candidates;
  if (tree.empty()) return false;
  // Cast the ray towards the nearer side of the root box: fewer leaves to visit. With the
  // half-open rule both directions give the same parity (every closed loop crosses the whole row
  // an even number of times), which the brute-force tests (always +x) check.
  const Box& root = tree.root_box();
  const RayDirection dir = p.x - root.lo.x < root.hi.x - p.x ? RayDirection::MinusX : RayDirection::PlusX;
  const auto on_ray = [p, dir](const Box& b) {
    return b.lo.y <= p.y && p.y <= b.hi.y && (dir == RayDirection::PlusX ? p.x <= b.hi.x : b.lo.x <= p.x);
  };
  tree.any_leaf(on_ray, [&](const auto& leaf) {
    candidates.insert(candidates.end(), tree.items().begin() + leaf.begin,
                      tree.items().begin() + leaf.begin + leaf.count);
    return false;
  });
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  bool in = false;
  for (const int id : candidates) {
    const Segment& s = geometry_.segments[id];
    const int r = ray_crossing(p, s.a, s.b, dir);
    if (r == 2) return true;
    if (r == 1) in = !in;
  }
  return in;
}

bool GeometryTree::crosses_boundary(Vec2 a, Vec2 b) const {
  const Quadtree& tree = impl_->wall_tree();
  // Both ends in one empty leaf: the move stays in a closed box that no segment touches.
  const int leaf = tree.locate(a);
  if (leaf >= 0) {
    const Node& node = tree.nodes()[static_cast<std::size_t>(leaf)];
    if (node.count == 0 && node.box.contains(b)) return false;
  }
  return tree.any_leaf([&](const Box& box) { return segment_touches_box(a, b, box); },
                       [&](const auto& leaf) {
                         for (int i = leaf.begin; i < leaf.begin + leaf.count; ++i) {
                           const Segment& s = geometry_.segments[tree.items()[i]];
                           if (move_touches_segment(a, b, s.a, s.b)) return true;
                         }
                         return false;
                       });
}

std::vector<Box> GeometryTree::leaf_boxes() const { return impl_->all.leaf_boxes(); }

Box GeometryTree::curve_box(int curve) const {
  if (curve < 0 || curve >= static_cast<int>(impl_->per_curve.size()))
    throw std::out_of_range("GeometryTree::curve_box: no curve " + std::to_string(curve));
  return impl_->per_curve[curve].bounds();
}

GeometryTreeStats GeometryTree::stats() const { return impl_->all.stats(); }

}  // namespace pdmesh
