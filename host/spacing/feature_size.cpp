// FeatureSize: inward normals and loop arc positions of the segments, a bounding-volume hierarchy over
// them, and the query for the closest boundary point ahead of a point that faces its closest point.
#include "spacing/feature_size.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include <fmt/format.h>

#include "core/box_distance.hpp"
#include "core/errors.hpp"
#include "geometry/closest_on_segment.hpp"

namespace pdmesh {

namespace {

constexpr int kLeafSize = 4;

// True when the whole box lies on or behind the line through x perpendicular to n.
bool box_behind(const Box& b, Vec2 x, Vec2 n) {
  const double hx = std::max(n.x * (b.lo.x - x.x), n.x * (b.hi.x - x.x));
  const double hy = std::max(n.y * (b.lo.y - x.y), n.y * (b.hi.y - x.y));
  return hx + hy <= 0.0;
}

}  // namespace

FeatureSize::FeatureSize(const Geometry& geometry) : geometry_(geometry) {
  const auto& segs = geometry.segments;
  const std::size_t n = segs.size();
  normal_.assign(n, Vec2{0.0, 0.0});
  loop_.assign(n, -1);
  arc_a_.assign(n, 0.0);
  arc_sign_.assign(n, 1.0);
  // Each loop's curves in traversal order: a loop with positive signed area runs counter-clockwise;
  // the domain lies inside a loop of even depth and outside one of odd depth (even-odd rule).
  for (std::size_t l = 0; l < geometry.loops.size(); ++l) {
    const Loop& loop = geometry.loops[l];
    const bool domain_left = (loop.signed_area > 0.0) == (loop.depth % 2 == 0);
    double offset = 0.0;
    for (std::size_t i = 0; i < loop.curves.size(); ++i) {
      const Curve& c = geometry.curves[static_cast<std::size_t>(loop.curves[i])];
      const bool reversed = loop.reversed[i] != 0;
      for (int k = 0; k < c.segment_count(); ++k) {
        const auto s = static_cast<std::size_t>(c.first_segment + k);
        const Vec2 d = segs[s].b - segs[s].a;
        const double len = norm(d);
        const Vec2 left{-d.y / len, d.x / len};
        // Left of the loop's direction is the domain when domain_left; the segment runs with the loop
        // unless the curve is traversed reversed.
        normal_[s] = (domain_left != reversed) ? left : Vec2{-left.x, -left.y};
        loop_[s] = static_cast<std::int32_t>(l);
        arc_a_[s] = reversed ? offset + c.length() - c.arc[static_cast<std::size_t>(k)]
                             : offset + c.arc[static_cast<std::size_t>(k)];
        arc_sign_[s] = reversed ? -1.0 : 1.0;
      }
      offset += c.length();
    }
    loop_length_.push_back(offset);
  }
  // Embedded constraints: one loop each, arc along the curve; the left normal stands for the inward
  // one (both sides are the domain). Then the points where curves of different loops meet.
  for (std::size_t c = 0; c < geometry.curves.size(); ++c) {
    const Curve& curve = geometry.curves[c];
    if (!curve.constraint) continue;
    const auto l = static_cast<std::int32_t>(loop_length_.size());
    for (int k = 0; k < curve.segment_count(); ++k) {
      const auto s = static_cast<std::size_t>(curve.first_segment + k);
      const Vec2 d = segs[s].b - segs[s].a;
      const double len = norm(d);
      normal_[s] = {-d.y / len, d.x / len};
      loop_[s] = l;
      arc_a_[s] = curve.arc[static_cast<std::size_t>(k)];
    }
    const bool closed = curve.points.front() == curve.points.back();
    loop_length_.push_back(closed ? curve.length() : std::numeric_limits<double>::infinity());
  }
  // The loops meeting at each critical point: every pair touches, and with constraints (more loops
  // than the geometry's) the pair is also a junction at that point.
  const bool constraints = loop_length_.size() > geometry.loops.size();
  for (const CriticalPoint& cp : geometry.critical) {
    std::vector<std::int32_t> loops;
    for (const int c : cp.curves) {
      const Curve& curve = geometry.curves[static_cast<std::size_t>(c)];
      if (curve.segment_count() > 0) loops.push_back(loop_[static_cast<std::size_t>(curve.first_segment)]);
    }
    std::sort(loops.begin(), loops.end());
    loops.erase(std::unique(loops.begin(), loops.end()), loops.end());
    for (std::size_t i = 0; i < loops.size(); ++i)
      for (std::size_t j = i + 1; j < loops.size(); ++j) {
        touching_.push_back({loops[i], loops[j]});
        if (constraints) junctions_.push_back({{loops[i], loops[j]}, cp.p});
      }
  }
  std::sort(touching_.begin(), touching_.end());
  touching_.erase(std::unique(touching_.begin(), touching_.end()), touching_.end());
  for (std::size_t s = 0; s < n; ++s)
    if (loop_[s] < 0)
      throw Error(fmt::format("feature size: segment {} of curve {} belongs to no loop", segs[s].index, segs[s].curve));
  scale_ = coordinate_magnitude(segs);
  segment_box_.resize(n);
  for (std::size_t s = 0; s < n; ++s) {
    segment_box_[s].add(segs[s].a);
    segment_box_[s].add(segs[s].b);
  }
  order_.resize(n);
  for (std::size_t s = 0; s < n; ++s) order_[s] = static_cast<std::int32_t>(s);
  if (n > 0) {
    nodes_.reserve(2 * n / kLeafSize + 2);
    nodes_.emplace_back();
    build(0, 0, static_cast<std::int32_t>(n));
  }
}

// Fills nodes_[node] for the segments order_[begin, end): a leaf of at most kLeafSize, or two children
// split at the median of the segment midpoints along the wider axis. nodes_ grows during the
// recursion, so nodes are referred to by index only.
void FeatureSize::build(std::int32_t node, std::int32_t begin, std::int32_t end) {
  const auto& segs = geometry_.segments;
  Box box, mids;
  double max_length = 0.0, min_length = std::numeric_limits<double>::infinity();
  for (std::int32_t i = begin; i < end; ++i) {
    const Segment& s = segs[static_cast<std::size_t>(order_[static_cast<std::size_t>(i)])];
    box.add(s.a);
    box.add(s.b);
    mids.add(0.5 * (s.a + s.b));
    max_length = std::max(max_length, s.length);
    min_length = std::min(min_length, s.length);
  }
  nodes_[static_cast<std::size_t>(node)].box = box;
  nodes_[static_cast<std::size_t>(node)].max_length = max_length;
  nodes_[static_cast<std::size_t>(node)].min_length = min_length;
  if (end - begin <= kLeafSize) {
    nodes_[static_cast<std::size_t>(node)].first = begin;
    nodes_[static_cast<std::size_t>(node)].count = end - begin;
    return;
  }
  const bool by_x = mids.width() >= mids.height();
  const std::int32_t mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](std::int32_t a, std::int32_t b) {
                     const Segment& sa = segs[static_cast<std::size_t>(a)];
                     const Segment& sb = segs[static_cast<std::size_t>(b)];
                     const double ka = by_x ? sa.a.x + sa.b.x : sa.a.y + sa.b.y;
                     const double kb = by_x ? sb.a.x + sb.b.x : sb.a.y + sb.b.y;
                     return ka < kb || (ka == kb && a < b);
                   });
  const auto first = static_cast<std::int32_t>(nodes_.size());
  nodes_[static_cast<std::size_t>(node)].first = first;
  nodes_.emplace_back();
  nodes_.emplace_back();
  build(first, begin, mid);
  build(first + 1, mid, end);
}

