// Wall refinement (LayerSettings::split_span): where the rays of neighbouring wall nodes diverge (a
// leading edge's nose), their top nodes lie several last-layer heights apart, and the core's first
// triangles on such a front edge are flat. The wall segment is split into equal parts (points on the
// segment), each with its own ray, so that the front's nodes are spaced about like its last layer.
#include <algorithm>
#include <array>
#include <cmath>

#include "layers/layers_detail.hpp"

namespace pdmesh::layers_detail {

namespace {

// The height of the last layer of a stack of thickness t (as layer_counts makes it).
double last_layer(double t, const LayerSettings& s) {
  const double h1 = s.first_height, g = s.growth;
  if (t < h1) return 0.0;
  int n = 1;
  while (stack_height(h1, g, n) < t * (1.0 - 1e-12)) ++n;
  double last = t - stack_height(h1, g, n - 1);
  if (n >= 3 && last < 0.25 * h1 * std::pow(g, n - 2)) last += h1 * std::pow(g, n - 2);
  return last;
}

Vec2 chain_point(const WallChain& chain, std::size_t k) { return chain.points[k % chain.points.size()]; }

}  // namespace

bool refine_sparse_walls(std::vector<WallChain>& chains, const Geometry& geometry, const LayerSettings& settings,
                         RaySet& set, std::vector<double>& allowed) {
  if (settings.split_span <= 0.0) return false;
  bool split = false;
  // Per chain and new wall point: the old points it lies between (equal for an old point).
  std::vector<std::vector<std::array<int, 2>>> source(chains.size());
  std::vector<std::vector<int>> first_of(chains.size()), last_of(chains.size());
  for (std::size_t c = 0; c < chains.size(); ++c) {
    WallChain& chain = chains[c];
    const int n = static_cast<int>(chain.points.size());
    const int rb = set.ray_begin[c], re = set.ray_begin[c + 1];
    // Each wall point's first and last ray (a fan has several).
    std::vector<int>& first = first_of[c];
    std::vector<int>& last = last_of[c];
    first.assign(n, -1);
    last.assign(n, -1);
    const int base = re > rb ? set.rays[rb].wall_node : 0;
    for (int r = rb; r < re; ++r) {
      const int i = set.rays[r].wall_node - base;
      if (first[i] < 0) first[i] = r;
      last[i] = r;
    }
    const auto top = [&](int r) {
      const LayerRay& ray = set.rays[r];
      return set.wall_points[ray.wall_node] + (allowed[r] / ray.correction) * ray.direction;
    };
    WallChain out;
    out.closed = chain.closed;
    for (int i = 0; i < n; ++i) {
      out.points.push_back(chain.points[i]);
      out.curve.push_back(chain.curve[i]);
      source[c].push_back({i, i});
      const int j = i + 1 < n ? i + 1 : (chain.closed ? 0 : -1);
      if (j < 0 || first[i] < 0 || first[j] < 0) continue;
      const int a = last[i], b = first[j];
      const double h = last_layer(std::min(allowed[a], allowed[b]), settings);
      const double gap = dist(top(a), top(b));
      if (h <= 0.0 || gap <= settings.split_span * h) continue;
      const int parts = static_cast<int>(std::ceil(gap / (settings.split_span * h)));
      for (int k = 1; k < parts; ++k) {
        const double t = static_cast<double>(k) / parts;
        out.points.push_back(chain.points[i] + t * (chain.points[j] - chain.points[i]));
        out.curve.push_back(chain.curve[i]);
        source[c].push_back({i, j});
      }
      split = true;
    }
    chain = std::move(out);
  }
  if (!split) return false;
  // The new rays' thickness limits: an old point's rays keep theirs (their collisions were found
  // with the same directions, up to the smoothing), a new point's ray the smaller of its two
  // neighbours' (it lies between them).
  RaySet refined = make_rays(chains, geometry, settings);
  std::vector<double> limits(refined.rays.size(), 0.0);
  for (std::size_t c = 0; c < chains.size(); ++c) {
    const int rb = refined.ray_begin[c], re = refined.ray_begin[c + 1];
    if (re <= rb) continue;
    const int base = refined.rays[rb].wall_node;
    // A new point's ray: the directions of its segment's end rays interpolated (the smoothing would
    // tilt a ray on a straight segment as far as its neighbours' mean, and the thin cells beside it
    // would be skewed), its correction over the segment's normal.
    std::vector<int> first_new(source[c].size(), -1), last_new(source[c].size(), -1);
    for (int r = rb; r < re; ++r) {
      const int p = refined.rays[r].wall_node - base;
      if (first_new[p] < 0) first_new[p] = r;
      last_new[p] = r;
    }
    for (std::size_t p = 0; p < source[c].size(); ++p) {
      const auto [i, j] = source[c][p];
      if (i == j) continue;
      std::size_t pi = p, pj = p;
      while (source[c][pi][0] != source[c][pi][1]) --pi;
      while (source[c][pj % source[c].size()][0] != source[c][pj % source[c].size()][1]) ++pj;
      const double t = static_cast<double>(p - pi) / static_cast<double>(pj - pi);
      const Vec2 da = refined.rays[last_new[pi]].direction;
      const Vec2 db = refined.rays[first_new[pj % source[c].size()]].direction;
      LayerRay& ray = refined.rays[first_new[p]];
      ray.direction = normalized((1.0 - t) * da + t * db);
      const Vec2 a = chain_point(chains[c], pi), b = chain_point(chains[c], pj);
      ray.correction = std::max(0.2, dot(ray.direction, left_normal(a, b)));
    }
    int previous_point = -1, fan_index = 0;
    for (int r = rb; r < re; ++r) {
      const int p = refined.rays[r].wall_node - base;
      fan_index = p == previous_point ? fan_index + 1 : 0;
      previous_point = p;
      const auto [i, j] = source[c][static_cast<std::size_t>(p)];
      if (i == j) {
        const int old = std::min(first_of[c][i] + fan_index, last_of[c][i]);
        limits[r] = allowed[old];
        refined.rays[r].free_thickness = set.rays[old].free_thickness;
      } else {
        limits[r] = std::min(allowed[last_of[c][i]], allowed[first_of[c][j]]);
        refined.rays[r].free_thickness =
            std::min(set.rays[last_of[c][i]].free_thickness, set.rays[first_of[c][j]].free_thickness);
      }
    }
  }
  set = std::move(refined);
  allowed = std::move(limits);
  return true;
}

}  // namespace pdmesh::layers_detail
