// Size sources: the geometric limits on q that the base field does not know, the local feature size
// (k node spacings across every gap) and the boundary curvature (q <= R * theta), with their floor
// next to input boundary points (docs/spacing.md).
#pragma once
#include <memory>
#include <vector>

#include "geometry/geometry_tree.hpp"
#include "spacing/feature_size.hpp"

namespace pdmesh {

struct SizeSourceOptions {
  double rows_in_gap = 0.0;      // k; q <= W / k across a gap of width W; 0 = off
  double curvature_angle = 0.0;  // theta in degrees; q <= R * theta where the boundary is curved; 0 = off
  // While the boundary nodes are the input points: the sources ask for no less than this fraction of
  // the closest input segment's length, and next to the boundary the final field keeps to at least
  // floor_at(): this fraction of each segment's length, falling off at kFloorSlope per unit distance
  // from it (the upper envelope over the segments), but not above what the shortest segment nearby
  // allows (the lower envelope of upward cones). 0 = none.
  double input_boundary_floor = 0.0;
  // Whether the final field keeps floor_at() too. Boundary nodes placed by the field need only the
  // sources' floor (it stops the feature size from asking for q -> 0 toward a sharp V tip); the final
  // floor would lift a fine field back to coarse input points' spacing.
  bool final_floor = true;
  double scale = 1.0;  // multiplies every value (spacing.scale)
  bool active() const { return rows_in_gap > 0.0 || curvature_angle > 0.0; }
};

class SizeSources {
 public:
  // Keeps a reference to the tree (and its geometry), which must outlive it.
  SizeSources(const GeometryTree& tree, const SizeSourceOptions& options);
  const SizeSourceOptions& options() const { return options_; }

  // The smallest spacing the sources ask for at p, +inf where none asks for less than `limit` (the
  // gap search stops there). Thread-safe. seed (optional): the closest segment of the caller's last
  // point, which starts this point's search (faster for a nearby point; the same value), and is set
  // to this point's.
  double at(Vec2 p, double limit, int* seed = nullptr) const;
  // at(p[i], limit[i]) for i in [0, n) into q[i], the same values bit for bit, each point's closest
  // segment seeding the next point's search (seed: the caller's state between calls). The points should come in spatial
  // order: consecutive points are searched in groups (FeatureSize::closest_many, width_many).
  void at_many(const Vec2* p, const double* limit, std::size_t n, double* q, FeatureSize::SearchSeed& seed) const;
  // The input-boundary floor at p (see input_boundary_floor) when it exceeds `q`, else q. Thread-safe.
  double floor_at(Vec2 p, double q) const;
  bool has_floor() const { return options_.input_boundary_floor > 0.0 && options_.final_floor; }
  // The floor's fall-off per unit distance from a segment (docs/spacing.md, "Input boundary points").
  static constexpr double kFloorSlope = 0.5;

 private:
  const GeometryTree& tree_;
  SizeSourceOptions options_;
  std::unique_ptr<FeatureSize> feature_;
  std::vector<double> radius_;  // per segment (curvature); empty when off
  double theta_ = 0.0;          // radians
  // Whether p, whose closest boundary point is `hit`, is in the domain: the side of the segment's inward
  // normal when the closest point is inside the segment, the exact test at a vertex.
  bool inside(Vec2 p, const ClosestHit& hit) const;
  // at()'s value from p's closest segment `hit` (found) before the gap search: the curvature's q
  // (+inf when none) and the floor; sets query to the gap search's arguments (when rows_in_gap > 0).
  double before_gap(Vec2 p, const ClosestHit& hit, double limit, double& floor, FeatureSize::WidthQuery& query) const;
  // at()'s value from before_gap's q and floor and the gap search's answer (width w, apart).
  double after_gap(double q, double floor, double w, bool apart) const;
};

}  // namespace pdmesh