bool FeatureSize::junction_corner(std::int32_t loop1, std::int32_t loop2, Vec2 p1, Vec2 p2, double chord) const {
  const std::pair<std::int32_t, std::int32_t> key{std::min(loop1, loop2), std::max(loop1, loop2)};
  for (const auto& [loops, j] : junctions_)
    if (loops == key && !(dist(p1, j) + dist(j, p2) > kArcRatio * chord)) return true;
  return false;
}

bool FeatureSize::touch(std::int32_t loop1, std::int32_t loop2) const {
  const std::pair<std::int32_t, std::int32_t> key{std::min(loop1, loop2), std::max(loop1, loop2)};
  return std::binary_search(touching_.begin(), touching_.end(), key);
}

double FeatureSize::loop_arc(int segment, double t) const {
  const auto s = static_cast<std::size_t>(segment);
  return arc_a_[s] + arc_sign_[s] * t * geometry_.segments[s].length;
}

// Depth first over the hierarchy, the child whose box is nearer to x first: skip(node, d2) prunes a
// node, d2 being its box's squared distance from x (it may use what `segment` found so far);
// segment(index) sees every segment of the leaves reached. Each node's d2 is computed once, when its
// parent orders its children, and kept beside it on the stack (two arrays, not one of pairs: a pair
// read as one 16-byte load right after its two stores would wait for them, store forwarding fails).
template <class Skip, class Visit>
void FeatureSize::traverse(Vec2 x, const Skip& skip, const Visit& segment) const {
  if (nodes_.empty()) return;
  // The depth is about log2(segments / kLeafSize), and each level leaves one node on the stack; 64
  // is far beyond it.
  double stack_d[64];
  std::int32_t stack_n[64];
  int top = 0;
  stack_d[top] = box_distance2(x, nodes_[0].box);
  stack_n[top++] = 0;
  while (top > 0) {
    --top;
    const Node& node = nodes_[static_cast<std::size_t>(stack_n[top])];
    if (skip(node, stack_d[top])) continue;
    if (node.count == 0) {
      const double da = box_distance2(x, nodes_[static_cast<std::size_t>(node.first)].box);
      const double db = box_distance2(x, nodes_[static_cast<std::size_t>(node.first + 1)].box);
      const bool a_first = da <= db;
      stack_d[top] = a_first ? db : da;
      stack_n[top++] = a_first ? node.first + 1 : node.first;
      stack_d[top] = a_first ? da : db;
      stack_n[top++] = a_first ? node.first : node.first + 1;
      continue;
    }
    for (std::int32_t i = node.first; i < node.first + node.count; ++i) segment(order_[static_cast<std::size_t>(i)]);
  }
}

