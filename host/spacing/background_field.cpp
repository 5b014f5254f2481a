// BackgroundSpacing: builds the adaptive quadtree of corner samples and domain tags from an exact
// spacing field and the geometry tree, and looks points up in it (see docs/spacing.md).
#include "spacing/background_field.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "spacing/background_builder.hpp"

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
  int node =
      d.root_node[static_cast<std::size_t>(gy) * static_cast<std::size_t>(d.grid) + static_cast<std::size_t>(gx)];
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

int background_locate_guessed(const BackgroundFieldData& d, Vec2 p, int& guess, double& u, double& v) {
  if (guess >= 0 && static_cast<std::size_t>(guess) < d.leaves()) {
    const std::int32_t* cell = &d.leaf_cell[4 * static_cast<std::size_t>(guess)];
    const double t = (p.x - d.origin_x) * d.inv_root_size;
    const double s = (p.y - d.origin_y) * d.inv_root_size;
    // Only a point on the grid converts to int (NaN and points off it compare false and never match).
    if (t >= 0.0 && t < static_cast<double>(d.grid) && s >= 0.0 && s < static_cast<double>(d.grid)) {
      const int gx = static_cast<int>(t), gy = static_cast<int>(s);
      // 2^L (t - gx) - ix is the descent's u after L levels: t - gx is exact, the doublings and the
      // subtractions of the bits taken are too.
      const double cells = std::ldexp(1.0, cell[1]);
      const double wu = (t - gx) * cells, wv = (s - gy) * cells;
      const double ix = cell[2], iy = cell[3];
      if (gy * d.grid + gx == cell[0] && wu >= ix && wu < ix + 1.0 && wv >= iy && wv < iy + 1.0) {
        u = wu - ix;
        v = wv - iy;
        return guess;
      }
    }
  }
  guess = background_locate(d, p, u, v);
  return guess;
}

Box background_leaf_box(const BackgroundFieldData& d, Vec2 p) {
  // The descent of background_locate, tracking the cell's position and side in root-cell units.
  const double t = (p.x - d.origin_x) * d.inv_root_size, s = (p.y - d.origin_y) * d.inv_root_size;
  const double ft = std::floor(t), fs = std::floor(s);
  const int gx = !(ft >= 0.0) ? 0 : ft > d.grid - 1 ? d.grid - 1 : static_cast<int>(ft);
  const int gy = !(fs >= 0.0) ? 0 : fs > d.grid - 1 ? d.grid - 1 : static_cast<int>(fs);
  double ru = std::clamp(t - gx, 0.0, 1.0), rv = std::clamp(s - gy, 0.0, 1.0);
  double lo_x = 0.0, lo_y = 0.0, side = 1.0;  // in root-cell units
  int node =
      d.root_node[static_cast<std::size_t>(gy) * static_cast<std::size_t>(d.grid) + static_cast<std::size_t>(gx)];
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

void check_background_options(const BackgroundOptions& o) {
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
  if (!(o.jump_min_side_fraction > 0.0) || !std::isfinite(o.jump_min_side_fraction))
    bad("jump_min_side_fraction", o.jump_min_side_fraction, "must be a positive number");
  if (!(o.jump_tolerance > 0.0) || !std::isfinite(o.jump_tolerance))
    bad("jump_tolerance", o.jump_tolerance, "must be a positive number");
  if (o.max_depth < 0 || o.max_depth > BackgroundOptions::kMaxDepthLimit)
    bad("max_depth", o.max_depth, "must be in [0, 20]");
  if (o.max_grid < 1 || o.max_grid > BackgroundOptions::kMaxGridLimit)
    bad("max_grid", o.max_grid, "must be in [1, 512]");
}

BackgroundSpacing::BackgroundSpacing(const SpacingField& exact, const GeometryTree& tree,
                                     const BackgroundOptions& options) {
  check_background_options(options);
  BackgroundBuilder builder(exact, tree, options);
  builder.build();
  data_ = builder.emit();
  stats_.exact_evaluations = builder.samples();
  stats_.exact_batches = builder.batches();
  fill_stats();
}

BackgroundSpacing::BackgroundSpacing(BackgroundFieldData data, const BackgroundStats& stats)
    : data_(std::move(data)), stats_(stats) {
  fill_stats();
}

void BackgroundSpacing::fill_stats() {
  stats_.nodes = data_.node_child.size();
  stats_.leaves = data_.leaves();
  stats_.corners = data_.corner_q.size();
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
  // A lookup is a descent of up to max_depth levels (~0.2-0.4 us on 30P30N's tree); large batches
  // (a population event's triangle circumcentres, every node of a mesh) are worth a second core.
  // Each value is at()'s whatever the thread.
  parallel_for(
      p.size(), [&](std::size_t i) { q[i] = at(p[i]); }, 8192);
}

void BackgroundSpacing::at_many_guessed(const std::vector<Vec2>& p, std::vector<double>& q,
                                        std::vector<int>& guesses) const {
  q.resize(p.size());
  guesses.resize(p.size(), 0);
  // Every step of a host run waits on this update: a few thousand nodes already use a second core.
  parallel_for(
      p.size(),
      [&](std::size_t i) {
        double u, v;
        const int leaf = background_locate_guessed(data_, p[i], guesses[i], u, v);
        q[i] = background_interpolate(data_, leaf, u, v);
      },
      2048);
}

int BackgroundSpacing::tag_at(Vec2 p) const {
  double u, v;
  return data_.leaf_tag[static_cast<std::size_t>(background_locate(data_, p, u, v))];
}

}  // namespace pdmesh
