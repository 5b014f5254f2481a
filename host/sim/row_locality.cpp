// The locality measure of the neighbour rows; see row_locality.hpp.
#include "sim/row_locality.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>

#include <fmt/format.h>

namespace pdmesh {

RowLocality row_locality(const NodeSet& nodes, double radius_factor) {
  RowLocality out;
  const std::size_t n = nodes.size();
  if (n == 0) return out;
  // A uniform grid with cells of the median radius; a node with a larger radius searches more cells
  // (where q is larger the nodes are sparser, so the work per node stays about the same).
  std::vector<double> radii(n);
  for (std::size_t i = 0; i < n; ++i) radii[i] = radius_factor * nodes.q[i];
  std::vector<double> sorted = radii;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(n / 2), sorted.end());
  const double cell = sorted[n / 2];
  if (!(cell > 0.0)) return out;
  double lo_x = nodes.x[0].x, lo_y = nodes.x[0].y;
  for (const Vec2& p : nodes.x) lo_x = std::min(lo_x, p.x), lo_y = std::min(lo_y, p.y);
  auto key = [&](std::int64_t cx, std::int64_t cy) {
    return (static_cast<std::uint64_t>(cx) << 32) | static_cast<std::uint64_t>(cy);
  };
  auto cx_of = [&](double x) { return static_cast<std::int64_t>(std::floor((x - lo_x) / cell)); };
  auto cy_of = [&](double y) { return static_cast<std::int64_t>(std::floor((y - lo_y) / cell)); };
  std::vector<std::pair<std::uint64_t, int>> binned(n);
  for (std::size_t i = 0; i < n; ++i) binned[i] = {key(cx_of(nodes.x[i].x), cy_of(nodes.x[i].y)), static_cast<int>(i)};
  std::sort(binned.begin(), binned.end());
  double sum = 0.0;
  std::uint64_t near64 = 0, near1024 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (nodes.kind[i] != NodeKind::Interior) continue;
    const Vec2 p = nodes.x[i];
    const double r = radii[i];
    for (std::int64_t cx = cx_of(p.x - r); cx <= cx_of(p.x + r); ++cx) {
      for (std::int64_t cy = cy_of(p.y - r); cy <= cy_of(p.y + r); ++cy) {
        if (cx < 0 || cy < 0) continue;
        auto it = std::lower_bound(binned.begin(), binned.end(), std::pair<std::uint64_t, int>{key(cx, cy), -1});
        for (; it != binned.end() && it->first == key(cx, cy); ++it) {
          const auto j = static_cast<std::size_t>(it->second);
          if (j == i || norm(nodes.x[j] - p) > r) continue;
          const double d = std::fabs(static_cast<double>(i) - static_cast<double>(j));
          ++out.entries;
          sum += d;
          near64 += d <= 64.0;
          near1024 += d <= 1024.0;
        }
      }
    }
  }
  if (out.entries == 0) return out;
  const auto e = static_cast<double>(out.entries);
  out.mean_distance = sum / e;
  out.within_64 = static_cast<double>(near64) / e;
  out.within_1024 = static_cast<double>(near1024) / e;
  return out;
}

void trace_row_locality(const char* when, const NodeSet& nodes) {
  const char* value = std::getenv("PDMESH_ROW_LOCALITY");
  if (!value) return;
  char* end = nullptr;
  double factor = std::strtod(value, &end);
  if (end == value || !(factor > 0.0) || !std::isfinite(factor)) factor = 2.7;
  const RowLocality r = row_locality(nodes, factor);
  fmt::print(stderr,
             "row locality {}: {} nodes, {} row entries (radius {} q), mean |i - j| {:.1f}, within 64: {:.4f}, "
             "within 1024: {:.4f}\n",
             when, nodes.size(), r.entries, factor, r.mean_distance, r.within_64, r.within_1024);
}

}  // namespace pdmesh
