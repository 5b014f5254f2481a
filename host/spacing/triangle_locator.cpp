// TriangleLocator: quadtrees over triangle and boundary-edge boxes, exact containment tests.
#include "spacing/triangle_locator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/predicates.hpp"
#include "geometry/hilbert.hpp"

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

namespace {

struct Pending {
  int node;
  Box box;
  int level;
  std::vector<std::int32_t> items;
};

}  // namespace

// Splits node's items down to leaves, depth first, children pushed in reverse so that leaves are
// numbered in child order.
static void build_subtree(BoxTree& t, const std::vector<Box>& boxes, Pending first) {
  std::vector<Pending> stack;
  stack.push_back(std::move(first));
  while (!stack.empty()) {
    Pending n = std::move(stack.back());
    stack.pop_back();
    bool split = n.items.size() > static_cast<std::size_t>(BoxTree::kLeafCapacity) && n.level < BoxTree::kMaxDepth;
    std::vector<std::int32_t> parts[4];
    if (split) {
      for (int c = 0; c < 4; ++c) {
        const Box cb = child_box(n.box, c);
        for (std::int32_t i : n.items)
          if (overlaps(boxes[static_cast<std::size_t>(i)], cb)) parts[c].push_back(i);
      }
      // Splitting must pay. Once the cell is about as small as its items, most of them overlap
      // several children (around a mesh vertex a dozen triangle boxes overlap any point); and items
      // that all meet the cell in one point (boxes touching its corner) all go to one child. Either
      // way splitting further would copy them down to kMaxDepth.
      std::size_t total = 0, largest = 0;
      for (const auto& p : parts) {
        total += p.size();
        largest = std::max(largest, p.size());
      }
      split = largest < n.items.size() &&
              static_cast<double>(total) <= BoxTree::kMaxDuplication * static_cast<double>(n.items.size());
    }
    if (!split) {
      t.node_child[static_cast<std::size_t>(n.node)] = -1 - static_cast<std::int32_t>(t.leaf_start.size() - 1);
      t.items.insert(t.items.end(), n.items.begin(), n.items.end());
      t.leaf_start.push_back(static_cast<std::int32_t>(t.items.size()));
      t.depth = std::max(t.depth, n.level);
      continue;
    }
    const auto first_child = static_cast<std::int32_t>(t.node_child.size());
    t.node_child[static_cast<std::size_t>(n.node)] = first_child;
    t.node_child.resize(t.node_child.size() + 4, -1);
    for (int c = 3; c >= 0; --c)
      stack.push_back({first_child + c, child_box(n.box, c), n.level + 1, std::move(parts[c])});
  }
}

