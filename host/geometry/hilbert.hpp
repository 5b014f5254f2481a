// Hilbert-curve ordering of points: consecutive points in the order are close in the plane,
// which keeps the triangulation's point-location walks short and its memory access local.
#pragma once
#include <cstdint>
#include <vector>

#include "core/vec2.hpp"

namespace pdmesh {

// Indices 0..points.size()-1 sorted by the Hilbert index of each point on a 2^b x 2^b grid over
// the points' bounding box, b growing with the point count (at most 16: about 16 cells per point
// is fine enough for locality). Ties (points in one grid cell) keep input order.
std::vector<int> hilbert_order(const std::vector<Vec2>& points);

// Position of grid cell (x, y), 0 <= x, y < 2^bits (bits <= 16), along the Hilbert curve
// through that grid.
std::uint32_t hilbert_key(std::uint32_t x, std::uint32_t y, int bits = 16);

}  // namespace pdmesh
