// What the parts of the layer generator share (host/layers/*.cpp): the wall chains, a uniform grid
// over segments, and the steps of build_boundary_layers().
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/vec2.hpp"
#include "geometry/geometry.hpp"
#include "layers/boundary_layers.hpp"

namespace pdmesh::layers_detail {

// A run of wall curves joined end to end, oriented so that the domain lies on its left.
struct WallChain {
  std::vector<Vec2> points;  // a closed chain does not repeat its first point
  std::vector<int> curve;    // per point: the curve of the segment that leaves it (the last: the one arriving)
  bool closed = false;
  int segment_count() const { return closed ? static_cast<int>(points.size()) : static_cast<int>(points.size()) - 1; }
};

// The wall chains of the given curves (geometry/loops give the order and the side of the domain).
std::vector<WallChain> wall_chains(const Geometry& geometry, const std::vector<int>& wall_curves);

// Unit left normal of the segment a -> b.
inline Vec2 left_normal(Vec2 a, Vec2 b) {
  const Vec2 d = b - a;
  const double l = norm(d);
  return {-d.y / l, d.x / l};
}
inline Vec2 normalized(Vec2 v) { return (1.0 / norm(v)) * v; }
inline Vec2 rotated(Vec2 v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v.x - s * v.y, s * v.x + c * v.y};
}

// A uniform grid over segments: each segment is listed in the cells its bounding box overlaps.
// Queries return every segment whose cells a box overlaps, each once (a superset of those that meet it).
class SegmentGrid {
 public:
  SegmentGrid(const Box& box, double cell);
  void insert(int id, Vec2 a, Vec2 b);
  // Calls visit(id) for each stored segment listed in a cell that the box of a, b overlaps.
  template <class Visit>
  void query(Vec2 a, Vec2 b, Visit&& visit) {
    int x0, y0, x1, y1;
    if (!cell_range(a, b, x0, y0, x1, y1)) return;
    ++stamp_;
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        for (const int id : cells_[static_cast<std::size_t>(y) * nx_ + x]) {
          if (id >= static_cast<int>(seen_.size())) seen_.resize(id + 1, 0);
          if (seen_[id] == stamp_) continue;
          seen_[id] = stamp_;
          visit(id);
        }
  }

 private:
  bool cell_range(Vec2 a, Vec2 b, int& x0, int& y0, int& x1, int& y1) const;
  Box box_;
  double cell_;
  int nx_ = 1, ny_ = 1;
  std::vector<std::vector<int>> cells_;
  std::vector<std::uint32_t> seen_;
  std::uint32_t stamp_ = 0;
};

// Where segments p -> q and a -> b meet, as the parameter along p -> q (they must intersect).
double intersection_parameter(Vec2 p, Vec2 q, Vec2 a, Vec2 b);

// The rays of every chain, with their directions, corrections and fans (layer_rays.cpp). Rays of
// chain c are [ray_begin[c], ray_begin[c+1]); a ray's wall_node indexes `wall_points`.
struct RaySet {
  std::vector<Vec2> wall_points;
  std::vector<int> wall_curve;
  std::vector<LayerRay> rays;
  std::vector<int> ray_begin;
  std::vector<std::uint8_t> closed;
  std::vector<int> fan_sizes;
};
// An open chain's end ray runs along the first segment of the curve that continues the boundary
// there (when that segment leaves into the domain side, more than acos 0.2 from the wall), else along
// the wall's normal. A fan has ceil(fan_elements_per_pi x turn / pi) elements (at least 2), or more
// (up to 32) so that its edges at the full thickness are no longer than core_spacing there.
RaySet make_rays(const std::vector<WallChain>& chains, const Geometry& geometry, const LayerSettings& settings,
                 const CoreSpacing& core_spacing);

// Cumulative height of n layers: h1 (g^n - 1) / (g - 1) (n h1 for g = 1).
double stack_height(double h1, double g, int n);

