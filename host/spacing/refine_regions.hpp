// Sizes the way users state them (docs/spacing.md, "Uniform size and refinement regions"): a uniform
// base size (spacing.size, --size) and refinement regions ([[refine]]: boxes, discs, points and
// polylines with a size and a radius of influence, as Gmsh's Box, Ball and Distance + Threshold
// fields, and subdomains of the geometry, as Gmsh's sizes per surface and Triangle's maximum areas
// per region), each the minimum with the base field before the pipeline's sources and gradation.
#pragma once
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/vec2.hpp"
#include "geometry/geometry.hpp"
#include "spacing/spacing_field.hpp"
#include "spacing/subdomains.hpp"

namespace pdmesh {

enum class RegionShape { Box, Disc, Points, Polyline, Subdomain };

struct RefineRegion {
  RegionShape shape = RegionShape::Box;
  double size = 0.0;           // the size asked for inside the region
  Box box{};                   // Box: [x0, x1] x [y0, y1]
  Vec2 centre{};               // Disc
  double radius = 0.0;         // Disc: its radius; Points, Polyline: the distance within which `size` holds
  std::vector<Vec2> points{};  // Points (>= 1), Polyline (>= 2)
  // Subdomain: the geometry's subdomains (spacing/subdomains.hpp) of one regional attribute, of one
  // region name, or the one holding a point; exactly one of the three.
  std::optional<double> attribute{};
  std::string region_name{};
  std::optional<Vec2> at{};
  std::string label{};  // how it was given, e.g. "refine[0]" or "case.toml:12: refine[0]", for messages
};

// The region's size at p: `size` inside it (a box or disc, or within `radius` of a point or of the
// polyline), +inf outside; a Subdomain region needs its geometry (RegionSpacing) and is +inf here.
double region_size(const RefineRegion& region, Vec2 p);

// Throws InputError naming the region's label, the key and the value on a size that is not finite
// and > 0, a box with x0 >= x1 or y0 >= y1, a radius that is not finite and > 0, too few points or a
// point that is not finite, a Subdomain region without exactly one of attribute, name and point.
void check_refine_region(const RefineRegion& region);

// The regions of a .poly file's maximum areas (GeometryRegion::max_area, Triangle's -a): the
// subdomain holding each such region point sized max_area_spacing(A).
std::vector<RefineRegion> max_area_regions(const std::vector<GeometryRegion>& regions);

// The same size everywhere (spacing.size). Thread-safe.
class UniformSpacing final : public SpacingField {
 public:
  explicit UniformSpacing(double size) : size_(size) {}
  double at(Vec2) const override { return size_; }
  void at_many(const std::vector<Vec2>& p, std::vector<double>& q) const override { q.assign(p.size(), size_); }

 private:
  double size_;
};

// min(base(x), every region's size at x); owns the base. Thread-safe as the base is. Batches go to
// the base's own at_many (and its closest segments through). InputError from check_refine_region,
// and for a Subdomain region without `geometry`, or whose attribute or name is no region's of the
// geometry, or whose point lies on a curve or outside the domain's faces.
class RegionSpacing final : public SpacingField {
 public:
  RegionSpacing(std::unique_ptr<SpacingField> base, std::vector<RefineRegion> regions,
                const Geometry* geometry = nullptr);
  double at(Vec2 p) const override;
  void at_many(const std::vector<Vec2>& p, std::vector<double>& q) const override;
  const SpacingField& base() const { return *base_; }
  const std::vector<RefineRegion>& regions() const { return regions_; }

 private:
  double regions_at(Vec2 p) const;
  std::unique_ptr<SpacingField> base_;
  std::vector<RefineRegion> regions_;
  std::unique_ptr<Subdomains> subdomains_;  // when a region is a Subdomain
  std::vector<std::vector<int>> faces_;     // per region, a Subdomain's faces
};

}  // namespace pdmesh