double FeatureSize::margin(Vec2 x) const { return 1e-11 * std::max({scale_, std::fabs(x.x), std::fabs(x.y)}); }

ClosestHit FeatureSize::closest(Vec2 x, int hint) const {
  ClosestHit best;
  double best2 = std::numeric_limits<double>::infinity();
  // Nodes and segments whose bounding box lies farther than best.distance + margin are skipped: their
  // distance exceeds the best by far more than either's rounding (~50 ulps of the coordinates'
  // magnitude) and closest_on_segment's snap to 0 (1e-12 of it), so their squared distance is
  // strictly larger and they could neither win nor tie. Every segment that could is measured,
  // whatever the order, so the answer is the least squared distance, then the lowest index, whichever
  // segment seeds the search.
  const double margin = this->margin(x);
  double skip2 = std::numeric_limits<double>::infinity();
  const auto& segs = geometry_.segments;
  const auto measure = [&](std::int32_t si) {
    const ClosestHit h = detail::closest_on_segment_inline(x, segs[static_cast<std::size_t>(si)], si);
    const double d2 = h.distance * h.distance;
    if (d2 < best2 || (d2 == best2 && si < best.segment)) {
      best2 = d2;
      best = h;
      skip2 = (h.distance + margin) * (h.distance + margin);
    }
  };
  const bool seeded = hint >= 0 && static_cast<std::size_t>(hint) < segs.size();
  if (seeded) measure(hint);
  traverse(
      x, [&](const Node&, double d2) { return d2 > skip2; },
      [&](std::int32_t si) {
        if (seeded && si == hint) return;  // measured first
        if (box_distance2(x, segment_box_[static_cast<std::size_t>(si)]) > skip2) return;
        measure(si);
      });
  return best;
}

void FeatureSize::closest_many(const Vec2* p, std::size_t n, ClosestHit* hit, SearchSeed& seed) const {
  int s = seed.segment;
  const auto segments = static_cast<int>(geometry_.segments.size());
  for (std::size_t first = 0; first < n; first += kGroup) {
    const std::size_t m = std::min(kGroup, n - first);
    if (seed.skip > 0) {
      --seed.skip;
    } else if (s >= 0 && s < segments && m > 1) {
      if (closest_group(p + first, m, hit + first, s)) {
        seed.backoff = 0;
        s = hit[first + m - 1].segment;
        continue;
      }
      seed.backoff = std::min(2 * seed.backoff + 1, 15);
      seed.skip = seed.backoff;
    }
    for (std::size_t i = first; i < first + m; ++i) {
      hit[i] = closest(p[i], s);
      s = hit[i].segment;
    }
  }
  seed.segment = s;
}

