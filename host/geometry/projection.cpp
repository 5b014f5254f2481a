// The local equirectangular projection of lon/lat geometry (projection.hpp).
#include "geometry/projection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "core/errors.hpp"

namespace pdmesh {

namespace {

constexpr double kRad = std::numbers::pi / 180.0;

void check_lonlat(Vec2 p, const std::string& file, int line, const char* what) {
  if (std::fabs(p.x) > 180.0 || std::fabs(p.y) > 90.0) {
    throw InputError(
        fmt::format("{}:{}: {} ({}, {}) is not longitude/latitude (|lon| <= 180, |lat| <= 90), but "
                    "geometry.projection = \"equirectangular\" takes lon/lat data; leave the projection "
                    "\"none\" for projected coordinates",
                    file, line, what, p.x, p.y));
  }
}

}  // namespace

Vec2 Equirectangular::forward(Vec2 lonlat) const {
  return {kEarthRadius * std::cos(lat0 * kRad) * (lonlat.x - lon0) * kRad, kEarthRadius * (lonlat.y - lat0) * kRad};
}

Vec2 Equirectangular::inverse(Vec2 xy) const {
  return {lon0 + xy.x / (kEarthRadius * std::cos(lat0 * kRad)) / kRad, lat0 + xy.y / kEarthRadius / kRad};
}

void Equirectangular::inverse(std::vector<Vec2>& points) const {
  for (Vec2& p : points) p = inverse(p);
}

Equirectangular project_lonlat(RawGeometry& raw) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  Vec2 lo{inf, inf}, hi{-inf, -inf};
  auto extend = [&](Vec2 p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
  };
  for (const RawCurve& c : raw.curves) {
    for (std::size_t k = 0; k < c.points.size(); ++k) {
      check_lonlat(c.points[k], c.file, k < c.lines.size() ? c.lines[k] : c.line + static_cast<int>(k), "point");
      extend(c.points[k]);
    }
  }
  for (const RawPoint& p : raw.points) {
    check_lonlat(p.p, p.file, p.line, "point");
    extend(p.p);
  }
  for (const RawHolePoint& h : raw.holes) check_lonlat(h.p, h.file, h.line, "hole point");
  Equirectangular proj;
  if (lo.x > hi.x) return proj;  // nothing to project
  proj.lon0 = 0.5 * (lo.x + hi.x);
  proj.lat0 = 0.5 * (lo.y + hi.y);
  if (std::fabs(proj.lat0) >= 89.0) {
    throw InputError(
        fmt::format("{}: the data's centre is at latitude {}, where an equirectangular projection "
                    "degenerates; project it (polar stereographic) and give projected coordinates",
                    raw.curves.empty() ? std::string("geometry") : raw.curves.front().file, proj.lat0));
  }
  for (RawCurve& c : raw.curves)
    for (Vec2& p : c.points) p = proj.forward(p);
  for (RawPoint& p : raw.points) p.p = proj.forward(p.p);
  for (RawHolePoint& h : raw.holes) h.p = proj.forward(h.p);
  return proj;
}

}  // namespace pdmesh