void BoxTree::build(const std::vector<Box>& boxes, bool grid) {
  root = Box{};
  for (const Box& b : boxes) {
    root.add(b.lo);
    root.add(b.hi);
  }
  node_child.clear();
  leaf_start.assign(1, 0);
  items.clear();
  root_node.clear();
  depth = 0;
  single_root = !grid || boxes.empty() || !(root.width() > 0.0 && root.height() > 0.0);
  if (single_root) {
    gx = gy = 1;
    root_node.push_back(0);
    node_child.push_back(-1);
    std::vector<std::int32_t> all(boxes.size());
    for (std::size_t i = 0; i < boxes.size(); ++i) all[i] = static_cast<std::int32_t>(i);
    build_subtree(*this, boxes, {0, root, 0, std::move(all)});
    return;
  }
  // Cells of a power-of-two side, about kItemsPerCell items each, at most kMaxCells of them, and
  // at most 4 per item (and 64): a long thin mesh (one far point) would otherwise get a row of
  // millions of empty cells for a few dozen triangles.
  const double target = std::max(1.0, static_cast<double>(boxes.size()) / kItemsPerCell);
  const double most = std::min(static_cast<double>(kMaxCells), 64.0 + 4.0 * static_cast<double>(boxes.size()));
  cell = std::exp2(std::ceil(std::log2(std::sqrt(root.width() * root.height() / target))));
  for (;;) {
    inv_cell = 1.0 / cell;
    i0 = std::floor(root.lo.x * inv_cell);
    j0 = std::floor(root.lo.y * inv_cell);
    const double nx = std::floor(root.hi.x * inv_cell) - i0 + 1, ny = std::floor(root.hi.y * inv_cell) - j0 + 1;
    if (nx * ny <= most) {
      gx = static_cast<int>(nx);
      gy = static_cast<int>(ny);
      break;
    }
    cell *= 2.0;
  }
  root = Box{{i0 * cell, j0 * cell}, {(i0 + gx) * cell, (j0 + gy) * cell}};
  // Bin the items into the cells their boxes' corners fall in (counting sort: counts, offsets, fill).
  const auto cells = static_cast<std::size_t>(gx) * static_cast<std::size_t>(gy);
  std::vector<std::size_t> start(cells + 1, 0);
  const auto range = [&](const Box& b, int& x0, int& x1, int& y0, int& y1) {
    x0 = static_cast<int>(std::floor(b.lo.x * inv_cell) - i0);
    x1 = static_cast<int>(std::floor(b.hi.x * inv_cell) - i0);
    y0 = static_cast<int>(std::floor(b.lo.y * inv_cell) - j0);
    y1 = static_cast<int>(std::floor(b.hi.y * inv_cell) - j0);
  };
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::int32_t> binned(pass == 0 ? 0 : start[cells]);
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      int x0, x1, y0, y1;
      range(boxes[i], x0, x1, y0, y1);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const auto c = static_cast<std::size_t>(y) * static_cast<std::size_t>(gx) + static_cast<std::size_t>(x);
          if (pass == 0) {
            ++start[c + 1];
          } else {
            binned[fill[c]++] = static_cast<std::int32_t>(i);
          }
        }
    }
    if (pass == 0) {
      for (std::size_t c = 0; c < cells; ++c) start[c + 1] += start[c];
      continue;
    }
    root_node.resize(cells);
    for (std::size_t c = 0; c < cells; ++c) {
      const auto node = static_cast<std::int32_t>(node_child.size());
      node_child.push_back(-1);
      root_node[c] = node;
      const double x = (i0 + static_cast<double>(c % static_cast<std::size_t>(gx))) * cell;
      const double y = (j0 + static_cast<double>(c / static_cast<std::size_t>(gx))) * cell;
      build_subtree(*this, boxes,
                    {node, Box{{x, y}, {x + cell, y + cell}}, 0,
                     std::vector<std::int32_t>(binned.begin() + static_cast<long>(start[c]),
                                               binned.begin() + static_cast<long>(start[c + 1]))});
    }
  }
}

int BoxTree::leaf_of(Vec2 p) const {
  Box b;
  int node;
  if (single_root) {
    if (!root.contains(p)) return -1;
    b = root;
    node = root_node[0];
  } else {
    const double fx = std::floor(p.x * inv_cell) - i0, fy = std::floor(p.y * inv_cell) - j0;
    if (!(fx >= 0.0 && fx < gx && fy >= 0.0 && fy < gy)) return -1;  // also false for NaN
    b.lo = {(i0 + fx) * cell, (j0 + fy) * cell};
    b.hi = {b.lo.x + cell, b.lo.y + cell};
    node = root_node[static_cast<std::size_t>(fy) * static_cast<std::size_t>(gx) + static_cast<std::size_t>(fx)];
  }
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
  return sizeof(std::int32_t) * (root_node.size() + node_child.size() + leaf_start.size() + items.size());
}

TriangleLocator::TriangleLocator(const std::vector<Vec2>& points, const std::vector<std::array<int, 3>>& triangles,
                                 const std::vector<double>& values)
    : points_(points) {
  std::vector<Vec2> centroids(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    Vec2 c{0.0, 0.0};
    for (int v : triangles[t]) c = c + points[static_cast<std::size_t>(v)];
    centroids[t] = (1.0 / 3.0) * c;
  }
  order_ = hilbert_order(centroids);
  position_of_.assign(triangles.size(), 0);
  corners_.resize(kStride * triangles.size());
  std::vector<Box> boxes(triangles.size());
  for (std::size_t pos = 0; pos < order_.size(); ++pos) {
    const auto t = static_cast<std::size_t>(order_[pos]);
    position_of_[t] = static_cast<int>(pos);
    for (std::size_t k = 0; k < 3; ++k) {
      const auto v = static_cast<std::size_t>(triangles[t][k]);
      corners_[kStride * pos + 3 * k] = points[v].x;
      corners_[kStride * pos + 3 * k + 1] = points[v].y;
      corners_[kStride * pos + 3 * k + 2] = values.empty() ? 0.0 : values[v];
      boxes[pos].add(points[v]);
    }
  }
  triangle_tree_.build(boxes, true);

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
  std::sort(edges.begin(), edges.end(),
            [](const Directed& x, const Directed& y) { return x.key != y.key ? x.key < y.key : x.t < y.t; });
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
  edge_tree_.build(boxes, false);
}