namespace {

// Segments a closest_group may gather before it gives up (its points are searched one by one).
constexpr int kGroupSegments = 64;
// Leaves a gap_group may gather before it gives up.
constexpr int kGroupLeaves = 32;

bool finite(Vec2 p) { return std::isfinite(p.x) && std::isfinite(p.y); }

}  // namespace

int FeatureSize::leaves_near(const Box& group, double reach2, std::int32_t* leaves, int capacity) const {
  int count = 0;
  std::int32_t stack[64];
  int top = 0;
  if (box_box_distance2(group, nodes_[0].box) <= reach2) stack[top++] = 0;
  while (top > 0) {
    const std::int32_t n = stack[--top];
    const Node& node = nodes_[static_cast<std::size_t>(n)];
    if (node.count == 0) {
      for (std::int32_t c = node.first; c < node.first + 2; ++c)
        if (box_box_distance2(group, nodes_[static_cast<std::size_t>(c)].box) <= reach2) stack[top++] = c;
      continue;
    }
    if (count == capacity) return -1;
    leaves[count++] = n;
  }
  return count;
}

// closest() at the m points p[0 .. m) at once: the seed segment's distance from each point plus that
// point's margin bounds what closest() would measure there (D, the largest over the group). One
// descent gathers the segments whose boxes lie within D of the group's bounding box (a lower bound on
// their distance from every point of the group, in floating point too: each operation of
// box_box_distance2 rounds a difference at least as large as box_distance2's does for a point in
// the box), and each point scans those alone, with closest()'s own skip test and comparison. A
// segment left out lies farther than the point's bound, so closest() would skip it too: every
// answer is the least (squared distance, index) over the same closest_on_segment values, closest()'s
// bits. Returns false (nothing written) for a group with a point not finite, or that gathers more than
// kGroupSegments leaves or segments (spread out, or far from fine segments).
bool FeatureSize::closest_group(const Vec2* p, std::size_t m, ClosestHit* hit, int seed) const {
  const auto& segs = geometry_.segments;
  const Segment& s0 = segs[static_cast<std::size_t>(seed)];
  double best2[kGroup], skip2[kGroup], margins[kGroup];
  Box group;
  double reach = 0.0;
  for (std::size_t i = 0; i < m; ++i) {
    if (!finite(p[i])) return false;
    const ClosestHit h = detail::closest_on_segment_inline(p[i], s0, seed);
    hit[i] = h;
    best2[i] = h.distance * h.distance;
    margins[i] = margin(p[i]);
    skip2[i] = (h.distance + margins[i]) * (h.distance + margins[i]);
    reach = std::max(reach, h.distance + margins[i]);
    group.add(p[i]);
  }
  if (!(reach < std::numeric_limits<double>::infinity())) return false;
  const double reach2 = reach * reach;
  std::int32_t leaves[kGroupSegments];
  const int count = leaves_near(group, reach2, leaves, kGroupSegments);
  if (count < 0) return false;
  std::int32_t candidates[kGroupSegments];
  Box boxes[kGroupSegments];
  int found = 0;
  for (int l = 0; l < count; ++l) {
    const Node& node = nodes_[static_cast<std::size_t>(leaves[l])];
    for (std::int32_t k = node.first; k < node.first + node.count; ++k) {
      const std::int32_t si = order_[static_cast<std::size_t>(k)];
      const Box& box = segment_box_[static_cast<std::size_t>(si)];
      if (si == seed || box_box_distance2(group, box) > reach2) continue;
      if (found == kGroupSegments) return false;
      boxes[found] = box;
      candidates[found++] = si;
    }
  }
  for (std::size_t i = 0; i < m; ++i) {
    const Vec2 x = p[i];
    ClosestHit best = hit[i];
    double b2 = best2[i], s2 = skip2[i];
    for (int k = 0; k < found; ++k) {
      if (box_distance2(x, boxes[k]) > s2) continue;
      const std::int32_t si = candidates[k];
      const ClosestHit h = detail::closest_on_segment_inline(x, segs[static_cast<std::size_t>(si)], si);
      const double d2 = h.distance * h.distance;
      if (d2 < b2 || (d2 == b2 && si < best.segment)) {
        b2 = d2;
        best = h;
        s2 = (h.distance + margins[i]) * (h.distance + margins[i]);
      }
    }
    hit[i] = best;
  }
  return true;
}

