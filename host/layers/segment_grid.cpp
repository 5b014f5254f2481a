// The uniform segment grid of the layer generator and the intersection parameter of two segments.
#include <algorithm>
#include <cmath>

#include "core/predicates.hpp"
#include "layers/layers_detail.hpp"

namespace pdmesh::layers_detail {

SegmentGrid::SegmentGrid(const Box& box, double cell) : box_(box), cell_(cell) {
  // At most ~4M cells, whatever the cell asked for.
  const double area = std::max(box.width(), cell) * std::max(box.height(), cell);
  cell_ = std::max(cell_, std::sqrt(area / 4.0e6));
  nx_ = std::max(1, static_cast<int>(std::ceil(box.width() / cell_)));
  ny_ = std::max(1, static_cast<int>(std::ceil(box.height() / cell_)));
  cells_.resize(static_cast<std::size_t>(nx_) * ny_);
}

bool SegmentGrid::cell_range(Vec2 a, Vec2 b, int& x0, int& y0, int& x1, int& y1) const {
  const double lx = std::min(a.x, b.x), hx = std::max(a.x, b.x);
  const double ly = std::min(a.y, b.y), hy = std::max(a.y, b.y);
  if (hx < box_.lo.x || lx > box_.hi.x || hy < box_.lo.y || ly > box_.hi.y) return false;
  auto clampi = [](double v, int n) { return std::clamp(static_cast<int>(std::floor(v)), 0, n - 1); };
  x0 = clampi((lx - box_.lo.x) / cell_, nx_);
  x1 = clampi((hx - box_.lo.x) / cell_, nx_);
  y0 = clampi((ly - box_.lo.y) / cell_, ny_);
  y1 = clampi((hy - box_.lo.y) / cell_, ny_);
  return true;
}

void SegmentGrid::insert(int id, Vec2 a, Vec2 b) {
  int x0, y0, x1, y1;
  if (!cell_range(a, b, x0, y0, x1, y1)) return;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) cells_[static_cast<std::size_t>(y) * nx_ + x].push_back(id);
}

double intersection_parameter(Vec2 p, Vec2 q, Vec2 a, Vec2 b) {
  const Vec2 r = q - p, s = b - a;
  const double den = cross(r, s);
  if (den == 0.0) {
    // Collinear overlap: the nearer end of a -> b that lies on p -> q.
    const double rr = dot(r, r);
    const double ta = dot(a - p, r) / rr, tb = dot(b - p, r) / rr;
    double t = 1.0;
    for (const double v : {ta, tb})
      if (v >= 0.0 && v <= 1.0) t = std::min(t, v);
    if (ta < 0.0 && tb > 0.0) t = 0.0;
    if (tb < 0.0 && ta > 0.0) t = 0.0;
    return t;
  }
  return std::clamp(cross(a - p, s) / den, 0.0, 1.0);
}

}  // namespace pdmesh::layers_detail
