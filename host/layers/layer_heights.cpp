// How thick each ray's layers may be: the free thickness (the settings and the core's spacing),
// the collisions with curves and with other rays, the limit on neighbouring thickness ratios, and
// the layer count and growth that give that thickness with the first height exact.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

#include "core/predicates.hpp"
#include "layers/layers_detail.hpp"

namespace pdmesh::layers_detail {

namespace {

// The free thickness of one ray: the settings' thickness (or layer count), or less where a layer's
// height reaches the core's spacing there divided by the growth.
double free_thickness(const LayerRay& ray, Vec2 p, const LayerSettings& s, const CoreSpacing& core) {
  const double target = s.layers > 0 ? stack_height(s.first_height, s.growth, s.layers) : s.thickness;
  if (!core) return target;
  double height = 0.0, layer = s.first_height;
  while (height + layer <= target * (1.0 + 1e-12)) {
    height += layer;
    const double q = core(p + (height / ray.correction) * ray.direction);
    if (layer * s.growth >= q) return height;
    layer *= s.growth;
  }
  return target;
}

}  // namespace

void free_and_collision_limits(RaySet& set, const Geometry& geometry, const LayerSettings& settings,
                               const CoreSpacing& core_spacing, std::vector<double>& allowed) {
  const int nr = static_cast<int>(set.rays.size());
  allowed.assign(nr, 0.0);
  std::vector<Vec2> end(nr), probe(nr);
  Box box;
  double longest = 0.0;
  // End rays per segment they run along: a segment between two open chains' ends (a one-segment
  // inlet between two walls) carries two, which share it.
  std::map<int, int> sliding;
  for (const LayerRay& ray : set.rays)
    if (ray.slide_segment >= 0) ++sliding[ray.slide_segment];
  for (int r = 0; r < nr; ++r) {
    LayerRay& ray = set.rays[r];
    const Vec2 p = set.wall_points[ray.wall_node];
    ray.free_thickness = free_thickness(ray, p, settings, core_spacing);
    if (ray.slide_segment >= 0) {  // stay on the first segment of the curve it runs along
      const Segment& s = geometry.segments[ray.slide_segment];
      const double share = sliding[ray.slide_segment] > 1 ? 0.45 : 0.9;
      ray.free_thickness = std::min(ray.free_thickness, share * s.length * ray.correction);
    }
    allowed[r] = ray.free_thickness;
    end[r] = p + (ray.free_thickness / ray.correction) * ray.direction;
    // A wall at distance L cuts the ray to gap_fraction x L also where the free layer would not
    // reach it (L up to the free thickness over gap_fraction): two facing walls between one and two
    // thicknesses apart would otherwise both grow their full layers into the gap.
    probe[r] = p + (ray.free_thickness / (settings.gap_fraction * ray.correction)) * ray.direction;
    box.add(p);
    box.add(probe[r]);
    longest = std::max(longest, ray.free_thickness / ray.correction);
  }
  if (nr == 0) return;
  const int ns = static_cast<int>(geometry.segments.size());
  const double cell = std::max(longest, box.diagonal() / std::sqrt(static_cast<double>(nr) + ns) * 0.5);
  SegmentGrid grid(box, cell > 0.0 ? cell : 1.0);
  for (int k = 0; k < ns; ++k) grid.insert(k, geometry.segments[k].a, geometry.segments[k].b);
  for (int r = 0; r < nr; ++r) grid.insert(ns + r, set.wall_points[set.rays[r].wall_node], end[r]);
  std::vector<std::uint8_t> wall(geometry.curves.size(), 0);
  for (const int c : set.wall_curve) wall[c] = 1;
  // First the curves: a ray that meets a curve at distance L stops at gap_fraction x L (a curve
  // without layers only where the free layer reaches it, a wall of these layers up to the probe).
  for (int r = 0; r < nr; ++r) {
    const LayerRay& ray = set.rays[r];
    const Vec2 p = set.wall_points[ray.wall_node], e = probe[r];
    const double length = norm(e - p), reach = norm(end[r] - p);
    grid.query(p, e, [&](int id) {
      if (id >= ns) return;
      const Segment& s = geometry.segments[id];
      if (s.a == p || s.b == p || !segments_intersect(p, e, s.a, s.b)) return;
      const double at = intersection_parameter(p, e, s.a, s.b) * length;
      if (!wall[s.curve] && at > reach) return;
      allowed[r] = std::min(allowed[r], settings.gap_fraction * at * ray.correction);
    });
  }
  // Then the rays as cut there: of two rays that cross at X, the one whose wall node is farther from
  // X stops at cross_fraction of that distance, and the other too when its distance is comparable
  // (at least half), so that a long ray passing close to another wall does not cut that wall's rays.
  std::vector<Vec2> cut(nr);
  for (int r = 0; r < nr; ++r)
    cut[r] = set.wall_points[set.rays[r].wall_node] + (allowed[r] / set.rays[r].correction) * set.rays[r].direction;
  std::vector<double> limit = allowed;
  for (int r = 0; r < nr; ++r) {
    const LayerRay& ray = set.rays[r];
    const Vec2 p = set.wall_points[ray.wall_node], e = cut[r];
    const double length = norm(e - p);
    grid.query(p, end[r], [&](int id) {
      if (id < ns) return;
      const int o = id - ns;
      const LayerRay& other = set.rays[o];
      const Vec2 q = set.wall_points[other.wall_node];
      if (other.wall_node == ray.wall_node || q == p) return;
      if (!segments_cross_properly(p, e, q, cut[o])) return;
      const double a = intersection_parameter(p, e, q, cut[o]) * length;
      const double b = intersection_parameter(q, cut[o], p, e) * norm(cut[o] - q);
      if (a >= 0.5 * b) limit[r] = std::min(limit[r], settings.cross_fraction * a * ray.correction);
    });
  }
  allowed = std::move(limit);
}

void leave_room_for_the_core(const RaySet& set, const Geometry& geometry, const LayerSettings& settings,
                             std::vector<double>& allowed) {
  const int nr = static_cast<int>(set.rays.size());
  if (nr == 0 || settings.core_room <= 0.0) return;
  // Each ray's distance to the first curve along it, within the reach the collision limits probe
  // (the free thickness over gap_fraction), and whether that curve carries these layers.
  std::vector<double> facing(nr, std::numeric_limits<double>::infinity());
  // 0: not facing it (an oblique hit), 1: a curve without layers, 2: a wall of these layers.
  std::vector<std::uint8_t> shared(nr, 0);
  std::vector<Vec2> probe(nr);
  Box box;
  double longest = 0.0;
  for (int r = 0; r < nr; ++r) {
    const LayerRay& ray = set.rays[r];
    const Vec2 p = set.wall_points[ray.wall_node];
    probe[r] = p + (ray.free_thickness / (settings.gap_fraction * ray.correction)) * ray.direction;
    box.add(p);
    box.add(probe[r]);
    longest = std::max(longest, dist(p, probe[r]));
  }
  const int ns = static_cast<int>(geometry.segments.size());
  const double cell = std::max(longest, box.diagonal() / std::sqrt(static_cast<double>(nr) + ns) * 0.5);
  SegmentGrid grid(box, cell > 0.0 ? cell : 1.0);
  for (int k = 0; k < ns; ++k) grid.insert(k, geometry.segments[k].a, geometry.segments[k].b);
  std::vector<std::uint8_t> wall(geometry.curves.size(), 0);
  for (const int c : set.wall_curve) wall[c] = 1;
  for (int r = 0; r < nr; ++r) {
    const LayerRay& ray = set.rays[r];
    if (ray.slide_segment >= 0) continue;  // its side lies on the curve it runs along
    const Vec2 p = set.wall_points[ray.wall_node], e = probe[r];
    const double length = norm(e - p);
    grid.query(p, e, [&](int id) {
      const Segment& s = geometry.segments[id];
      if (s.a == p || s.b == p || !segments_intersect(p, e, s.a, s.b)) return;
      // A wall node inserted by the refinement lies on its own segment.
      const Vec2 d = s.b - s.a;
      if (std::abs(cross(d, p - s.a)) <= 1e-12 * dot(d, d)) return;
      const double at = intersection_parameter(p, e, s.a, s.b) * length;
      if (at >= facing[r]) return;
      facing[r] = at;
      // Only a curve met within 45 degrees of head-on faces the ray's front (a wedge, a slot): at
      // a concave corner the rays lean towards its bisector and meet the other wall obliquely,
      // beside that wall's layer rather than opposite it.
      shared[r] = std::abs(cross(normalized(d), ray.direction)) >= std::cos(0.25 * std::numbers::pi)
                      ? (wall[s.curve] ? 2 : 1)
                      : 0;
    });
  }
  // The front's edge at each ray: the longer of the distances from its top to its neighbours'
  // tops in the chain, at the thickness the grading will leave. Two rounds: a thinner layer moves
  // the tops of converging or diverging rays.
  for (int round = 0; round < 2; ++round) {
    std::vector<double> graded = allowed;
    grade_thickness(set, settings, graded);
    const auto top = [&](int r) {
      const LayerRay& ray = set.rays[r];
      return set.wall_points[ray.wall_node] + (graded[r] / ray.correction) * ray.direction;
    };
    for (std::size_t c = 0; c + 1 < set.ray_begin.size(); ++c) {
      const int b = set.ray_begin[c], e = set.ray_begin[c + 1], n = e - b;
      const bool closed = set.closed[c] != 0;
      for (int k = 0; k < n; ++k) {
        const int r = b + k;
        if (!std::isfinite(facing[r]) || shared[r] == 0) continue;
        double edge = 0.0;
        for (const int j : {k - 1, k + 1}) {
          if (!closed && (j < 0 || j >= n)) continue;
          edge = std::max(edge, dist(top(r), top(b + (j + n) % n)));
        }
        const double gap = facing[r] * set.rays[r].correction;
        // A facing layer of these settings takes its share of the gap from the other side.
        const double room = shared[r] == 2 ? 0.5 * (gap - settings.core_room * edge) : gap - settings.core_room * edge;
        allowed[r] = std::min(allowed[r], room < settings.first_height ? 0.0 : room);
      }
    }
  }
}

void grade_thickness(const RaySet& set, const LayerSettings& settings, std::vector<double>& allowed) {
  const double max_jump = settings.max_jump, max_slope = settings.max_slope;
  // A ray without a layer (below the first height) lets its neighbour have one layer: a stair of
  // one layer where the layer ends, not a ramp of many thin rays up from a tiny thickness.
  const double floor = settings.first_height / max_jump;
  for (std::size_t c = 0; c + 1 < set.ray_begin.size(); ++c) {
    const int b = set.ray_begin[c], e = set.ray_begin[c + 1], n = e - b;
    if (n < 2) continue;
    const bool closed = set.closed[c] != 0;
    // A few passes that lower each thickness to its neighbourhood's mean: fronts cut by collisions
    // come out smooth instead of saw-toothed.
    for (int pass = 0; pass < 4; ++pass) {
      std::vector<double> next(allowed.begin() + b, allowed.begin() + e);
      for (int k = 0; k < n; ++k) {
        if (!closed && (k == 0 || k == n - 1)) continue;
        const double mean = (allowed[b + (k + n - 1) % n] + allowed[b + k] + allowed[b + (k + 1) % n]) / 3.0;
        next[k] = std::min(next[k], mean);
      }
      std::copy(next.begin(), next.end(), allowed.begin() + b);
    }
    // Sweeps until nothing changes; each sweep passes a limit along the whole chain.
    for (int round = 0; round < n + 2; ++round) {
      bool changed = false;
      auto limit = [&](int r, int from) {
        const LayerRay& a = set.rays[r];
        const LayerRay& o = set.rays[from];
        const double turn = std::acos(std::clamp(dot(a.direction, o.direction), -1.0, 1.0));
        const double d = dist(set.wall_points[a.wall_node], set.wall_points[o.wall_node]) +
                         turn * std::min(allowed[r], allowed[from]);
        const double cap = std::min(max_jump * std::max(allowed[from], floor), allowed[from] + max_slope * d);
        if (allowed[r] > cap) {
          allowed[r] = cap;
          changed = true;
        }
      };
      for (int k = 1; k < n; ++k) limit(b + k, b + k - 1);
      if (closed) limit(b, e - 1);
      for (int k = n - 2; k >= 0; --k) limit(b + k, b + k + 1);
      if (closed) limit(e - 1, b);
      if (!changed) break;
    }
  }
}

void layer_counts(const RaySet& set, const LayerSettings& settings, const std::vector<double>& allowed,
                  std::vector<int>& count, std::vector<double>& top) {
  const double h1 = settings.first_height, g = settings.growth;
  const int nr = static_cast<int>(set.rays.size());
  count.assign(nr, 0);
  top.assign(nr, 0.0);
  for (int r = 0; r < nr; ++r) {
    const double a = allowed[r];
    if (a < h1 * (1.0 - 1e-12)) continue;
    // The fewest layers of the settings' stack that reach a; the last one ends at a.
    int n = layers_reaching(h1, g, a);
    const double last = a - stack_height(h1, g, n - 1);
    // A last layer thinner than a quarter of the one below joins it (growth <= 1.25 g there), except
    // the first layer, whose height is the settings': above it such a layer is left out (the ray's
    // top is h1, below its allowed thickness; a layer's end steps down to it).
    if (n >= 2 && last < 0.25 * h1 * std::pow(g, n - 2)) --n;
    count[r] = n;
    top[r] = std::abs(stack_height(h1, g, n) - a) <= 1e-9 * a ? stack_height(h1, g, n) : (n == 1 ? h1 : a);
  }
  // A column whose neighbours both have no layer is a spike where a layer ended (an acute corner's
  // ray, whose cells with its neighbours' wall nodes would be as flat as the corner): none either.
  std::vector<int> spike;
  for (std::size_t c = 0; c + 1 < set.ray_begin.size(); ++c) {
    const int b = set.ray_begin[c], e = set.ray_begin[c + 1], n = e - b;
    if (n < 3) continue;
    for (int k = 0; k < n; ++k) {
      if (set.closed[c] == 0 && (k == 0 || k == n - 1)) continue;
      const int r = b + k;
      if (count[r] > 0 && count[b + (k + n - 1) % n] == 0 && count[b + (k + 1) % n] == 0) spike.push_back(r);
    }
  }
  for (const int r : spike) {
    count[r] = 0;
    top[r] = 0.0;
  }
}

}  // namespace pdmesh::layers_detail
