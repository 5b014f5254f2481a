// Column merging (LayerSettings::merge_span): where the rays of a chain are dense for their layers'
// height (a trailing edge's clustered wall nodes), a ray's column ends at a layer and its two
// neighbours' columns close over it, so that the front's nodes are spaced like its last layer's
// height, which is what the core's triangles there are sized by.
#include <algorithm>

#include "layers/layers_detail.hpp"

namespace pdmesh::layers_detail {

ColumnPlan plan_columns(const RaySet& set, const std::vector<std::vector<double>>& height, double merge_span) {
  ColumnPlan plan;
  const int nr = static_cast<int>(set.rays.size());
  plan.end.assign(nr, -1);
  auto node_at = [&](int r, int k) {
    const LayerRay& ray = set.rays[r];
    return set.wall_points[ray.wall_node] + (height[r][k] / ray.correction) * ray.direction;
  };
  for (std::size_t c = 0; c + 1 < set.ray_begin.size(); ++c) {
    const int b = set.ray_begin[c], e = set.ray_begin[c + 1], n = e - b;
    const bool closed = set.closed[c] != 0;
    const std::size_t first_pair = plan.pairs.size();
    for (int k = 0; k < (closed ? n : n - 1); ++k) plan.pairs.push_back({b + k, b + (k + 1) % n, 0, -1});
    if (merge_span <= 0.0 || n < 4) continue;
    // The rays whose columns reach the current layer, in chain order; changed[r]: the layer at which
    // r's neighbours last changed (no ray of a merge is in another merge at the same layer).
    std::vector<int> active;
    for (int r = b; r < e; ++r) active.push_back(r);
    std::vector<int> changed(nr, -2);
    int top = 0;
    for (int r = b; r < e; ++r) top = std::max(top, static_cast<int>(height[r].size()) - 1);
    for (int k = 1; k < top; ++k) {
      std::vector<int> kept;
      const int m = static_cast<int>(active.size());
      if (m < 4) break;
      std::vector<char> ends(m, 0);
      for (int p = closed ? 0 : 1; p < (closed ? m : m - 1); ++p) {
        const int pl = (p + m - 1) % m, pr = (p + 1) % m;
        if (ends[pl] || (closed && p == m - 1 && ends[0])) continue;  // never two neighbours at one layer
        const int l = active[pl], r = active[p], x = active[pr];
        const LayerRay& ray = set.rays[r];
        if (ray.fan || ray.slide_segment >= 0) continue;
        // Every layer up to k + 1 of the three is on the settings' stack (below their tops).
        const int nl = static_cast<int>(height[l].size()) - 1, nm = static_cast<int>(height[r].size()) - 1,
                  nx = static_cast<int>(height[x].size()) - 1;
        if (k >= nm || k >= nl || k >= nx) continue;
        const double layer = std::min(height[l][k + 1] - height[l][k], height[x][k + 1] - height[x][k]);
        // The edge the merge makes between the neighbours' next nodes (diverging rays widen it).
        const double span = dist(node_at(l, k + 1), node_at(x, k + 1));
        if (span > merge_span * layer) continue;
        if (changed[l] == k || changed[r] == k || changed[x] == k) continue;
        ends[p] = 1;
      }
      for (int p = 0; p < m; ++p) {
        if (!ends[p]) {
          kept.push_back(active[p]);
          continue;
        }
        const int l = active[(p + m - 1) % m], r = active[p], x = active[(p + 1) % m];
        plan.end[r] = k;
        changed[l] = changed[x] = k;
        for (std::size_t q = first_pair; q < plan.pairs.size(); ++q) {
          ColumnPair& pair = plan.pairs[q];
          if (pair.to < 0 && ((pair.a == l && pair.b == r) || (pair.a == r && pair.b == x))) pair.to = k;
        }
        plan.merges.push_back({r, l, x, k});
        plan.pairs.push_back({l, x, k + 1, -1});
      }
      active = std::move(kept);
    }
  }
  return plan;
}

}  // namespace pdmesh::layers_detail
