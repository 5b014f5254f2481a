// BackgroundSpacing: builds the adaptive quadtree of corner samples and domain tags from an exact
// spacing field and the geometry tree, and looks points up in it (see docs/spacing.md).
#include "spacing/background_field.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <fmt/format.h>

#include "core/errors.hpp"

namespace pdmesh {

std::size_t BackgroundFieldData::bytes() const {
  return sizeof(std::int32_t) *
             (root_node.size() + node_child.size() + leaf_corner.size() + leaf_tag.size() + leaf_cell.size()) +
         sizeof(double) * corner_q.size();
}

int background_locate(const BackgroundFieldData& d, Vec2 p, double& u, double& v) {
  // Written so that NaN lands in cell 0 at u = 0 (every comparison with NaN is false).
  const double t = (p.x - d.origin_x) * d.inv_root_size;
  const double s = (p.y - d.origin_y) * d.inv_root_size;
  const double ft = std::floor(t), fs = std::floor(s);
  const double last = static_cast<double>(d.grid - 1);
  const int gx = !(ft >= 0.0) ? 0 : ft > last ? d.grid - 1 : static_cast<int>(ft);
  const int gy = !(fs >= 0.0) ? 0 : fs > last ? d.grid - 1 : static_cast<int>(fs);
  // t - gx is exact (Sterbenz) whenever t lies in cell gx; clamping covers points off the grid.
  u = t - gx;
  v = s - gy;
  u = !(u >= 0.0) ? 0.0 : u > 1.0 ? 1.0 : u;
  v = !(v >= 0.0) ? 0.0 : v > 1.0 ? 1.0 : v;
  int node = d.root_node[static_cast<std::size_t>(gy) * static_cast<std::size_t>(d.grid) + static_cast<std::size_t>(gx)];
  int child;
  // Doubling and subtracting 0 or 1 are exact, so every level keeps (u, v) exact.
  while ((child = d.node_child[static_cast<std::size_t>(node)]) >= 0) {
    const int cx = u >= 0.5 ? 1 : 0;
    const int cy = v >= 0.5 ? 1 : 0;
    u = 2.0 * u - cx;
    v = 2.0 * v - cy;
    node = child + cx + 2 * cy;
  }
  return -1 - child;
}

Box background_leaf_box(const BackgroundFieldData& d, Vec2 p) {
  // The descent of background_locate, tracking the cell's position and side in root-cell units.
  const double t = (p.x - d.origin_x) * d.inv_root_size, s = (p.y - d.origin_y) * d.inv_root_size;
  const double ft = std::floor(t), fs = std::floor(s);
  const int gx = !(ft >= 0.0) ? 0 : ft > d.grid - 1 ? d.grid - 1 : static_cast<int>(ft);
  const int gy = !(fs >= 0.0) ? 0 : fs > d.grid - 1 ? d.grid - 1 : static_cast<int>(fs);
  double ru = std::clamp(t - gx, 0.0, 1.0), rv = std::clamp(s - gy, 0.0, 1.0);
  double lo_x = 0.0, lo_y = 0.0, side = 1.0;  // in root-cell units
  int node = d.root_node[static_cast<std::size_t>(gy) * static_cast<std::size_t>(d.grid) + static_cast<std::size_t>(gx)];
  int child;
  while ((child = d.node_child[static_cast<std::size_t>(node)]) >= 0) {
    const int cx = ru >= 0.5 ? 1 : 0, cy = rv >= 0.5 ? 1 : 0;
    ru = 2.0 * ru - cx;
    rv = 2.0 * rv - cy;
    side *= 0.5;
    lo_x += cx * side;
    lo_y += cy * side;
    node = child + cx + 2 * cy;
  }
  Box b;
  b.lo = {d.origin_x + d.root_size * (gx + lo_x), d.origin_y + d.root_size * (gy + lo_y)};
  b.hi = {d.origin_x + d.root_size * (gx + lo_x + side), d.origin_y + d.root_size * (gy + lo_y + side)};
  return b;
}

double background_interpolate(const BackgroundFieldData& d, int leaf, double u, double v) {
  const std::int32_t* c = &d.leaf_corner[4 * static_cast<std::size_t>(leaf)];
  const double q00 = d.corner_q[static_cast<std::size_t>(c[0])], q10 = d.corner_q[static_cast<std::size_t>(c[1])];
  const double q01 = d.corner_q[static_cast<std::size_t>(c[2])], q11 = d.corner_q[static_cast<std::size_t>(c[3])];
  // The kernel evaluates this same expression in the same order (FP_CONTRACT off there).
  return (1.0 - v) * ((1.0 - u) * q00 + u * q10) + v * ((1.0 - u) * q01 + u * q11);
}

namespace {

// Builds the quadtree on an integer lattice: level R = max_depth + 2 resolves the quarter points of
// the finest cells, so every sample point has integer coordinates (X, Y) and a 64-bit key; samples
// shared by neighbouring cells are evaluated once and stored once.
class Builder {
 public:
  Builder(const SpacingField& exact, const GeometryTree& tree, const BackgroundOptions& options,
          BackgroundFieldData& data)
      : exact_(exact), tree_(tree), opt_(options), d_(data), resolution_(options.max_depth + 2) {}

