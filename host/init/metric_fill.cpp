// The initial nodes of a metric run; see metric_fill.hpp.
#include "init/metric_fill.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <vector>

#include <fmt/format.h>

#include "core/errors.hpp"

namespace pdmesh {
namespace {

constexpr double kPi = 3.14159265358979323846;
// The grid's cells hold about this many nodes on average (from the metric's sampled node count).
constexpr double kNodesPerCell = 1.0;
// Samples per side of the bounding box for that count.
constexpr int kCountSamples = 64;
constexpr int kMaxCellsPerSide = 2048;

// The metric distance from p to segment [a, b] in the metric m: the segment mapped by m^(1/2) is a
// segment, so the closest point is at t = clamp(<p - a, b - a>_m / |b - a|_m^2, 0, 1).
double metric_distance_to_segment(const Metric& m, Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 d = b - a, w = p - a;
  const double dd = m.quad(d);
  const double wd = m.m11 * w.x * d.x + m.m12 * (w.x * d.y + w.y * d.x) + m.m22 * w.y * d.y;
  const double t = dd > 0.0 ? std::clamp(wd / dd, 0.0, 1.0) : 0.0;
  return m.length(w - t * d);
}

// Whether p clears the curves by `clearance` in the metric m: the closest segment of each curve and its
// neighbours along the curve (the closest in the metric can be a neighbour of the closest in length).
bool clears_curves_in(const GeometryTree& tree, const Metric& m, Vec2 p, double clearance,
                      std::vector<ClosestHit>& hits) {
  const Geometry& geometry = tree.geometry();
  tree.closest_per_curve(p, hits);
  for (const ClosestHit& hit : hits) {
    if (hit.segment < 0) continue;
    const Segment& s = geometry.segments[static_cast<std::size_t>(hit.segment)];
    const Curve& curve = geometry.curves[static_cast<std::size_t>(s.curve)];
    for (int k = std::max(0, s.index - 2); k <= std::min(curve.segment_count() - 1, s.index + 2); ++k) {
      const Segment& t = geometry.segments[static_cast<std::size_t>(curve.first_segment + k)];
      if (metric_distance_to_segment(m, p, t.a, t.b) < clearance) return false;
    }
  }
  return true;
}

// Nodes by grid cell over the geometry's bounding box, for the fill's spacing test.
class NodeGrid {
 public:
  NodeGrid(Vec2 lo, Vec2 hi, double cell) : lo_(lo), cell_(cell) {
    nx_ = std::clamp(static_cast<int>(std::ceil((hi.x - lo.x) / cell)), 1, kMaxCellsPerSide);
    ny_ = std::clamp(static_cast<int>(std::ceil((hi.y - lo.y) / cell)), 1, kMaxCellsPerSide);
    cells_.resize(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_));
  }
  void add(Vec2 p, int id) { cells_[index(col(p.x - lo_.x), row(p.y - lo_.y))].push_back(id); }
  // Whether any node lies in `m` closer than r to p (nodes within the ellipse's bounding box checked).
  bool any_within(const std::vector<Vec2>& x, const Metric& m, Vec2 p, double r) const {
    const double det = m.det();
    const double wx = r * std::sqrt(m.m22 / det), wy = r * std::sqrt(m.m11 / det);
    const int c0 = col(p.x - wx - lo_.x), c1 = col(p.x + wx - lo_.x);
    const int r0 = row(p.y - wy - lo_.y), r1 = row(p.y + wy - lo_.y);
    const double r2 = r * r;
    for (int j = r0; j <= r1; ++j)
      for (int i = c0; i <= c1; ++i)
        for (const int id : cells_[index(i, j)])
          if (m.quad(x[static_cast<std::size_t>(id)] - p) < r2) return true;
    return false;
  }

 private:
  int col(double dx) const { return std::clamp(static_cast<int>(std::floor(dx / cell_)), 0, nx_ - 1); }
  int row(double dy) const { return std::clamp(static_cast<int>(std::floor(dy / cell_)), 0, ny_ - 1); }
  std::size_t index(int i, int j) const {
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(i);
  }
  Vec2 lo_;
  double cell_;
  int nx_ = 1, ny_ = 1;
  std::vector<std::vector<int>> cells_;
};

// The bounding box of the geometry's segments.
void bounds(const Geometry& g, Vec2& lo, Vec2& hi) {
  lo = {INFINITY, INFINITY};
  hi = {-INFINITY, -INFINITY};
  for (const Segment& s : g.segments)
    for (const Vec2 p : {s.a, s.b}) {
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
    }
}

// A grid cell side for about kNodesPerCell nodes per cell: the node count of the box, 2 / sqrt(3)
// integral sqrt(det M) dA, by the midpoint rule on kCountSamples^2 cells.
template <class MetricAt>
double cell_side(const MetricAt& metric_at, Vec2 lo, Vec2 hi) {
  const double w = hi.x - lo.x, h = hi.y - lo.y;
  double c = 0.0;
  for (int j = 0; j < kCountSamples; ++j)
    for (int i = 0; i < kCountSamples; ++i) {
      const Vec2 p{lo.x + (i + 0.5) / kCountSamples * w, lo.y + (j + 0.5) / kCountSamples * h};
      c += std::sqrt(metric_at(p).det());
    }
  const double area = w * h;
  const double count = 2.0 / std::sqrt(3.0) * c * area / (kCountSamples * kCountSamples);
  const double side = std::sqrt(area * kNodesPerCell / std::max(count, 1.0));
  return std::max(side, std::max(w, h) / kMaxCellsPerSide);
}

}  // namespace

