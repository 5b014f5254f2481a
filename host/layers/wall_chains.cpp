// The wall chains: runs of wall curves along the geometry's loops, oriented with the domain on the left.
#include <algorithm>

#include "layers/layers_detail.hpp"

namespace pdmesh::layers_detail {

namespace {

// Appends curve `c` (reversed if asked) to the chain, without its first point when the chain
// already ends there.
void append_curve(WallChain& chain, const Curve& curve, int c, bool reversed) {
  std::vector<Vec2> pts = curve.points;
  if (reversed) std::reverse(pts.begin(), pts.end());
  std::size_t start = chain.points.empty() ? 0 : 1;
  if (!chain.curve.empty()) chain.curve.back() = c;  // the joint leaves along this curve
  for (std::size_t k = start; k < pts.size(); ++k) {
    chain.points.push_back(pts[k]);
    chain.curve.push_back(c);
  }
}

void orient(WallChain& chain, bool domain_on_left) {
  if (domain_on_left) return;
  std::reverse(chain.points.begin(), chain.points.end());
  std::reverse(chain.curve.begin(), chain.curve.end());
  // After reversal, the curve of the segment leaving point k is the one that arrived at it before.
  if (chain.points.size() >= 2) {
    std::vector<int> leaving(chain.curve.size());
    const std::size_t n = chain.curve.size();
    for (std::size_t k = 0; k + 1 < n; ++k) leaving[k] = chain.curve[k + 1];
    leaving[n - 1] = chain.closed ? chain.curve[0] : chain.curve[n - 1];
    chain.curve = std::move(leaving);
  }
}

}  // namespace

std::vector<WallChain> wall_chains(const Geometry& geometry, const std::vector<int>& wall_curves) {
  std::vector<std::uint8_t> is_wall(geometry.curves.size(), 0);
  for (const int c : wall_curves) is_wall[static_cast<std::size_t>(c)] = 1;
  std::vector<WallChain> chains;
  for (const Loop& loop : geometry.loops) {
    const int n = static_cast<int>(loop.curves.size());
    // Domain on the left of the loop's direction: a counter-clockwise outer boundary, or a clockwise hole.
    const bool left = (loop.signed_area > 0.0) == (loop.depth % 2 == 0);
    int walls = 0;
    for (const int c : loop.curves) walls += is_wall[static_cast<std::size_t>(c)];
    if (walls == 0) continue;
    if (walls == n) {
      WallChain chain;
      chain.closed = true;
      for (int k = 0; k < n; ++k)
        append_curve(chain, geometry.curves[loop.curves[k]], loop.curves[k], loop.reversed[k] != 0);
      chain.points.pop_back();  // the loop's first point again
      chain.curve.pop_back();
      orient(chain, left);
      chains.push_back(std::move(chain));
      continue;
    }
    // Start after a curve that is not a wall, then collect the runs of walls.
    int start = 0;
    while (is_wall[static_cast<std::size_t>(loop.curves[start])]) ++start;
    WallChain chain;
    for (int j = 1; j <= n; ++j) {
      const int k = (start + j) % n;
      const int c = loop.curves[k];
      if (is_wall[static_cast<std::size_t>(c)]) {
        append_curve(chain, geometry.curves[c], c, loop.reversed[k] != 0);
      } else if (!chain.points.empty()) {
        orient(chain, left);
        chains.push_back(std::move(chain));
        chain = WallChain{};
      }
    }
    if (!chain.points.empty()) {
      orient(chain, left);
      chains.push_back(std::move(chain));
    }
  }
  return chains;
}

}  // namespace pdmesh::layers_detail