  void build() {
    choose_grid();
    const auto g = static_cast<std::size_t>(d_.grid);
    std::vector<std::vector<int>> root_segments(g * g);
    bin_segments(root_segments);
    d_.root_node.resize(g * g);
    for (std::size_t k = 0; k < g * g; ++k) {
      d_.root_node[k] = new_node();
      const Cell cell{static_cast<std::uint32_t>(k % g) << resolution_, static_cast<std::uint32_t>(k / g) << resolution_,
                      0};
      build_cell(d_.root_node[k], cell, root_segments[k]);
    }
  }

  std::size_t evaluations() const { return samples_.size(); }

 private:
  struct Cell {
    std::uint32_t x, y;  // lattice coordinates of the low corner
    int level;           // 0 = root cell
  };

  std::uint32_t span(int level) const { return std::uint32_t{1} << (resolution_ - level); }
  double coord(double origin, std::uint32_t lattice) const {
    return origin + d_.root_size * std::ldexp(static_cast<double>(lattice), -resolution_);
  }
  Box box(const Cell& c) const {
    Box b;
    b.lo = {coord(d_.origin_x, c.x), coord(d_.origin_y, c.y)};
    b.hi = {coord(d_.origin_x, c.x + span(c.level)), coord(d_.origin_y, c.y + span(c.level))};
    return b;
  }
  static std::uint64_t key(std::uint32_t x, std::uint32_t y) { return (std::uint64_t{x} << 32) | y; }

  double sample(std::uint32_t x, std::uint32_t y) {
    const auto [it, inserted] = samples_.try_emplace(key(x, y), 0.0);
    if (inserted) it->second = exact_.at({coord(d_.origin_x, x), coord(d_.origin_y, y)});
    return it->second;
  }
  std::int32_t corner(std::uint32_t x, std::uint32_t y) {
    const auto [it, inserted] = corners_.try_emplace(key(x, y), static_cast<std::int32_t>(d_.corner_q.size()));
    if (inserted) d_.corner_q.push_back(sample(x, y));
    return it->second;
  }
  int new_node() {
    d_.node_child.push_back(-1);
    return static_cast<int>(d_.node_child.size()) - 1;
  }

  // The square: the extents' bounding square grown by 1/64 so that points off the grid are outside
  // the domain; the top grid makes root cells about size_factor * (largest sampled q).
  void choose_grid() {
    const Box& e = tree_.geometry().extents;
    Vec2 centre{0.0, 0.0};
    double side = 1.0;
    if (e.lo.x <= e.hi.x && e.lo.y <= e.hi.y) {
      centre = e.centre();
      side = std::max(e.width(), e.height());
      if (!(side > 0.0)) side = 1.0;
    }
    side *= 1.0 + 1.0 / 64.0;
    double q_max = 0.0;
    for (int i = 0; i <= 8; ++i)
      for (int j = 0; j <= 8; ++j)
        q_max = std::max(q_max, exact_.at({centre.x + side * (i / 8.0 - 0.5), centre.y + side * (j / 8.0 - 0.5)}));
    const double cells = std::ceil(side / (opt_.size_factor * q_max));
    d_.grid = cells >= opt_.max_grid ? opt_.max_grid : std::max(1, static_cast<int>(cells));
    d_.root_size = side / d_.grid;
    d_.inv_root_size = 1.0 / d_.root_size;
    d_.origin_x = centre.x - 0.5 * side;
    d_.origin_y = centre.y - 0.5 * side;
  }

