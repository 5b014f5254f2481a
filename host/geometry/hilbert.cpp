// Hilbert-curve ordering of points (integer grid key + stable radix sort).
#include "geometry/hilbert.hpp"

#include <algorithm>
#include <cstdint>

namespace pdmesh {
namespace {

// Computed top level first. Instead of rotating the coordinates at each level we track the accumulated
// rotation as two bits (swap x/y, complement both), which commute; no branches.
}  // namespace

std::uint32_t hilbert_key(std::uint32_t x, std::uint32_t y, int bits) {
  std::uint32_t d = 0, swap = 0, complement = 0;
  for (int level = bits - 1; level >= 0; --level) {
    const std::uint32_t bx = ((x >> level) & 1u) ^ complement, by = ((y >> level) & 1u) ^ complement;
    const std::uint32_t rx = swap ? by : bx, ry = swap ? bx : by;
    d = (d << 2) | ((3u * rx) ^ ry);
    const std::uint32_t rotate = ry ^ 1u;  // the lower-left and lower-right quadrants are rotated
    swap ^= rotate;
    complement ^= rotate & rx;
  }
  return d;
}

std::vector<int> hilbert_order(const std::vector<Vec2>& points) {
  const std::size_t n = points.size();
  Box box;
  for (const Vec2& p : points) box.add(p);
  int bits = 4;
  while (bits < 16 && (std::size_t{1} << (2 * bits)) < 16 * n) ++bits;
  const std::uint32_t grid = 1u << bits;
  const double extent = std::max(box.width(), box.height());
  const double scale = extent > 0.0 ? (grid - 1) / extent : 0.0;
  // Pack key (high 32 bits) and index (low 32 bits), then sort by key with an LSD radix sort
  // on the key's 2 * bits bits, a byte at a time: linear time, and stable, so equal keys keep
  // input order.
  std::vector<std::uint64_t> items(n), scratch(n);
  for (std::size_t i = 0; i < n; ++i) {
    auto cell = [&](double v, double lo) {
      const double c = (v - lo) * scale;
      if (!(c > 0.0)) return 0u;  // also catches NaN, which the triangulation rejects anyway
      if (c >= grid - 1) return grid - 1;
      return static_cast<std::uint32_t>(c);
    };
    const std::uint32_t key = hilbert_key(cell(points[i].x, box.lo.x), cell(points[i].y, box.lo.y), bits);
    items[i] = (static_cast<std::uint64_t>(key) << 32) | static_cast<std::uint32_t>(i);
  }
  for (int shift = 32; shift < 32 + 2 * bits; shift += 8) {
    std::size_t count[257] = {};
    for (std::uint64_t v : items) ++count[((v >> shift) & 0xff) + 1];
    for (int b = 0; b < 256; ++b) count[b + 1] += count[b];
    for (std::uint64_t v : items) scratch[count[(v >> shift) & 0xff]++] = v;
    items.swap(scratch);
  }
  std::vector<int> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<int>(items[i] & 0xffffffffu);
  return order;
}

}  // namespace pdmesh
