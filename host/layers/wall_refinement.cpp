// Wall refinement (LayerSettings::split_span): where the rays of neighbouring wall nodes diverge (a
// leading edge's nose), their top nodes lie several last-layer heights apart, and the core's first
// triangles on such a front edge are flat. The wall segment is split into equal parts (points on the
// segment), each with its own ray, so that the front's nodes are spaced about like its last layer.
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "layers/layers_detail.hpp"

namespace pdmesh::layers_detail {

namespace {

// The height of the last layer of a stack of thickness t (as layer_counts makes it).
double last_layer(double t, const LayerSettings& s) {
  const double h1 = s.first_height, g = s.growth;
  if (t < h1) return 0.0;
  const int n = layers_reaching(h1, g, t);
  double last = t - stack_height(h1, g, n - 1);
  if (n >= 3 && last < 0.25 * h1 * std::pow(g, n - 2)) last += h1 * std::pow(g, n - 2);
  if (n == 2 && last < 0.25 * h1) last = h1;  // the first layer alone
  return last;
}

// The largest layer of a stack of thickness t: the last or the one below it (as layer_counts makes
// them), the layers the columns merge under.
double top_layer(double t, const LayerSettings& s) {
  const double h1 = s.first_height, g = s.growth;
  if (t < h1) return 0.0;
  const int n = layers_reaching(h1, g, t);
  return std::max(last_layer(t, s), n >= 2 ? h1 * std::pow(g, n - 2) : 0.0);
}

Vec2 chain_point(const WallChain& chain, std::size_t k) { return chain.points[k % chain.points.size()]; }

// Each wall point's first and last ray in chain c (a fan has several); n: the chain's points.
struct PointRays {
  std::vector<int> first, last;
};
PointRays point_rays(const RaySet& set, std::size_t c, std::size_t n) {
  PointRays out{std::vector<int>(n, -1), std::vector<int>(n, -1)};
  const int rb = set.ray_begin[c], re = set.ray_begin[c + 1];
  for (int r = rb; r < re; ++r) {
    const auto i = static_cast<std::size_t>(set.rays[r].wall_node - set.rays[rb].wall_node);
    if (out.first[i] < 0) out.first[i] = r;
    out.last[i] = r;
  }
  return out;
}

// Splits the chain's sparse segments; source gets, per new point, the old points it lies between
// (equal for an old point). Returns whether any segment was split.
bool split_chain(WallChain& chain, const PointRays& rays, const RaySet& set, const std::vector<double>& allowed,
                 const LayerSettings& settings, std::vector<std::array<int, 2>>& source) {
  const auto top = [&](int r) {
    const LayerRay& ray = set.rays[r];
    return set.wall_points[ray.wall_node] + (allowed[r] / ray.correction) * ray.direction;
  };
  const int n = static_cast<int>(chain.points.size());
  // Whether ray r (of chain point i) keeps its column to its top (column_merge.cpp): a fan ray, a
  // sliding end ray or an open chain's end.
  const auto fixed_column = [&](int r, int i) {
    return set.rays[r].fan || set.rays[r].slide_segment >= 0 || (!chain.closed && (i == 0 || i == n - 1));
  };
  bool split = false;
  WallChain out;
  out.closed = chain.closed;
  for (int i = 0; i < n; ++i) {
    out.points.push_back(chain.points[i]);
    out.curve.push_back(chain.curve[i]);
    source.push_back({i, i});
    const int j = i + 1 < n ? i + 1 : (chain.closed ? 0 : -1);
    if (j < 0 || rays.first[i] < 0 || rays.first[j] < 0) continue;
    const int a = rays.last[i], b = rays.first[j];
    // The thinner last layer; where one end has no layer (a layer's end), the other's.
    const double la = last_layer(allowed[a], settings), lb = last_layer(allowed[b], settings);
    const double h = la > 0.0 && lb > 0.0 ? std::min(la, lb) : std::max(la, lb);
    const double gap = dist(top(a), top(b));
    const double span = settings.split_span * h;
    if (h <= 0.0 || gap <= span) continue;
    int parts = static_cast<int>(std::ceil(gap / span));
    // Between two rays whose columns never merge (fan rays, an open chain's ends: plan_columns),
    // the new rays' columns merge in pairs from one end where two parts fit under a layer
    // (merge_span). An odd number of parts would leave one front edge of a single part, half as
    // long as its neighbours, beside the fan: the core's triangles on it are flat. With an even
    // number the pairs fill the segment.
    if (parts % 2 == 1 && fixed_column(a, i) && fixed_column(b, j) &&
        2.0 * gap / parts <=
            settings.merge_span * std::min(top_layer(allowed[a], settings), top_layer(allowed[b], settings)))
      ++parts;
    for (int k = 1; k < parts; ++k) {
      const double t = static_cast<double>(k) / parts;
      out.points.push_back(chain.points[i] + t * (chain.points[j] - chain.points[i]));
      out.curve.push_back(chain.curve[i]);
      source.push_back({i, j});
    }
    split = true;
  }
  chain = std::move(out);
  return split;
}

// A new point's ray: the directions of its segment's end rays interpolated (the smoothing would
// tilt a ray on a straight segment as far as its neighbours' mean, and the thin cells beside it
// would be skewed), its correction over the segment's normal. Beside an end ray more than 75
// degrees off the segment's normal it is kept within max_tilt of that normal: an end ray at a
// sharp concave vertex (a wedge's tip, whose ray runs along its
// bisector, far off both walls' normals) would otherwise tilt the rays along a long segment with
// it, and their cells would be sheared flat.
void interpolate_new_rays(RaySet& refined, std::size_t c, const WallChain& chain,
                          const std::vector<std::array<int, 2>>& source, double max_tilt) {
  const std::size_t n = source.size();
  const PointRays rays = point_rays(refined, c, n);
  for (std::size_t p = 0; p < n; ++p) {
    if (source[p][0] == source[p][1]) continue;
    std::size_t pi = p, pj = p;
    while (source[pi][0] != source[pi][1]) --pi;
    while (source[pj % n][0] != source[pj % n][1]) ++pj;
    const double t = static_cast<double>(p - pi) / static_cast<double>(pj - pi);
    const Vec2 da = refined.rays[rays.last[pi]].direction;
    const Vec2 db = refined.rays[rays.first[pj % n]].direction;
    LayerRay& ray = refined.rays[rays.first[p]];
    ray.direction = normalized((1.0 - t) * da + t * db);
    const Vec2 normal = left_normal(chain_point(chain, pi), chain_point(chain, pj));
    // Only beside an end ray more than 75 degrees off the segment's normal (a corner sharper than
    // 30 degrees): beside blunter concave corners the new rays lean with the corner's ray, so that
    // their columns do not cross its column.
    const double acute = std::cos(75.0 * std::numbers::pi / 180.0);
    const bool steep_end = dot(da, normal) < acute || dot(db, normal) < acute;
    if (steep_end && dot(ray.direction, normal) < std::cos(max_tilt))
      ray.direction = rotated(normal, cross(normal, ray.direction) < 0.0 ? -max_tilt : max_tilt);
    ray.correction = std::max(0.2, dot(ray.direction, normal));
  }
}

// The refined rays' thickness limits: an old point's rays keep theirs (their collisions were found
// with the same directions, up to the smoothing), a new point's ray the smaller of its two
// neighbours' (it lies between them).
void carry_limits(const RaySet& set, const std::vector<double>& allowed, const PointRays& old_rays, RaySet& refined,
                  std::size_t c, const std::vector<std::array<int, 2>>& source, std::vector<double>& limits) {
  const int rb = refined.ray_begin[c], re = refined.ray_begin[c + 1];
  int previous_point = -1, fan_index = 0;
  for (int r = rb; r < re; ++r) {
    const int p = refined.rays[r].wall_node - refined.rays[rb].wall_node;
    fan_index = p == previous_point ? fan_index + 1 : 0;
    previous_point = p;
    const auto [i, j] = source[static_cast<std::size_t>(p)];
    const int a = i == j ? std::min(old_rays.first[i] + fan_index, old_rays.last[i]) : old_rays.last[i];
    const int b = i == j ? a : old_rays.first[j];
    limits[r] = std::min(allowed[a], allowed[b]);
    refined.rays[r].free_thickness = std::min(set.rays[a].free_thickness, set.rays[b].free_thickness);
  }
}

}  // namespace

bool refine_sparse_walls(std::vector<WallChain>& chains, const Geometry& geometry, const LayerSettings& settings,
                         const CoreSpacing& core_spacing, RaySet& set, std::vector<double>& allowed) {
  if (settings.split_span <= 0.0) return false;
  bool split = false;
  std::vector<std::vector<std::array<int, 2>>> source(chains.size());
  std::vector<PointRays> old_rays;
  // The tops where the layer will end: the limits graded along the chains as build_boundary_layers
  // grades them (collisions thin a whole stretch of the layer, not only the colliding rays).
  std::vector<double> graded = allowed;
  grade_thickness(set, settings, graded);
  for (std::size_t c = 0; c < chains.size(); ++c) {
    old_rays.push_back(point_rays(set, c, chains[c].points.size()));
    split = split_chain(chains[c], old_rays[c], set, graded, settings, source[c]) || split;
  }
  if (!split) return false;
  RaySet refined = make_rays(chains, geometry, settings, core_spacing);
  // The new rays' tilt limit beside an acute corner: the settings' (split quads), else 45 degrees.
  const double max_tilt =
      (settings.max_ray_tilt_deg > 0.0 ? settings.max_ray_tilt_deg : 45.0) * std::numbers::pi / 180.0;
  std::vector<double> limits(refined.rays.size(), 0.0);
  for (std::size_t c = 0; c < chains.size(); ++c) {
    interpolate_new_rays(refined, c, chains[c], source[c], max_tilt);
    carry_limits(set, allowed, old_rays[c], refined, c, source[c], limits);
  }
  set = std::move(refined);
  allowed = std::move(limits);
  return true;
}

}  // namespace pdmesh::layers_detail