  // Each segment goes to the root cells its bounding box overlaps that it really touches (exact test).
  void bin_segments(std::vector<std::vector<int>>& root_segments) const {
    const auto& segs = tree_.geometry().segments;
    const int g = d_.grid;
    auto cell_of = [&](double c, double origin) {
      const double f = std::floor((c - origin) * d_.inv_root_size);
      return f < 0.0 ? 0 : f > g - 1 ? g - 1 : static_cast<int>(f);
    };
    for (std::size_t s = 0; s < segs.size(); ++s) {
      const Segment& seg = segs[s];
      // One cell of slack each way: the floor above may round either way at a cell edge.
      const int x0 = std::max(0, cell_of(std::min(seg.a.x, seg.b.x), d_.origin_x) - 1);
      const int x1 = std::min(g - 1, cell_of(std::max(seg.a.x, seg.b.x), d_.origin_x) + 1);
      const int y0 = std::max(0, cell_of(std::min(seg.a.y, seg.b.y), d_.origin_y) - 1);
      const int y1 = std::min(g - 1, cell_of(std::max(seg.a.y, seg.b.y), d_.origin_y) + 1);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const Cell root{static_cast<std::uint32_t>(x) << resolution_, static_cast<std::uint32_t>(y) << resolution_, 0};
          if (segment_touches_box(seg.a, seg.b, box(root)))
            root_segments[static_cast<std::size_t>(y) * static_cast<std::size_t>(g) + static_cast<std::size_t>(x)]
                .push_back(static_cast<int>(s));
        }
    }
  }

  bool needs_split(const Cell& c, const double q[4], int tag) {
    if (c.level >= opt_.max_depth || tag == kTagOutside) return false;
    const double q_min = std::min(std::min(q[0], q[1]), std::min(q[2], q[3]));
    const double side = std::ldexp(d_.root_size, -c.level);
    if (side > opt_.size_factor * q_min) return true;
    if (side < (tag == kTagBoundary ? opt_.boundary_min_side_fraction : opt_.min_side_fraction) * q_min) return false;
    // Test points in quarters of the cell: centre, edge midpoints, the four quarter points.
    static constexpr int kTests[9][2] = {{2, 2}, {2, 0}, {2, 4}, {0, 2}, {4, 2}, {1, 1}, {3, 1}, {1, 3}, {3, 3}};
    const std::uint32_t quarter = span(c.level) / 4;
    for (const auto& t : kTests) {
      const double exact = sample(c.x + quarter * static_cast<std::uint32_t>(t[0]),
                                  c.y + quarter * static_cast<std::uint32_t>(t[1]));
      const double u = t[0] / 4.0, v = t[1] / 4.0;
      const double bilinear = (1.0 - v) * ((1.0 - u) * q[0] + u * q[1]) + v * ((1.0 - u) * q[2] + u * q[3]);
      // Half the tolerance: the 9 test points see most, but not all, of the worst error in the cell.
      if (std::fabs(bilinear - exact) > 0.5 * opt_.tolerance * exact) return true;
    }
    return false;
  }

