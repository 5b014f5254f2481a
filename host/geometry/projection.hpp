// geometry.projection (docs/geometry-input.md, "Longitude and latitude"): lon/lat geometry meshed in a
// local equirectangular projection about its bounding box's centre, in metres, and the outputs'
// coordinates mapped back to lon/lat.
#pragma once
#include <vector>

#include "geometry/geometry.hpp"

namespace pdmesh {

enum class ProjectionKind { None, Equirectangular };

// x = R cos(lat0) (lon - lon0), y = R (lat - lat0), angles in radians, R the mean Earth radius.
struct Equirectangular {
  static constexpr double kEarthRadius = 6371008.8;  // metres (IUGG mean radius R1)
  double lon0 = 0.0, lat0 = 0.0;                     // degrees: the centre of the data's bounding box
  Vec2 forward(Vec2 lonlat) const;
  Vec2 inverse(Vec2 xy) const;
  void inverse(std::vector<Vec2>& points) const;
};

// Checks that every point of `raw` is lon/lat (|lon| <= 180, |lat| <= 90; InputError naming the file,
// line and value otherwise, and for a centre at a pole), projects it in place about the centre of its
// bounding box, and returns the projection.
Equirectangular project_lonlat(RawGeometry& raw);

}  // namespace pdmesh
