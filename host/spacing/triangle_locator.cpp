// TriangleLocator: quadtrees over triangle and boundary-edge boxes, exact containment tests.
#include "spacing/triangle_locator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/predicates.hpp"

namespace pdmesh {
namespace {

Box child_box(const Box& b, int child) {
  const Vec2 mid{0.5 * (b.lo.x + b.hi.x), 0.5 * (b.lo.y + b.hi.y)};
  Box c;
  c.lo = {(child & 1) ? mid.x : b.lo.x, (child & 2) ? mid.y : b.lo.y};
  c.hi = {(child & 1) ? b.hi.x : mid.x, (child & 2) ? b.hi.y : mid.y};
  return c;
}

bool overlaps(const Box& a, const Box& b) {
  return a.lo.x <= b.hi.x && a.hi.x >= b.lo.x && a.lo.y <= b.hi.y && a.hi.y >= b.lo.y;
}

double box_distance2(const Box& b, Vec2 p) {
  const double dx = p.x < b.lo.x ? b.lo.x - p.x : p.x > b.hi.x ? p.x - b.hi.x : 0.0;
  const double dy = p.y < b.lo.y ? b.lo.y - p.y : p.y > b.hi.y ? p.y - b.hi.y : 0.0;
  return dx * dx + dy * dy;
}

}  // namespace

void BoxTree::build(const std::vector<Box>& boxes) {
  root = Box{};
  for (const Box& b : boxes) {
    root.add(b.lo);
    root.add(b.hi);
  }
  node_child.assign(1, -1);
  leaf_start.assign(1, 0);
  items.clear();
  depth = 0;
  struct Pending {
    int node;
    Box box;
    int level;
    std::vector<std::int32_t> items;
  };
  std::vector<Pending> stack;
  std::vector<std::int32_t> all(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) all[i] = static_cast<std::int32_t>(i);
  stack.push_back({0, root, 0, std::move(all)});
  // Depth first, children pushed in reverse so that leaves are numbered in child order.
  while (!stack.empty()) {
    Pending n = std::move(stack.back());
    stack.pop_back();
    bool split = n.items.size() > static_cast<std::size_t>(kLeafCapacity) && n.level < kMaxDepth;
    std::vector<std::int32_t> parts[4];
    if (split) {
      for (int c = 0; c < 4; ++c) {
        const Box cb = child_box(n.box, c);
        for (std::int32_t i : n.items)
          if (overlaps(boxes[static_cast<std::size_t>(i)], cb)) parts[c].push_back(i);
      }
      // Splitting must make progress: items that all straddle the midpoints (or share one point)
      // would otherwise be copied down to kMaxDepth.
      std::size_t largest = 0;
      for (const auto& p : parts) largest = std::max(largest, p.size());
      split = largest < n.items.size();
    }
    if (!split) {
      node_child[static_cast<std::size_t>(n.node)] = -1 - static_cast<std::int32_t>(leaf_start.size() - 1);
      items.insert(items.end(), n.items.begin(), n.items.end());
      leaf_start.push_back(static_cast<std::int32_t>(items.size()));
      depth = std::max(depth, n.level);
      continue;
    }
    const auto first = static_cast<std::int32_t>(node_child.size());
    node_child[static_cast<std::size_t>(n.node)] = first;
    node_child.resize(node_child.size() + 4, -1);
    for (int c = 3; c >= 0; --c) stack.push_back({first + c, child_box(n.box, c), n.level + 1, std::move(parts[c])});
  }
}

int BoxTree::leaf_of(Vec2 p) const {
  if (!root.contains(p)) return -1;
  Box b = root;
  int node = 0;
  while (node_child[static_cast<std::size_t>(node)] >= 0) {
    const Vec2 mid{0.5 * (b.lo.x + b.hi.x), 0.5 * (b.lo.y + b.hi.y)};
    const int c = (p.x >= mid.x ? 1 : 0) + (p.y >= mid.y ? 2 : 0);
    (c & 1 ? b.lo.x : b.hi.x) = mid.x;
    (c & 2 ? b.lo.y : b.hi.y) = mid.y;
    node = node_child[static_cast<std::size_t>(node)] + c;
  }
  return -1 - node_child[static_cast<std::size_t>(node)];
}

std::size_t BoxTree::bytes() const {
  return sizeof(std::int32_t) * (node_child.size() + leaf_start.size() + items.size());
}

TriangleLocator::TriangleLocator(const std::vector<Vec2>& points, const std::vector<std::array<int, 3>>& triangles)
    : points_(points), triangles_(triangles) {
  std::vector<Box> boxes(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int v : triangles[t]) boxes[t].add(points[static_cast<std::size_t>(v)]);
  triangle_tree_.build(boxes);

  // Sorting the directed edges by their (min, max) point pair brings each next to its twin: an edge
  // used once is on the boundary; twice in opposite directions, interior; anything else a conflict.
  struct Directed {
    std::uint64_t key;
    int a, b, t;
  };
  std::vector<Directed> edges;
  edges.reserve(3 * triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (std::size_t k = 0; k < 3; ++k) {
      const int a = triangles[t][k], b = triangles[t][(k + 1) % 3];
      const auto lo = static_cast<std::uint64_t>(std::min(a, b)), hi = static_cast<std::uint64_t>(std::max(a, b));
      edges.push_back({(lo << 32) | hi, a, b, static_cast<int>(t)});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Directed& x, const Directed& y) {
    return x.key != y.key ? x.key < y.key : x.t < y.t;
  });
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    if (j - i == 1) {
      boundary_edges_.push_back({edges[i].a, edges[i].b});
    } else if (conflict_.first < 0 && (j - i > 2 || edges[i].a == edges[i + 1].a)) {
      conflict_ = {edges[i].a, edges[i].b, edges[i].t, edges[i + 1].t, j - i == 2};
    }
    i = j;
  }
  boxes.assign(boundary_edges_.size(), Box{});
  for (std::size_t e = 0; e < boundary_edges_.size(); ++e)
    for (int v : boundary_edges_[e]) boxes[e].add(points[static_cast<std::size_t>(v)]);
  edge_tree_.build(boxes);
}