  void build_cell(int node, const Cell& c, const std::vector<int>& segments) {
    const std::uint32_t s = span(c.level);
    const double q[4] = {sample(c.x, c.y), sample(c.x + s, c.y), sample(c.x, c.y + s), sample(c.x + s, c.y + s)};
    const Box b = box(c);
    int tag = kTagBoundary;
    if (segments.empty()) tag = tree_.inside(b.centre()) ? kTagInside : kTagOutside;
    d_.max_depth = std::max(d_.max_depth, c.level);
    if (!needs_split(c, q, tag)) {
      d_.node_child[static_cast<std::size_t>(node)] = -1 - static_cast<std::int32_t>(d_.leaf_tag.size());
      d_.leaf_tag.push_back(tag);
      const std::uint32_t below_root = (std::uint32_t{1} << resolution_) - 1;
      d_.leaf_cell.push_back(static_cast<std::int32_t>((c.y >> resolution_) * static_cast<std::uint32_t>(d_.grid) +
                                                       (c.x >> resolution_)));
      d_.leaf_cell.push_back(c.level);
      d_.leaf_cell.push_back(static_cast<std::int32_t>((c.x & below_root) >> (resolution_ - c.level)));
      d_.leaf_cell.push_back(static_cast<std::int32_t>((c.y & below_root) >> (resolution_ - c.level)));
      for (const auto& [dx, dy] : {std::pair{0u, 0u}, {s, 0u}, {0u, s}, {s, s}})
        d_.leaf_corner.push_back(corner(c.x + dx, c.y + dy));
      return;
    }
    // Four consecutive children; indices, not references, since node_child grows.
    const int first = new_node();
    for (int k = 1; k < 4; ++k) new_node();
    d_.node_child[static_cast<std::size_t>(node)] = first;
    const std::uint32_t h = s / 2;
    const auto& segs = tree_.geometry().segments;
    std::vector<int> child_segments;
    for (int k = 0; k < 4; ++k) {
      const Cell child{c.x + (k & 1 ? h : 0u), c.y + (k & 2 ? h : 0u), c.level + 1};
      const Box cb = box(child);
      child_segments.clear();
      for (const int i : segments)
        if (segment_touches_box(segs[static_cast<std::size_t>(i)].a, segs[static_cast<std::size_t>(i)].b, cb))
          child_segments.push_back(i);
      build_cell(first + k, child, child_segments);  // each level has its own list
    }
  }

  const SpacingField& exact_;
  const GeometryTree& tree_;
  const BackgroundOptions& opt_;
  BackgroundFieldData& d_;
  const int resolution_;
  std::unordered_map<std::uint64_t, double> samples_;
  std::unordered_map<std::uint64_t, std::int32_t> corners_;
};

void check_options(const BackgroundOptions& o) {
  auto bad = [](const char* name, double value, const char* rule) {
    throw InputError(fmt::format("background spacing option {} = {}: {}", name, value, rule));
  };
  if (!(o.tolerance > 0.0) || !std::isfinite(o.tolerance)) bad("tolerance", o.tolerance, "must be a positive number");
  if (!(o.size_factor > 0.0) || !std::isfinite(o.size_factor))
    bad("size_factor", o.size_factor, "must be a positive number");
  if (!(o.min_side_fraction > 0.0) || !std::isfinite(o.min_side_fraction))
    bad("min_side_fraction", o.min_side_fraction, "must be a positive number");
  if (!(o.boundary_min_side_fraction > 0.0) || !std::isfinite(o.boundary_min_side_fraction))
    bad("boundary_min_side_fraction", o.boundary_min_side_fraction, "must be a positive number");
  if (o.max_depth < 0 || o.max_depth > BackgroundOptions::kMaxDepthLimit)
    bad("max_depth", o.max_depth, "must be in [0, 20]");
  if (o.max_grid < 1 || o.max_grid > BackgroundOptions::kMaxGridLimit) bad("max_grid", o.max_grid, "must be in [1, 512]");
}

}  // namespace

BackgroundSpacing::BackgroundSpacing(const SpacingField& exact, const GeometryTree& tree,
                                     const BackgroundOptions& options) {
  check_options(options);
  Builder builder(exact, tree, options, data_);
  builder.build();
  stats_.nodes = data_.node_child.size();
  stats_.leaves = data_.leaves();
  stats_.corners = data_.corner_q.size();
  stats_.exact_evaluations = builder.evaluations();
  stats_.bytes = data_.bytes();
  stats_.grid = data_.grid;
  stats_.max_depth = data_.max_depth;
}

double BackgroundSpacing::at(Vec2 p) const {
  double u, v;
  const int leaf = background_locate(data_, p, u, v);
  return background_interpolate(data_, leaf, u, v);
}

void BackgroundSpacing::at_many(const std::vector<Vec2>& p, std::vector<double>& q) const {
  q.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) q[i] = at(p[i]);
}

int BackgroundSpacing::tag_at(Vec2 p) const {
  double u, v;
  return data_.leaf_tag[static_cast<std::size_t>(background_locate(data_, p, u, v))];
}

}  // namespace pdmesh
