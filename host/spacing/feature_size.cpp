// FeatureSize: inward normals and loop arc positions of the segments, a bounding-volume hierarchy over
// them, and the query for the closest boundary point ahead of a point that faces its closest point.
#include "spacing/feature_size.hpp"

#include <algorithm>
#include <cmath>
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

ClosestHit FeatureSize::closest(Vec2 x, int hint) const {
  ClosestHit best;
  double best2 = std::numeric_limits<double>::infinity();
  // Nodes and segments whose bounding box lies farther than best.distance + margin are skipped: their
  // distance exceeds the best by far more than either's rounding (~50 ulps of the coordinates'
  // magnitude) and closest_on_segment's snap to 0 (1e-12 of it), so their squared distance is
  // strictly larger and they could neither win nor tie. Every segment that could is measured,
  // whatever the order, so the answer is the least squared distance, then the lowest index, whichever
  // segment seeds the search.
  const double margin = 1e-11 * std::max({scale_, std::fabs(x.x), std::fabs(x.y)});
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

double FeatureSize::width(Vec2 x, const ClosestHit& nearest, bool inside, double max_width, bool* apart) const {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  if (apart) *apart = false;
  if (nearest.segment < 0 || !(max_width > 0.0)) return kNone;
  const Vec2 p1 = nearest.point;
  // Ahead: inside, away from p1 through x; otherwise from p1 along its segment's inward normal.
  Vec2 from = x, ahead;
  double d1 = 0.0;
  if (inside && nearest.distance > 0.0) {
    d1 = nearest.distance;
    ahead = (1.0 / d1) * (x - p1);
  } else {
    from = p1;
    ahead = normal_[static_cast<std::size_t>(nearest.segment)];
  }
  const double radius = max_width - d1;
  if (!(radius > 0.0)) return kNone;
  const std::int32_t loop1 = loop_[static_cast<std::size_t>(nearest.segment)];
  const double arc1 = loop_arc(nearest.segment, nearest.t);
  const double length1 = loop_length_[static_cast<std::size_t>(loop1)];
  const auto& segs = geometry_.segments;
  double best2 = radius * radius;
  bool found = false;
  std::int32_t found_loop = -1;
  // Pruned by distance and by the half-plane.
  traverse(
      from, [&](const Node& n, double d2) { return d2 >= best2 || box_behind(n.box, from, ahead); },
      [&](std::int32_t si) {
        if (si == nearest.segment) return;  // a straight segment never faces itself
        const Segment& s = segs[static_cast<std::size_t>(si)];
        // The part of the segment strictly ahead: h(t) = ahead . (a + t (b - a) - from) > 0.
        const double ha = dot(ahead, s.a - from), hb = dot(ahead, s.b - from);
        if (ha <= 0.0 && hb <= 0.0) return;
        double t0 = 0.0, t1 = 1.0;
        if (ha <= 0.0) t0 = ha / (ha - hb);
        if (hb <= 0.0) t1 = ha / (ha - hb);
        const Vec2 d = s.b - s.a;
        const double len2 = norm2(d);
        const double t = std::clamp(len2 > 0.0 ? dot(from - s.a, d) / len2 : 0.0, t0, t1);
        const Vec2 p2 = s.a + t * d;
        const double d2 = norm2(p2 - from);
        if (d2 >= best2) return;
        // Facing: another loop, or far enough along this one (decided at the candidate point).
        const std::int32_t loop2 = loop_[static_cast<std::size_t>(si)];
        if (loop2 != loop1 && !junctions_.empty() && junction_corner(loop1, loop2, p1, p2, dist(p1, p2))) return;
        if (loop2 == loop1) {
          // p2 == p1 (a neighbour segment's shared vertex) is no gap, however the two arc positions round.
          const double chord = dist(p1, p2);
          const double along = std::fabs(loop_arc(si, t) - arc1);
          const double arc = std::min(along, length1 - along);
          if (!(chord > 0.0) || !(arc > kArcRatio * chord)) return;
        }
        best2 = d2;
        found = true;
        found_loop = loop2;
      });
  if (!found) return kNone;
  if (apart) *apart = found_loop != loop1 && !touch(loop1, found_loop);
  return d1 + std::sqrt(best2);
}

}  // namespace pdmesh