// Closed containment: p is on the left of, or on, each counter-clockwise edge.
bool TriangleLocator::contains(int t, Vec2 p, double w[3]) const {
  const auto& tri = triangles_[static_cast<std::size_t>(t)];
  const Vec2 a = points_[static_cast<std::size_t>(tri[0])];
  const Vec2 b = points_[static_cast<std::size_t>(tri[1])];
  const Vec2 c = points_[static_cast<std::size_t>(tri[2])];
  if ((w[0] = orient2d(b, c, p)) < 0.0) return false;
  if ((w[1] = orient2d(c, a, p)) < 0.0) return false;
  return (w[2] = orient2d(a, b, p)) >= 0.0;
}

bool TriangleLocator::strictly_inside(int t, Vec2 p, double w[3]) const {
  return contains(t, p, w) && w[0] > 0.0 && w[1] > 0.0 && w[2] > 0.0;
}

Located TriangleLocator::locate(Vec2 p) const {
  Located out;
  const int leaf = triangle_tree_.leaf_of(p);
  if (leaf < 0) return out;
  const auto begin = static_cast<std::size_t>(triangle_tree_.leaf_start[static_cast<std::size_t>(leaf)]);
  const auto end = static_cast<std::size_t>(triangle_tree_.leaf_start[static_cast<std::size_t>(leaf) + 1]);
  for (std::size_t i = begin; i < end; ++i) {
    const int t = triangle_tree_.items[i];
    if (contains(t, p, out.w)) {
      out.triangle = t;
      return out;
    }
  }
  return out;
}

std::pair<const std::int32_t*, const std::int32_t*> TriangleLocator::triangles_near(Vec2 p) const {
  const int leaf = triangle_tree_.leaf_of(p);
  if (leaf < 0) return {nullptr, nullptr};
  const std::int32_t* items = triangle_tree_.items.data();
  return {items + triangle_tree_.leaf_start[static_cast<std::size_t>(leaf)],
          items + triangle_tree_.leaf_start[static_cast<std::size_t>(leaf) + 1]};
}

void TriangleLocator::nearest_in(int node, const Box& box, Vec2 p, BoundaryHit& best) const {
  const std::int32_t child = edge_tree_.node_child[static_cast<std::size_t>(node)];
  if (child < 0) {
    const auto leaf = static_cast<std::size_t>(-1 - child);
    for (auto i = static_cast<std::size_t>(edge_tree_.leaf_start[leaf]);
         i < static_cast<std::size_t>(edge_tree_.leaf_start[leaf + 1]); ++i) {
      const int e = edge_tree_.items[i];
      const Vec2 a = points_[static_cast<std::size_t>(boundary_edges_[static_cast<std::size_t>(e)][0])];
      const Vec2 b = points_[static_cast<std::size_t>(boundary_edges_[static_cast<std::size_t>(e)][1])];
      const Vec2 ab = b - a;
      const double t = std::clamp(dot(p - a, ab) / norm2(ab), 0.0, 1.0);
      const double d = dist(p, a + t * ab);
      if (d < best.distance || (d == best.distance && e < best.edge)) best = {e, t, d};
    }
    return;
  }
  // Nearer children first, so that the far ones are usually pruned.
  int order[4] = {0, 1, 2, 3};
  double d2[4];
  Box boxes[4];
  for (int c = 0; c < 4; ++c) {
    boxes[c] = child_box(box, c);
    d2[c] = box_distance2(boxes[c], p);
  }
  std::sort(order, order + 4, [&](int x, int y) { return d2[x] != d2[y] ? d2[x] < d2[y] : x < y; });
  for (int c : order) {
    // <= keeps equally distant children, where a lower-index edge at the same distance may be.
    if (d2[c] <= best.distance * best.distance) nearest_in(child + c, boxes[c], p, best);
  }
}

BoundaryHit TriangleLocator::nearest_boundary(Vec2 p) const {
  BoundaryHit best;
  best.distance = std::numeric_limits<double>::infinity();
  if (boundary_edges_.empty()) return best;
  nearest_in(0, edge_tree_.root, p, best);
  return best;
}

LocatorStats TriangleLocator::stats() const {
  LocatorStats s;
  s.nodes = triangle_tree_.node_child.size();
  s.leaves = triangle_tree_.leaf_start.size() - 1;
  s.references = triangle_tree_.items.size();
  s.boundary_edges = boundary_edges_.size();
  s.depth = triangle_tree_.depth;
  s.bytes = triangle_tree_.bytes() + edge_tree_.bytes() + boundary_edges_.size() * sizeof(boundary_edges_[0]);
  return s;
}

}  // namespace pdmesh