// Closed containment: p is on the left of, or on, each counter-clockwise edge.
bool TriangleLocator::contains(std::size_t position, Vec2 p, double w[3]) const {
  const double* c = corners_.data() + kStride * position;
  const Vec2 a{c[0], c[1]}, b{c[3], c[4]}, d{c[6], c[7]};
  if ((w[0] = orient2d(b, d, p)) < 0.0) return false;
  if ((w[1] = orient2d(d, a, p)) < 0.0) return false;
  return (w[2] = orient2d(a, b, p)) >= 0.0;
}

bool TriangleLocator::strictly_inside(int position, Vec2 p, Located& out) const {
  if (!contains(static_cast<std::size_t>(position), p, out.w) ||
      !(out.w[0] > 0.0 && out.w[1] > 0.0 && out.w[2] > 0.0)) {
    return false;
  }
  out.position = position;
  out.triangle = order_[static_cast<std::size_t>(position)];
  return true;
}

Located TriangleLocator::locate(Vec2 p) const {
  Located out;
  const int leaf = triangle_tree_.leaf_of(p);
  if (leaf < 0) return out;
  const auto begin = static_cast<std::size_t>(triangle_tree_.leaf_start[static_cast<std::size_t>(leaf)]);
  const auto end = static_cast<std::size_t>(triangle_tree_.leaf_start[static_cast<std::size_t>(leaf) + 1]);
  // The leaf's triangles are near each other in the Hilbert order but not adjacent: ask for all their
  // cache lines at once, so that the misses overlap instead of coming one per test.
  for (std::size_t i = begin; i < end; ++i) {
    __builtin_prefetch(corners_.data() + kStride * static_cast<std::size_t>(triangle_tree_.items[i]));
  }
  for (std::size_t i = begin; i < end; ++i) {
    const auto position = static_cast<std::size_t>(triangle_tree_.items[i]);
    if (contains(position, p, out.w)) {
      out.position = static_cast<int>(position);
      out.triangle = order_[position];
      return out;
    }
  }
  return out;
}

// The weights are orient2d values, all >= 0 with a positive sum (the triangle has positive area and
// holds the point). The clamp keeps rounding from leaving the corner values' range.
double TriangleLocator::interpolate(const Located& l) const {
  const double* c = corners_.data() + kStride * static_cast<std::size_t>(l.position);
  const double v = (l.w[0] * c[2] + l.w[1] * c[5] + l.w[2] * c[8]) / (l.w[0] + l.w[1] + l.w[2]);
  return std::clamp(v, std::min({c[2], c[5], c[8]}), std::max({c[2], c[5], c[8]}));
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
  nearest_in(edge_tree_.root_node[0], edge_tree_.root, p, best);
  return best;
}

LocatorStats TriangleLocator::stats() const {
  LocatorStats s;
  s.cells = triangle_tree_.root_node.size();
  s.nodes = triangle_tree_.node_child.size();
  s.leaves = triangle_tree_.leaf_start.size() - 1;
  s.references = triangle_tree_.items.size();
  s.boundary_edges = boundary_edges_.size();
  s.depth = triangle_tree_.depth;
  s.bytes = triangle_tree_.bytes() + edge_tree_.bytes() + boundary_edges_.size() * sizeof(boundary_edges_[0]) +
            sizeof(double) * corners_.size() + sizeof(int) * (order_.size() + position_of_.size());
  return s;
}

}  // namespace pdmesh
