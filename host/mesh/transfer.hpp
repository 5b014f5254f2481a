// Solution transfer between two meshes of a moving-geometry run (docs/motion.md, "Solution transfer"):
// point data of one mesh interpolated linearly at the points of another, in the triangle of the first
// that contains each point (spacing/triangle_locator); a point outside the first mesh (where the body
// was) takes the value at the nearest point of its boundary.
#pragma once
#include <cstddef>
#include <vector>

#include "core/vec2.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

struct TransferCounts {
  std::size_t inside = 0;   // points located in a triangle
  std::size_t outside = 0;  // points given the value at the nearest boundary point
  double max_distance = 0.0;
};

// values: `components` per point of `from`, point-major; returns the same per point of `at`.
std::vector<double> transfer_point_values(const Mesh& from, const std::vector<double>& values, int components,
                                          const std::vector<Vec2>& at, TransferCounts* counts = nullptr);

}  // namespace pdmesh
