// Linear transfer of point data (transfer.hpp).
#include "mesh/transfer.hpp"

#include <algorithm>
#include <limits>

#include "spacing/triangle_locator.hpp"

namespace pdmesh {

std::vector<double> transfer_point_values(const Mesh& from, const std::vector<double>& values, int components,
                                          const std::vector<Vec2>& at, TransferCounts* counts) {
  const TriangleLocator locator(from.points, from.triangles);
  const auto nc = static_cast<std::size_t>(components);
  std::vector<double> out(at.size() * nc, std::numeric_limits<double>::quiet_NaN());
  TransferCounts c;
  const auto value = [&](int point, std::size_t k) { return values[static_cast<std::size_t>(point) * nc + k]; };
  for (std::size_t i = 0; i < at.size(); ++i) {
    const Located l = locator.locate(at[i]);
    if (l.triangle >= 0) {
      ++c.inside;
      const auto& t = from.triangles[static_cast<std::size_t>(l.triangle)];
      const double sum = l.w[0] + l.w[1] + l.w[2];
      for (std::size_t k = 0; k < nc; ++k)
        out[i * nc + k] = (l.w[0] * value(t[0], k) + l.w[1] * value(t[1], k) + l.w[2] * value(t[2], k)) / sum;
      continue;
    }
    const BoundaryHit h = locator.nearest_boundary(at[i]);
    if (h.edge < 0) continue;
    ++c.outside;
    c.max_distance = std::max(c.max_distance, h.distance);
    const auto& e = locator.boundary_edges()[static_cast<std::size_t>(h.edge)];
    for (std::size_t k = 0; k < nc; ++k) out[i * nc + k] = (1.0 - h.t) * value(e[0], k) + h.t * value(e[1], k);
  }
  if (counts) *counts = c;
  return out;
}

}  // namespace pdmesh
