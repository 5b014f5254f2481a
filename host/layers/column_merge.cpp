// Column merging (LayerSettings::merge_span): where the rays of a chain are dense for their layers'
// height (a trailing edge's clustered wall nodes), a ray's column ends at a layer and its two
// neighbours' columns close over it, so that the front's nodes are spaced like its last layer's
// height, which is what the core's triangles there are sized by.
#include <algorithm>

#include "layers/layers_detail.hpp"

namespace pdmesh::layers_detail {

namespace {

// One chain's merges, layer after layer. pair_left[r] / pair_right[r]: the open pair (index into
// plan.pairs) whose b / a is ray r.
class ChainMerger {
 public:
  ChainMerger(const RaySet& set, const std::vector<std::vector<double>>& height, double merge_span, double fan_span,
              ColumnPlan& plan)
      : set_(set), height_(height), merge_span_(merge_span), fan_span_(fan_span), plan_(plan) {}

  void run(int b, int e, bool closed) {
    const int n = e - b;
    std::vector<int> pair_left(set_.rays.size(), -1), pair_right(set_.rays.size(), -1);
    for (int k = 0; k < (closed ? n : n - 1); ++k) {
      const int a = b + k, c = b + (k + 1) % n;
      pair_right[a] = pair_left[c] = static_cast<int>(plan_.pairs.size());
      plan_.pairs.push_back({a, c, 0, -1});
    }
    if (merge_span_ <= 0.0 || n < 4) return;
    std::vector<int> active;  // the rays whose columns reach the current layer, in chain order
    int top = 0;
    for (int r = b; r < e; ++r) {
      active.push_back(r);
      top = std::max(top, layers(r));
    }
    for (int k = 1; k < top && active.size() >= 4; ++k) {
      const std::vector<char> ends = ending(active, k, closed);
      std::vector<int> kept;
      const int m = static_cast<int>(active.size());
      for (int p = 0; p < m; ++p) {
        if (!ends[p]) {
          kept.push_back(active[p]);
          continue;
        }
        const int l = active[(p + m - 1) % m], r = active[p], x = active[(p + 1) % m];
        plan_.end[r] = k;
        plan_.pairs[pair_left[r]].to = plan_.pairs[pair_right[r]].to = k;
        plan_.merges.push_back({r, l, x, k});
        pair_right[l] = pair_left[x] = static_cast<int>(plan_.pairs.size());
        plan_.pairs.push_back({l, x, k + 1, -1});
      }
      active = std::move(kept);
    }
  }

 private:
  int layers(int r) const { return static_cast<int>(height_[r].size()) - 1; }
  Vec2 node_at(int r, int k) const {
    const LayerRay& ray = set_.rays[r];
    return set_.wall_points[ray.wall_node] + (height_[r][k] / ray.correction) * ray.direction;
  }
  // Which of the active rays' columns end at layer k: never two neighbours (the merge's triangles
  // use both neighbours' nodes at k and k + 1).
  std::vector<char> ending(const std::vector<int>& active, int k, bool closed) const {
    const int m = static_cast<int>(active.size());
    std::vector<char> ends(m, 0);
    for (int p = closed ? 0 : 1; p < (closed ? m : m - 1); ++p) {
      const int pl = (p + m - 1) % m, pr = (p + 1) % m;
      if (ends[pl] || (closed && p == m - 1 && ends[0])) continue;
      ends[p] = merges(active[pl], active[p], active[pr], k) ? 1 : 0;
    }
    return ends;
  }
  // Whether r's column ends at layer k between l and x.
  bool merges(int l, int r, int x, int k) const {
    const LayerRay& ray = set_.rays[r];
    if (ray.slide_segment >= 0) return false;
    // Every layer up to k + 1 of the three is on the settings' stack (below their tops).
    if (k >= layers(r) || k >= layers(l) || k >= layers(x)) return false;
    if (ray.fan && !fan_edge_between_fans(l, r, x)) return fan_middle_merges(l, r, x, k);
    const double layer = std::min(height_[l][k + 1] - height_[l][k], height_[x][k + 1] - height_[x][k]);
    // The edge the merge makes between the neighbours' next nodes (diverging rays widen it).
    return dist(node_at(l, k + 1), node_at(x, k + 1)) <= merge_span_ * layer;
  }

  // Whether r is the edge ray of a fan whose neighbour across the wall segment is the edge ray of
  // another fan (a blunt trailing edge: a short wall segment between two convex corners). The two
  // edge rays are parallel, so their column keeps the segment's width up to the top however far
  // apart the fans' other rays are there, and the core met its short top edge between the fans'
  // long ones with flat triangles. That column ends as any other where its neighbours' nodes come
  // within merge_span of a layer.
  bool fan_edge_between_fans(int l, int r, int x) const {
    const int node = set_.rays[r].wall_node;
    const bool l_same = set_.rays[l].wall_node == node, x_same = set_.rays[x].wall_node == node;
    if (l_same == x_same) return false;  // a middle ray of its fan
    return set_.rays[l_same ? x : l].fan;
  }

  // The middle ray of a fan of two elements (a vertex that the triangles' ray tilt limit fans)
  // ends at its last layer where the fan's edge rays' tops are at most fan_span x the last layer
  // apart: the fan then has one front edge, about as long as the front edges beside it, while its
  // cells below keep the two elements' angles. Two half-length edges there would make the core's
  // spacing at the front half that of the wall segments beside the fan.
  bool fan_middle_merges(int l, int r, int x, int k) const {
    const int node = set_.rays[r].wall_node;
    if (fan_span_ <= 0.0 || k + 1 != layers(r)) return false;
    if (set_.rays[l].wall_node != node || set_.rays[x].wall_node != node) return false;
    if (r - l != 1 || x - r != 1) return false;  // the neighbours in the chain, not across its start
    if ((l > 0 && set_.rays[l - 1].wall_node == node) ||
        (x + 1 < static_cast<int>(set_.rays.size()) && set_.rays[x + 1].wall_node == node))
      return false;
    if (k + 1 != layers(l) || k + 1 != layers(x)) return false;
    const double layer = std::min(height_[l][k + 1] - height_[l][k], height_[x][k + 1] - height_[x][k]);
    return dist(node_at(l, k + 1), node_at(x, k + 1)) <= fan_span_ * layer;
  }

  const RaySet& set_;
  const std::vector<std::vector<double>>& height_;
  double merge_span_;
  double fan_span_;
  ColumnPlan& plan_;
};

}  // namespace

ColumnPlan plan_columns(const RaySet& set, const std::vector<std::vector<double>>& height, double merge_span,
                        double fan_span) {
  ColumnPlan plan;
  plan.end.assign(set.rays.size(), -1);
  ChainMerger merger(set, height, merge_span, fan_span, plan);
  for (std::size_t c = 0; c + 1 < set.ray_begin.size(); ++c)
    merger.run(set.ray_begin[c], set.ray_begin[c + 1], set.closed[c] != 0);
  return plan;
}

}  // namespace pdmesh::layers_detail
