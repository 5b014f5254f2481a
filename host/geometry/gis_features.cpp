// Features of GIS files as RawGeometry parts (gis_features.hpp).
#include "geometry/gis_features.hpp"

#include <map>
#include <set>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/progress_notes.hpp"

namespace pdmesh::gis {

namespace {

std::string part_name(const FeatureSource& src, int part) {
  if (src.name.empty()) return {};
  return part > 0 ? fmt::format("{}_{}", src.name, part) : src.name;
}

// Drops consecutive repeats (and noting them); returns how many were dropped.
std::size_t drop_repeats(std::vector<Vec2>& pts) {
  std::vector<Vec2> kept;
  kept.reserve(pts.size());
  for (const Vec2& p : pts)
    if (kept.empty() || !(kept.back() == p)) kept.push_back(p);
  const std::size_t dropped = pts.size() - kept.size();
  pts = std::move(kept);
  return dropped;
}

RawCurve make_curve(const FeatureSource& src, std::string name, std::vector<Vec2> pts, bool constraint) {
  RawCurve c;
  c.name = std::move(name);
  c.points = std::move(pts);
  c.file = src.file;
  c.line = src.line;
  // Every point of a feature is reported at the feature's line.
  c.lines.assign(c.points.size(), src.line);
  c.constraint = constraint;
  return c;
}

}  // namespace

std::string plain_name(const std::string& name) {
  std::string s = name;
  for (char& ch : s) {
    const bool plain = (ch >= 'A' && ch <= 'Z') || (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_' ||
                       ch == '.' || ch == '+' || ch == '-';
    if (!plain) ch = '_';
  }
  return s;
}

void add_polygon(RawGeometry& out, const FeatureSource& src, int part, std::vector<std::vector<Vec2>> rings) {
  const std::string base = part_name(src, part);
  for (std::size_t r = 0; r < rings.size(); ++r) {
    std::vector<Vec2>& ring = rings[r];
    const std::size_t given = ring.size();
    std::size_t dropped = drop_repeats(ring);
    if (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();
    if (ring.size() < 3) {
      throw InputError(
          fmt::format("{}:{}: {}: ring {} {}has {} distinct point{} ({} position{} given); a ring needs "
                      "at least 3",
                      src.file, src.line, src.what, r, part > 0 ? fmt::format("of polygon {} ", part) : "", ring.size(),
                      ring.size() == 1 ? "" : "s", given, given == 1 ? "" : "s"));
    }
    if (dropped > 0) {
      progress_line(fmt::format("geometry: {}:{}: {}: ring {}: dropped {} repeated consecutive position{}", src.file,
                                src.line, src.what, r, dropped, dropped == 1 ? "" : "s"));
    }
    ring.push_back(ring.front());
    std::string name = base.empty() ? base : (r == 0 ? base : fmt::format("{}_hole{}", base, r));
    out.curves.push_back(make_curve(src, std::move(name), std::move(ring), false));
  }
}

void add_line(RawGeometry& out, const FeatureSource& src, int part, std::vector<Vec2> points) {
  const std::size_t given = points.size();
  const std::size_t dropped = drop_repeats(points);
  if (points.size() < 2) {
    throw InputError(fmt::format("{}:{}: {}: line {}has {} distinct point{} ({} given); a line needs at least 2",
                                 src.file, src.line, src.what, part > 0 ? fmt::format("{} ", part) : "", points.size(),
                                 points.size() == 1 ? "" : "s", given));
  }
  if (dropped > 0) {
    progress_line(fmt::format("geometry: {}:{}: {}: dropped {} repeated consecutive position{}", src.file, src.line,
                              src.what, dropped, dropped == 1 ? "" : "s"));
  }
  out.curves.push_back(make_curve(src, part_name(src, part), std::move(points), true));
}

void add_point(RawGeometry& out, const FeatureSource& src, Vec2 p) { out.points.push_back({p, src.file, src.line}); }

void finish(RawGeometry& out, const std::string& file, std::size_t first_curve, std::size_t first_point) {
  if (out.curves.size() == first_curve) {
    const std::size_t points = out.points.size() - first_point;
    throw InputError(
        fmt::format("{}: the file holds {} point{} and no polygon or line: nothing bounds a domain; "
                    "a GIS file needs a polygon (or lines, with the boundary given in another file)",
                    file, points, points == 1 ? "" : "s"));
  }
  std::map<std::string, int> count;
  std::set<std::string> taken;
  for (std::size_t c = first_curve; c < out.curves.size(); ++c) {
    if (out.curves[c].name.empty()) continue;
    ++count[out.curves[c].name];
    taken.insert(out.curves[c].name);
  }
  std::map<std::string, int> next;
  for (std::size_t c = first_curve; c < out.curves.size(); ++c) {
    std::string& name = out.curves[c].name;
    if (name.empty() || count[name] < 2) continue;
    int& k = next[name];
    std::string candidate;
    do candidate = fmt::format("{}_{}", name, ++k);
    while (taken.count(candidate) > 0);
    taken.insert(candidate);
    name = std::move(candidate);
  }
}

}  // namespace pdmesh::gis
