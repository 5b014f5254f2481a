// Measures of a mesh read back from a run's output, for the tests of sizes and far fields: the
// smallest angle, the mean length of the edges whose midpoint satisfies a predicate, the area.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <set>
#include <utility>

#include "mesh/mesh.hpp"

namespace pdmesh_test {

inline double min_angle_deg(const pdmesh::Mesh& m) {
  double least = 180.0;
  for (const auto& t : m.triangles) {
    for (int k = 0; k < 3; ++k) {
      const pdmesh::Vec2 a = m.points[t[k]], b = m.points[t[(k + 1) % 3]], c = m.points[t[(k + 2) % 3]];
      const double u = std::atan2(b.y - a.y, b.x - a.x), v = std::atan2(c.y - a.y, c.x - a.x);
      double d = std::fabs(u - v);
      if (d > std::numbers::pi) d = 2.0 * std::numbers::pi - d;
      least = std::min(least, d * 180.0 / std::numbers::pi);
    }
  }
  return least;
}

// The sum of the triangles' signed areas (the domain's area for a counter-clockwise mesh).
inline double mesh_area(const pdmesh::Mesh& m) {
  double sum = 0.0;
  for (const auto& t : m.triangles)
    sum += 0.5 * pdmesh::cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]);
  return sum;
}

struct EdgeMean {
  double mean = 0.0;
  std::size_t count = 0;
};

// Each edge once (by its sorted node pair).
inline EdgeMean mean_edge(const pdmesh::Mesh& m, const std::function<bool(pdmesh::Vec2)>& where) {
  std::set<std::pair<int, int>> seen;
  EdgeMean e;
  double sum = 0.0;
  for (const auto& t : m.triangles) {
    for (int k = 0; k < 3; ++k) {
      const int i = std::min(t[k], t[(k + 1) % 3]), j = std::max(t[k], t[(k + 1) % 3]);
      if (!seen.insert({i, j}).second) continue;
      const pdmesh::Vec2 a = m.points[i], b = m.points[j];
      if (!where({0.5 * (a.x + b.x), 0.5 * (a.y + b.y)})) continue;
      sum += std::hypot(b.x - a.x, b.y - a.y);
      ++e.count;
    }
  }
  e.mean = e.count > 0 ? sum / static_cast<double>(e.count) : 0.0;
  return e;
}

}  // namespace pdmesh_test