double FeatureSize::segment_envelope(Vec2 x, double fraction, double slope, double at_least) const {
  double best = std::max(0.0, at_least);
  const auto& segs = geometry_.segments;
  // No segment below a node can beat `best`: its length is at most max_length, its distance at least the box's.
  traverse(
      x, [&](const Node& n, double d2) { return fraction * n.max_length - slope * std::sqrt(d2) <= best; },
      [&](std::int32_t si) {
        const Segment& s = segs[static_cast<std::size_t>(si)];
        best = std::max(best, fraction * s.length - slope * closest_on_segment(x, s, si).distance);
      });
  return best;
}

double FeatureSize::segment_lower_envelope(Vec2 x, double fraction, double slope) const {
  double best = std::numeric_limits<double>::infinity();
  const auto& segs = geometry_.segments;
  traverse(
      x, [&](const Node& n, double d2) { return fraction * n.min_length + slope * std::sqrt(d2) >= best; },
      [&](std::int32_t si) {
        const Segment& s = segs[static_cast<std::size_t>(si)];
        best = std::min(best, fraction * s.length + slope * closest_on_segment(x, s, si).distance);
      });
  return best;
}

namespace {

// The part of segment s strictly ahead of a gap search's `from` (ahead . (a + t (b - a) - from) > 0):
// false when there is none; else its point p2 nearest to from (t along s) and d2 = |p2 - from|^2.
inline bool ahead_point(const Segment& s, Vec2 from, Vec2 ahead, Vec2& p2, double& t, double& d2) {
  const double ha = dot(ahead, s.a - from), hb = dot(ahead, s.b - from);
  if (ha <= 0.0 && hb <= 0.0) return false;
  double t0 = 0.0, t1 = 1.0;
  if (ha <= 0.0) t0 = ha / (ha - hb);
  if (hb <= 0.0) t1 = ha / (ha - hb);
  const Vec2 d = s.b - s.a;
  const double len2 = norm2(d);
  t = std::clamp(len2 > 0.0 ? dot(from - s.a, d) / len2 : 0.0, t0, t1);
  p2 = s.a + t * d;
  d2 = norm2(p2 - from);
  return true;
}

}  // namespace

bool FeatureSize::gap_setup(Vec2 x, const ClosestHit& nearest, bool inside, double max_width, GapSearch& g) const {
  if (nearest.segment < 0 || !(max_width > 0.0)) return false;
  g.p1 = nearest.point;
  g.segment = nearest.segment;
  // Ahead: inside, away from p1 through x; otherwise from p1 along its segment's inward normal.
  g.from = x;
  g.d1 = 0.0;
  if (inside && nearest.distance > 0.0) {
    g.d1 = nearest.distance;
    g.ahead = (1.0 / g.d1) * (x - g.p1);
  } else {
    g.from = g.p1;
    g.ahead = normal_[static_cast<std::size_t>(nearest.segment)];
  }
  g.radius = max_width - g.d1;
  if (!(g.radius > 0.0)) return false;
  g.loop1 = loop_[static_cast<std::size_t>(nearest.segment)];
  g.arc1 = loop_arc(nearest.segment, nearest.t);
  g.length1 = loop_length_[static_cast<std::size_t>(g.loop1)];
  const auto s1 = static_cast<std::size_t>(nearest.segment);
  g.segment_length1 = geometry_.segments[s1].length;
  const double other_end = arc_a_[s1] + arc_sign_[s1] * g.segment_length1;
  g.rest_up1 = std::max(arc_a_[s1], other_end) - g.arc1;
  g.rest_down1 = g.arc1 - std::min(arc_a_[s1], other_end);
  return true;
}

