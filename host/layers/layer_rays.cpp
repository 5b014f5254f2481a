// The rays of the layer generator: one per wall vertex along the smoothed normal, a fan of rays at
// a sharp convex vertex (a trailing edge), and each ray's height correction.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "layers/layers_detail.hpp"

namespace pdmesh::layers_detail {

namespace {

// The most elements a fan gets from the core spacing rule below.
constexpr int kMaxFanElements = 32;

struct Vertex {
  Vec2 n_in, n_out;  // left normals of the segments arriving and leaving (equal at an open end)
  bool has_in = false, has_out = false;
  double turn = 0.0;  // > 0 turning left (towards the domain: concave), < 0 convex
  int fan = 0;        // fan elements (0: a single ray)
};

}  // namespace

namespace {

// The segment of another curve than the chain's that starts or ends at p and leaves into the domain
// side of the wall normal n (cosine > 0.2), the most normal one; -1 when none.
int slide_segment(const Geometry& geometry, Vec2 p, Vec2 n, const std::vector<int>& chain_curves, Vec2& direction) {
  int best = -1;
  double best_cos = 0.2;
  for (std::size_t k = 0; k < geometry.segments.size(); ++k) {
    const Segment& s = geometry.segments[k];
    if (!(s.a == p || s.b == p)) continue;
    if (std::find(chain_curves.begin(), chain_curves.end(), s.curve) != chain_curves.end()) continue;
    const Vec2 d = normalized((s.a == p ? s.b : s.a) - p);
    if (dot(d, n) > best_cos) {
      best_cos = dot(d, n);
      best = static_cast<int>(k);
      direction = d;
    }
  }
  return best;
}

}  // namespace

RaySet make_rays(const std::vector<WallChain>& chains, const Geometry& geometry, const LayerSettings& settings,
                 const CoreSpacing& core_spacing) {
  RaySet set;
  const double fan_turn = settings.fan_angle_deg * std::numbers::pi / 180.0;
  const double max_tilt = settings.max_ray_tilt_deg * std::numbers::pi / 180.0;
  // Both normals of a ray's segments within max_tilt: the cosine to each at least this.
  const double min_cos = max_tilt > 0.0 ? std::max(0.3, std::cos(max_tilt)) : 0.3;
  const double target =
      settings.layers > 0 ? stack_height(settings.first_height, settings.growth, settings.layers) : settings.thickness;
  for (const WallChain& chain : chains) {
    set.ray_begin.push_back(static_cast<int>(set.rays.size()));
    set.closed.push_back(chain.closed ? 1 : 0);
    const int n = static_cast<int>(chain.points.size());
    const int base = static_cast<int>(set.wall_points.size());
    for (int i = 0; i < n; ++i) {
      set.wall_points.push_back(chain.points[i]);
      set.wall_curve.push_back(chain.curve[i]);
    }
    std::vector<Vertex> vx(n);
    for (int i = 0; i < n; ++i) {
      Vertex& v = vx[i];
      const int prev = chain.closed ? (i + n - 1) % n : i - 1;
      const int next = chain.closed ? (i + 1) % n : i + 1;
      v.has_in = prev >= 0;
      v.has_out = next < n;
      if (v.has_in) v.n_in = left_normal(chain.points[prev], chain.points[i]);
      if (v.has_out) v.n_out = left_normal(chain.points[i], chain.points[next]);
      if (!v.has_in) v.n_in = v.n_out;
      if (!v.has_out) v.n_out = v.n_in;
      if (v.has_in && v.has_out) {
        // The turn from the arriving to the leaving direction equals the turn of the normals.
        v.turn = std::atan2(cross(v.n_in, v.n_out), dot(v.n_in, v.n_out));
        if (-v.turn > fan_turn || (max_tilt > 0.0 && -v.turn > 2.0 * max_tilt)) {
          v.fan = std::max(
              2, static_cast<int>(std::ceil(settings.fan_elements_per_pi * -v.turn / std::numbers::pi - 1e-9)));
          // Enough elements that the fan's front edges at the full thickness are no longer than
          // the core's spacing there (at most kMaxFanElements): the core meets them with
          // triangles of its own size rather than with flat ones.
          if (core_spacing) {
            const Vec2 mid = chain.points[i] + target * rotated(v.n_in, 0.5 * v.turn);
            const double q = core_spacing(mid);
            if (q > 0.0)
              v.fan = std::clamp(static_cast<int>(std::ceil(-v.turn * target / q - 1e-9)), v.fan, kMaxFanElements);
          }
        }
      }
    }
    // Directions: fans fixed, the others the bisector, then smoothed (Jacobi passes over the
    // neighbours' rays; a fan neighbour offers its nearer edge ray).
    std::vector<Vec2> dir(n);
    for (int i = 0; i < n; ++i) dir[i] = normalized(vx[i].n_in + vx[i].n_out);
    std::vector<int> slide(n, -1);
    if (!chain.closed)
      for (const int i : {0, n - 1}) slide[i] = slide_segment(geometry, chain.points[i], dir[i], chain.curve, dir[i]);
    auto near_ray = [&](int j, bool from_before) {  // neighbour j's ray seen from its side
      if (vx[j].fan == 0) return dir[j];
      return from_before ? vx[j].n_out : vx[j].n_in;
    };
    for (int pass = 0; pass < settings.smoothing_passes; ++pass) {
      std::vector<Vec2> next_dir = dir;
      for (int i = 0; i < n; ++i) {
        if (vx[i].fan > 0 || !vx[i].has_in || !vx[i].has_out) continue;
        const int prev = (i + n - 1) % n, next = (i + 1) % n;
        if (!chain.closed && (i == 0 || i == n - 1)) continue;
        const Vec2 s = normalized(2.0 * dir[i] + near_ray(prev, true) + near_ray(next, false));
        // Keep the ray clearly on the domain side of both its wall segments (within max_tilt of
        // both normals where that is set), and its first node's
        // heights over both within 1 % of the mean (a ray tilted from the bisector is higher over
        // one segment than over the other): the largest step towards s that does.
        auto fits = [&](Vec2 d) {
          const double a = dot(d, vx[i].n_in), b = dot(d, vx[i].n_out), c = 0.5 * (a + b);
          return a > min_cos && b > min_cos && std::abs(a / c - 1.0) <= 0.01 && std::abs(b / c - 1.0) <= 0.01;
        };
        for (const double w : {1.0, 0.5, 0.25, 0.125}) {
          const Vec2 d = normalized((1.0 - w) * dir[i] + w * s);
          if (fits(d)) {
            next_dir[i] = d;
            break;
          }
        }
      }
      dir = std::move(next_dir);
    }
    for (int i = 0; i < n; ++i) {
      const Vertex& v = vx[i];
      LayerRay ray;
      ray.wall_node = base + i;
      ray.curve = chain.curve[i];
      ray.slide_segment = slide[i];
      if (v.fan == 0) {
        ray.direction = dir[i];
        ray.correction = std::max(0.2, 0.5 * (dot(dir[i], v.n_in) + dot(dir[i], v.n_out)));
        set.rays.push_back(ray);
        continue;
      }
      ray.fan = true;
      set.fan_sizes.push_back(v.fan);
      for (int j = 0; j <= v.fan; ++j) {
        ray.direction = normalized(rotated(v.n_in, v.turn * j / v.fan));
        ray.correction = 1.0;
        set.rays.push_back(ray);
      }
    }
  }
  set.ray_begin.push_back(static_cast<int>(set.rays.size()));
  return set;
}

double stack_height(double h1, double g, int n) {
  if (g == 1.0) return n * h1;
  return h1 * (std::pow(g, n) - 1.0) / (g - 1.0);
}

int layers_reaching(double h1, double g, double t) {
  int n = 1;
  while (stack_height(h1, g, n) < t * (1.0 - 1e-12)) ++n;
  return n;
}

}  // namespace pdmesh::layers_detail
