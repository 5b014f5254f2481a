// Uniform size and refinement regions (refine_regions.hpp).
#include "spacing/refine_regions.hpp"

#include <algorithm>
#include <cmath>

#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/errors.hpp"
#include "core/parallel.hpp"

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
    case RegionShape::Subdomain:
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
    case RegionShape::Subdomain: {
      const int given = (r.attribute ? 1 : 0) + (r.region_name.empty() ? 0 : 1) + (r.at ? 1 : 0);
      if (given != 1)
        throw InputError(
            fmt::format("{}: a region is given by exactly one of region (an attribute or a name) and "
                        "point, got {}",
                        r.label, given));
      if (r.attribute && !std::isfinite(*r.attribute))
        throw InputError(fmt::format("{}.region = {}: must be finite", r.label, *r.attribute));
      if (r.at && !finite(*r.at))
        throw InputError(fmt::format("{}.point = [{}, {}]: must be finite", r.label, r.at->x, r.at->y));
      return;
    }
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

std::vector<RefineRegion> max_area_regions(const std::vector<GeometryRegion>& regions) {
  std::vector<RefineRegion> out;
  for (const GeometryRegion& g : regions) {
    if (!(g.max_area > 0.0)) continue;
    RefineRegion r;
    r.shape = RegionShape::Subdomain;
    r.size = max_area_spacing(g.max_area);
    r.at = g.p;
    r.label = g.file.empty() ? fmt::format("the region at ({}, {})", g.p.x, g.p.y)
                             : fmt::format("{}:{}: the region's maximum area {}", g.file, g.line, g.max_area);
    out.push_back(std::move(r));
  }
  return out;
}

namespace {

std::string attributes_of(const std::vector<GeometryRegion>& regions) {
  std::set<double> attributes;
  for (const GeometryRegion& r : regions) attributes.insert(r.attribute);
  if (attributes.empty())
    return "the geometry has no regions: a .poly file's regional attributes, a mesh file's regions or "
           "Python's Geometry(regions=...) give them";
  std::vector<std::string> names;
  for (const double a : attributes) {
    std::string name;
    for (const GeometryRegion& r : regions)
      if (r.attribute == a && !r.name.empty()) name = r.name;
    names.push_back(name.empty() ? fmt::format("{}", a) : fmt::format("{} \"{}\"", a, name));
  }
  return fmt::format("its regions: {}", fmt::join(names, ", "));
}

}  // namespace

RegionSpacing::RegionSpacing(std::unique_ptr<SpacingField> base, std::vector<RefineRegion> regions,
                             const Geometry* geometry)
    : base_(std::move(base)), regions_(std::move(regions)) {
  faces_.resize(regions_.size());
  for (std::size_t k = 0; k < regions_.size(); ++k) {
    const RefineRegion& r = regions_[k];
    check_refine_region(r);
    if (r.shape != RegionShape::Subdomain) continue;
    if (geometry == nullptr) throw InputError(fmt::format("{}: a region's size needs the geometry", r.label));
    if (!subdomains_) subdomains_ = std::make_unique<Subdomains>(*geometry);
    std::vector<int>& faces = faces_[k];
    if (r.attribute) {
      faces = subdomains_->faces_with_attribute(*r.attribute);
      if (faces.empty())
        throw InputError(fmt::format("{}.region = {}: no region of the geometry has this attribute ({})", r.label,
                                     *r.attribute, attributes_of(geometry->regions)));
    } else if (!r.region_name.empty()) {
      faces = subdomains_->faces_named(r.region_name);
      if (faces.empty())
        throw InputError(fmt::format("{}.region = \"{}\": no region of the geometry has this name ({})", r.label,
                                     r.region_name, attributes_of(geometry->regions)));
    } else {
      const int f = subdomains_->face_at(*r.at);
      if (f < 0)
        throw InputError(
            fmt::format("{}: the point ({}, {}) lies on a curve or outside every loop; give a point "
                        "inside the subdomain to size",
                        r.label, r.at->x, r.at->y));
      faces = {f};
    }
  }
}

double RegionSpacing::regions_at(Vec2 p) const {
  double q = kInfinity;
  for (std::size_t k = 0; k < regions_.size(); ++k) {
    const RefineRegion& r = regions_[k];
    if (r.size >= q) continue;
    if (r.shape == RegionShape::Subdomain) {
      if (subdomains_->in_any(faces_[k], p)) q = r.size;
    } else {
      q = std::min(q, region_size(r, p));
    }
  }
  return q;
}

double RegionSpacing::at(Vec2 p) const { return std::min(base_->at(p), regions_at(p)); }

void RegionSpacing::at_many(const std::vector<Vec2>& p, std::vector<double>& q) const {
  base_->at_many(p, q);
  // On all cores (each point writes its own value): a subdomain's test walks its faces' boundaries.
  parallel_for(
      p.size(), [&](std::size_t i) { q[i] = std::min(q[i], regions_at(p[i])); }, 1024);
}

}  // namespace pdmesh
