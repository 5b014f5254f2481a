// The subdomains of a geometry: the faces its curves (boundaries and embedded constraints) cut the
// plane into (geometry/planar_faces), each with the regional attribute of the region points in it,
// for sizes given per subdomain ([[refine]] shape = "region", a .poly file's maximum areas:
// docs/spacing.md, "Sizes per region"). A subdomain is closed: a point on a curve between two
// subdomains belongs to both, so that the finer size holds along the interface.
#pragma once
#include <optional>
#include <vector>

#include "core/vec2.hpp"
#include "geometry/geometry.hpp"
#include "geometry/planar_faces.hpp"

namespace pdmesh {

class Subdomains {
 public:
  // The faces of the geometry's segments (ends that coincide are one vertex; build_geometry snaps
  // curve ends into joints) and the attribute of each: that of the last of `geometry.regions` whose
  // point lies in it (Triangle's rule), none where no region point does.
  explicit Subdomains(const Geometry& geometry);

  int face_count() const { return static_cast<int>(faces_.outer.size()); }
  // The bounded face holding p strictly inside (the innermost), -1 when p lies on a curve or in no
  // bounded face.
  int face_at(Vec2 p) const;
  // The faces whose regional attribute is `attribute`, or whose region's name is `name`.
  std::vector<int> faces_with_attribute(double attribute) const;
  std::vector<int> faces_named(const std::string& name) const;
  // Whether p lies in the closure of one of `faces`: inside or on its outer boundary and strictly
  // inside none of the smaller faces (those nested in it). Thread-safe.
  bool in_any(const std::vector<int>& faces, Vec2 p) const;

 private:
  // A closed cycle of the graph with its edges bucketed in horizontal slabs: the crossing count of
  // the ray from p towards +x and the on-edge test look at p's slab only.
  struct IndexedCycle {
    std::vector<std::array<Vec2, 2>> edges;
    Box box;
    double slab_height = 1.0;
    std::vector<std::vector<int>> slabs;  // edge indices per slab
  };
  enum class Side { Outside, On, Inside };
  static IndexedCycle index_cycle(const std::vector<Vec2>& vertices, const std::vector<int>& cycle);
  static Side side_of(const IndexedCycle& c, Vec2 p);

  std::vector<Vec2> vertices_;
  std::vector<std::array<int, 2>> edges_;
  PlanarFaces faces_;
  std::vector<IndexedCycle> cycles_;                // per face, its outer boundary
  std::vector<std::optional<std::size_t>> region_;  // per face, the index in `regions_` of its region
  std::vector<GeometryRegion> regions_;
};

}  // namespace pdmesh
