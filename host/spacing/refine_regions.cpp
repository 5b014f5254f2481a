// Uniform size and refinement regions (refine_regions.hpp).
#include "spacing/refine_regions.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/errors.hpp"

namespace pdmesh {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

double distance_to_segment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double l2 = norm2(ab);
  const double t = l2 > 0.0 ? std::clamp(dot(p - a, ab) / l2, 0.0, 1.0) : 0.0;
  return dist(p, Vec2{a.x + t * ab.x, a.y + t * ab.y});
}

bool finite(Vec2 p) { return std::isfinite(p.x) && std::isfinite(p.y); }

}  // namespace

double region_size(const RefineRegion& r, Vec2 p) {
  switch (r.shape) {
    case RegionShape::Box:
      return r.box.contains(p) ? r.size : kInfinity;
    case RegionShape::Disc:
      return dist(p, r.centre) <= r.radius ? r.size : kInfinity;
    case RegionShape::Points:
      for (const Vec2 q : r.points)
        if (dist(p, q) <= r.radius) return r.size;
      return kInfinity;
    case RegionShape::Polyline:
      for (std::size_t k = 0; k + 1 < r.points.size(); ++k)
        if (distance_to_segment(p, r.points[k], r.points[k + 1]) <= r.radius) return r.size;
      return kInfinity;
  }
  return kInfinity;
}

void check_refine_region(const RefineRegion& r) {
  if (!(r.size > 0.0) || !std::isfinite(r.size))
    throw InputError(fmt::format("{}.size = {}: must be a finite number > 0", r.label, r.size));
  switch (r.shape) {
    case RegionShape::Box:
      if (!finite(r.box.lo) || !finite(r.box.hi) || !(r.box.lo.x < r.box.hi.x && r.box.lo.y < r.box.hi.y))
        throw InputError(fmt::format("{}.box = [{}, {}, {}, {}]: needs finite x0 < x1 and y0 < y1", r.label, r.box.lo.x,
                                     r.box.lo.y, r.box.hi.x, r.box.hi.y));
      return;
    case RegionShape::Disc:
      if (!finite(r.centre))
        throw InputError(fmt::format("{}.centre = [{}, {}]: must be finite", r.label, r.centre.x, r.centre.y));
      break;
    case RegionShape::Points:
    case RegionShape::Polyline: {
      const std::size_t least = r.shape == RegionShape::Points ? 1 : 2;
      if (r.points.size() < least)
        throw InputError(fmt::format("{}.points: a {} needs at least {} point{}, got {}", r.label,
                                     r.shape == RegionShape::Points ? "points region" : "polyline", least,
                                     least == 1 ? "" : "s", r.points.size()));
      for (std::size_t k = 0; k < r.points.size(); ++k)
        if (!finite(r.points[k]))
          throw InputError(
              fmt::format("{}.points[{}] = [{}, {}]: must be finite", r.label, k, r.points[k].x, r.points[k].y));
      break;
    }
  }
  if (!(r.radius > 0.0) || !std::isfinite(r.radius))
    throw InputError(fmt::format("{}.radius = {}: must be a finite number > 0", r.label, r.radius));
}

RegionSpacing::RegionSpacing(std::unique_ptr<SpacingField> base, std::vector<RefineRegion> regions)
    : base_(std::move(base)), regions_(std::move(regions)) {
  for (const RefineRegion& r : regions_) check_refine_region(r);
}

double RegionSpacing::regions_at(Vec2 p) const {
  double q = kInfinity;
  for (const RefineRegion& r : regions_) q = std::min(q, region_size(r, p));
  return q;
}

double RegionSpacing::at(Vec2 p) const { return std::min(base_->at(p), regions_at(p)); }

void RegionSpacing::at_many(const std::vector<Vec2>& p, std::vector<double>& q) const {
  base_->at_many(p, q);
  for (std::size_t i = 0; i < p.size(); ++i) q[i] = std::min(q[i], regions_at(p[i]));
}

}  // namespace pdmesh