double CurveMetricSpacing::at(Vec2 p) const {
  const ClosestHit hit = tree_.closest(p);
  const Metric m = metric_.at(p);
  if (hit.segment < 0) return 1.0 / std::sqrt(std::sqrt(m.det()));
  const Segment& s = tree_.geometry().segments[static_cast<std::size_t>(hit.segment)];
  const Vec2 d = s.b - s.a;
  const double len = norm(d);
  return len / m.length(d);
}

std::size_t metric_fill(const GeometryTree& tree, const MetricField& metric, const SpacingField& q, NodeSet& nodes,
                        const MetricFillOptions& options) {
  const Geometry& geometry = tree.geometry();
  if (geometry.segments.empty()) return 0;
  Vec2 lo, hi;
  bounds(geometry, lo, hi);
  NodeGrid grid(lo, hi, cell_side([&metric](Vec2 p) { return metric.at(p); }, lo, hi));
  for (std::size_t i = 0; i < nodes.size(); ++i) grid.add(nodes.x[i], static_cast<int>(i));

  std::vector<ClosestHit> hits;
  const auto clears_curves = [&](const Metric& m, Vec2 p) {
    return clears_curves_in(tree, m, p, options.boundary_clearance, hits);
  };

  // One lattice grown from one seed (the middle node of the curve with the most nodes), so that it
  // is coherent wherever the metric lets it be; the other boundary nodes are obstacles, and seeds in
  // turn only where the lattice has not reached (a region cut off from the first seed).
  const std::size_t boundary = nodes.size();
  std::vector<char> expanded(boundary, 0);
  std::size_t seed = 0;
  {
    std::size_t most = 0;
    for (const std::vector<int>& list : nodes.curve_nodes)
      if (list.size() > most) {
        most = list.size();
        seed = static_cast<std::size_t>(list[list.size() / 2]);
      }
  }
  std::deque<int> front;
  std::size_t next_seed = 0;
  if (options.grow_from_interior)
    for (std::size_t i = 0; i < boundary; ++i)
      if (nodes.kind[i] == NodeKind::Interior) front.push_back(static_cast<int>(i));
  if (front.empty() && boundary > 0) {
    front.push_back(static_cast<int>(seed));
  }
  std::size_t added = 0;
  for (;;) {
    if (front.empty()) {
      while (next_seed < boundary && (expanded[next_seed] || next_seed == seed)) ++next_seed;
      if (next_seed >= boundary) break;
      front.push_back(static_cast<int>(next_seed++));
    }
    const int from = front.front();
    front.pop_front();
    if (static_cast<std::size_t>(from) < boundary) {
      if (expanded[static_cast<std::size_t>(from)]) continue;
      expanded[static_cast<std::size_t>(from)] = 1;
    }
    const Vec2 p = nodes.x[static_cast<std::size_t>(from)];
    const MetricEigen e = eigen(metric.at(p));
    const double h_large = 1.0 / std::sqrt(e.lambda2), h_small = 1.0 / std::sqrt(e.lambda1);
    for (int k = 0; k < 6; ++k) {
      const double theta = k * kPi / 3.0;
      Vec2 step = (h_large * std::cos(theta)) * e.v2() + (h_small * std::sin(theta)) * e.v1();
      // One metric step measured at the step's midpoint.
      const Vec2 mid = p + 0.5 * step;
      if (!tree.inside(mid)) continue;
      step = (options.step / metric.at(mid).length(step)) * step;
      const Vec2 c = p + step;
      if (!tree.inside(c) || tree.crosses_boundary(p, c)) continue;
      const Metric mc = metric.at(c);
      if (grid.any_within(nodes.x, mc, c, options.min_distance) || !clears_curves(mc, c)) continue;
      if (options.max_nodes > 0 && added >= options.max_nodes)
        throw LimitError(
            fmt::format("the metric field asks for more than --max-nodes {} nodes (the interior fill at unit metric "
                        "spacing); coarsen the metric or raise --max-nodes",
                        options.max_nodes));
      const int id = nodes.add(c, q.at(c), NodeKind::Interior, -1);
      grid.add(c, id);
      front.push_back(id);
      ++added;
    }
  }
  return added;
}

std::size_t warm_fill(const GeometryTree& tree, const MetricField* metric, const SpacingField& q, NodeSet& nodes,
                      const std::vector<Vec2>& points, const MetricFillOptions& options) {
  const Geometry& geometry = tree.geometry();
  if (geometry.segments.empty()) return 0;
  const auto metric_at = [metric, &q](Vec2 p) {
    if (metric != nullptr) return metric->at(p);
    const double s = q.at(p);
    return Metric{1.0 / (s * s), 0.0, 1.0 / (s * s)};
  };
  Vec2 lo, hi;
  bounds(geometry, lo, hi);
  NodeGrid grid(lo, hi, cell_side(metric_at, lo, hi));
  for (std::size_t i = 0; i < nodes.size(); ++i) grid.add(nodes.x[i], static_cast<int>(i));
  std::vector<ClosestHit> hits;
  std::size_t added = 0;
  for (const Vec2 p : points) {
    if (!tree.inside(p)) continue;
    const Metric m = metric_at(p);
    if (grid.any_within(nodes.x, m, p, options.min_distance) ||
        !clears_curves_in(tree, m, p, options.boundary_clearance, hits))
      continue;
    if (options.max_nodes > 0 && added >= options.max_nodes)
      throw LimitError(
          fmt::format("init.file: more than --max-nodes {} interior nodes; raise --max-nodes", options.max_nodes));
    grid.add(p, nodes.add(p, q.at(p), NodeKind::Interior, -1));
    ++added;
  }
  return added;
}

}  // namespace pdmesh