// The fewest layers (at least 1) whose stack_height reaches t, up to a relative 1e-12.
int layers_reaching(double h1, double g, double t);

// The thickness each ray may have (layer_heights.cpp): the free thickness (settings, core spacing),
// cut where a ray meets a curve of the geometry or another ray.
void free_and_collision_limits(RaySet& set, const Geometry& geometry, const LayerSettings& settings,
                               const CoreSpacing& core_spacing, std::vector<double>& allowed);
// Limits neighbouring rays of each chain to thickness ratios <= max_jump and thickness changes
// <= max_slope x their distance (only lowers); a ray below the first height (no layer) counts as
// first_height / max_jump for the ratio, so that its neighbour may have one layer.
void grade_thickness(const RaySet& set, const LayerSettings& settings, std::vector<double>& allowed);
// Where fronts close in (a wedge, a strait, a slot's tip): a ray that meets a curve at distance L
// (within the collision limits' probe, within 45 degrees of head-on) leaves the core at least
// core_room x the front's edge e
// there: its thickness is at most (L - core_room e) / 2 facing a wall of these layers (whose layer
// takes as much), L - core_room e facing another curve, and 0 (no layer) where that is below the
// first height. e is the longer distance from its top to its neighbours' tops at the graded
// thickness. Nothing with core_room 0.
void leave_room_for_the_core(const RaySet& set, const Geometry& geometry, const LayerSettings& settings,
                             std::vector<double>& allowed);
// The layer count and top height of each ray for its allowed thickness: every layer but the last
// of the settings' stack (first height and growth exact, so that neighbouring rays' layers match),
// the last ending at the allowed thickness (1/4 to 1.25 times the stack's next layer).
void layer_counts(const RaySet& set, const LayerSettings& settings, const std::vector<double>& allowed,
                  std::vector<int>& count, std::vector<double>& top);

// Splits each wall segment whose neighbouring rays' top nodes (at their allowed thickness, graded as
// grade_thickness will grade it) are more than split_span x the thinner of their last layers apart
// into equal parts that are not, and remakes the
// rays (make_rays) and their limits (an inserted ray: the smaller of its neighbours'; its wall node
// lies on the segment, whose collision test would stop it at once) (wall_refinement.cpp); the fans
// are sized with core_spacing as make_rays sized them before. Returns whether any segment was split.
bool refine_sparse_walls(std::vector<WallChain>& chains, const Geometry& geometry, const LayerSettings& settings,
                         const CoreSpacing& core_spacing, RaySet& set, std::vector<double>& allowed);

// Which columns are zipped with which, from which layer to which (column_merge.cpp).
struct ColumnPair {
  int a = -1, b = -1;  // neighbouring rays at these layers, a before b in the chain
  int from = 0;        // the layer both start at (0: the wall)
  int to = -1;         // the layer both end at (a merge's layer), -1: their tops
};
struct ColumnMerge {
  int ray = -1, left = -1, right = -1;  // the ray whose column ends, its neighbours there
  int layer = 0;                        // its last node's layer
};
struct ColumnPlan {
  std::vector<ColumnPair> pairs;    // every chain's neighbouring rays in chain order, then the pairs merges make
  std::vector<ColumnMerge> merges;  // in the order the layers are passed
  std::vector<int> end;             // per ray: the layer its column ends at, -1: its top
};
// The columns of every chain: ray r's column ends at layer k where its current neighbours' nodes
// at layer k + 1 are at most merge_span x their layer's height apart (not at fans, sliding end rays,
// the ends of an open chain, or layers that are not on the settings' stack for all three; never
// two neighbours at one layer). The middle ray of a fan of two elements ends at its last layer
// where the fan's edge rays' tops are at most fan_span x that layer apart (0: never).
// height[r]: ray r's node heights over the wall (0 first).
ColumnPlan plan_columns(const RaySet& set, const std::vector<std::vector<double>>& height, double merge_span,
                        double fan_span);

}  // namespace pdmesh::layers_detail