bool FeatureSize::faces(const GapSearch& g, std::int32_t si, Vec2 p2, double t, bool& strait) const {
  strait = false;
  const std::int32_t loop2 = loop_[static_cast<std::size_t>(si)];
  if (loop2 != g.loop1 && !junctions_.empty() && junction_corner(g.loop1, loop2, g.p1, p2, dist(g.p1, p2)))
    return false;
  if (loop2 == g.loop1) {
    // p2 == p1 (a neighbour segment's shared vertex) is no gap, however the two arc positions round.
    const double chord = dist(g.p1, p2);
    const double arc2 = loop_arc(si, t);
    const double along = std::fabs(arc2 - g.arc1);
    const double arc = std::min(along, g.length1 - along);
    if (!(chord > 0.0) || !(arc > kArcRatio * chord)) return false;
    // The shorter way leaves p1 toward higher arc when it runs directly to a higher arc2 or across
    // the loop's start to a lower one; it then enters p2's segment at its lower end.
    const auto s2 = static_cast<std::size_t>(si);
    const double length2 = geometry_.segments[s2].length;
    const double other_end = arc_a_[s2] + arc_sign_[s2] * length2;
    const bool up = (arc2 > g.arc1) == (along <= g.length1 - along);
    const double between = up ? arc - g.rest_up1 - (arc2 - std::min(arc_a_[s2], other_end))
                              : arc - g.rest_down1 - (std::max(arc_a_[s2], other_end) - arc2);
    strait = between > kStraitArcs * std::max(g.segment_length1, length2) && between > kStraitRatio * chord;
  }
  return true;
}

bool FeatureSize::gap_search(const GapSearch& g, double& best2, std::int32_t& loop, bool& strait) const {
  const auto& segs = geometry_.segments;
  best2 = g.radius * g.radius;
  bool found = false;
  // Pruned by distance and by the half-plane.
  traverse(
      g.from, [&](const Node& n, double d2) { return d2 >= best2 || box_behind(n.box, g.from, g.ahead); },
      [&](std::int32_t si) {
        if (si == g.segment) return;  // a straight segment never faces itself
        Vec2 p2;
        double t = 0.0, d2 = 0.0;
        if (!ahead_point(segs[static_cast<std::size_t>(si)], g.from, g.ahead, p2, t, d2)) return;
        if (d2 >= best2) return;
        // Facing: another loop, or far enough along this one (decided at the candidate point).
        bool across = false;
        if (!faces(g, si, p2, t, across)) return;
        best2 = d2;
        found = true;
        loop = loop_[static_cast<std::size_t>(si)];
        strait = across;
      });
  return found;
}

double FeatureSize::width(Vec2 x, const ClosestHit& nearest, bool inside, double max_width, bool* apart) const {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  if (apart) *apart = false;
  GapSearch g;
  if (!gap_setup(x, nearest, inside, max_width, g)) return kNone;
  double best2 = 0.0;
  std::int32_t found_loop = -1;
  bool strait = false;
  if (!gap_search(g, best2, found_loop, strait)) return kNone;
  if (apart) *apart = found_loop != g.loop1 ? !touch(g.loop1, found_loop) : strait;
  return g.d1 + std::sqrt(best2);
}

// gap_search for m searches at once. One descent gathers the leaves whose boxes lie within
// R = max(radius + margin) of the bounding box of the searches' `from` points (a leaf farther holds no
// segment nearer than a search's radius, the margin covering the rounding). Each search then scans
// those leaves alone, skipping a leaf behind its half-plane (none of its segments has a part ahead:
// box_behind's rounded sum is at least each endpoint's) or beyond its best + margin (none of its
// segments can get within best). So each search finds m*, the least squared distance of all the
// segments that pass gap_search's tests, whatever the order; gap_search finds the same m* unless
// its pruning, which compares a leaf's box with the best exactly, skips the segment that gives it:
// possible only where rounding puts that segment's candidate point nearer than its leaf's box
// (`anomalous`). Both answers are then the same when some segment giving m* is not anomalous, and
// the loops and strait flags of all the segments giving m* agree (gap_search keeps the first it
// meets, in its own order): exact[i] says so, and the caller searches the others again with
// gap_search. Returns false (nothing written) for a group with a `from` not finite, or that gathers
// more than kGroupLeaves.
bool FeatureSize::gap_group(const GapSearch* g, std::size_t m, double* best2, std::int32_t* loop, bool* strait,
                            bool* found, bool* exact) const {
  const auto& segs = geometry_.segments;
  double margins[kGroup];
  Box group;
  double reach = 0.0;
  for (std::size_t i = 0; i < m; ++i) {
    if (!finite(g[i].from)) return false;
    margins[i] = margin(g[i].from);
    reach = std::max(reach, g[i].radius + margins[i]);
    group.add(g[i].from);
  }
  if (!(reach < std::numeric_limits<double>::infinity())) return false;
  const double reach2 = reach * reach;
  std::int32_t leaves[kGroupLeaves];
  const int count = leaves_near(group, reach2, leaves, kGroupLeaves);
  if (count < 0) return false;
  for (std::size_t i = 0; i < m; ++i) {
    const GapSearch& s = g[i];
    double b2 = s.radius * s.radius;
    double skip2 = (s.radius + margins[i]) * (s.radius + margins[i]);
    bool any = false, tie = false, sound = false, best_strait = false;
    std::int32_t best_loop = -1;
    for (int l = 0; l < count; ++l) {
      const Node& node = nodes_[static_cast<std::size_t>(leaves[l])];
      const double box2 = box_distance2(s.from, node.box);
      if (box2 > skip2 || box_behind(node.box, s.from, s.ahead)) continue;
      for (std::int32_t k = node.first; k < node.first + node.count; ++k) {
        const std::int32_t si = order_[static_cast<std::size_t>(k)];
        if (si == s.segment) continue;
        Vec2 p2;
        double t = 0.0, d2 = 0.0;
        if (!ahead_point(segs[static_cast<std::size_t>(si)], s.from, s.ahead, p2, t, d2)) continue;
        // A tie with the best found is examined too (its loop or strait flag may differ); radius^2
        // itself is not a gap.
        if (d2 > b2 || (d2 == b2 && !any)) continue;
        bool across = false;
        if (!faces(s, si, p2, t, across)) continue;
        const std::int32_t loop2 = loop_[static_cast<std::size_t>(si)];
        const bool anomalous = d2 < box2;
        if (d2 < b2) {
          b2 = d2;
          any = true;
          best_loop = loop2;
          best_strait = across;
          tie = false;
          sound = !anomalous;
          const double r = std::sqrt(b2) + margins[i];
          skip2 = r * r;
        } else {
          tie = tie || loop2 != best_loop || across != best_strait;
          sound = sound || !anomalous;
        }
      }
    }
    best2[i] = b2;
    loop[i] = best_loop;
    strait[i] = best_strait;
    found[i] = any;
    exact[i] = !any || (sound && !tie);
  }
  return true;
}

void FeatureSize::width_many(const WidthQuery* q, std::size_t n, double* width, bool* apart) const {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  GapSearch g[kGroup];
  std::size_t at[kGroup];
  std::size_t m = 0;
  // The pending searches g[0 .. m) of queries at[0 .. m): grouped where gap_group answers exactly,
  // the rest one by one.
  const auto run = [&] {
    double best2[kGroup];
    std::int32_t loop[kGroup];
    bool strait[kGroup], found[kGroup], exact[kGroup];
    const bool grouped = m > 1 && gap_group(g, m, best2, loop, strait, found, exact);
    for (std::size_t k = 0; k < m; ++k) {
      if (!grouped || !exact[k]) found[k] = gap_search(g[k], best2[k], loop[k], strait[k]);
      if (!found[k]) continue;
      apart[at[k]] = loop[k] != g[k].loop1 ? !touch(g[k].loop1, loop[k]) : strait[k];
      width[at[k]] = g[k].d1 + std::sqrt(best2[k]);
    }
    m = 0;
  };
  for (std::size_t i = 0; i < n; ++i) {
    width[i] = kNone;
    apart[i] = false;
    if (!gap_setup(q[i].x, q[i].nearest, q[i].inside, q[i].max_width, g[m])) continue;
    at[m++] = i;
    if (m == kGroup) run();
  }
  if (m > 0) run();
}

}  // namespace pdmesh
