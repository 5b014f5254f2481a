// region_tags(): per-triangle regional attributes by flood fill (see region_tags.hpp).
#include "mesh/region_tags.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <unordered_map>
#include <utility>

#include "core/predicates.hpp"

namespace pdmesh {
namespace {

// The geometry's segments bucketed in a uniform grid of about one cell per segment.
class SegmentGrid {
 public:
  explicit SegmentGrid(const Geometry& g) : segments_(g.segments) {
    if (segments_.empty()) return;
    box_ = g.extents;
    for (const Segment& s : segments_) box_.add(s.a), box_.add(s.b);
    const double w = std::max(box_.hi.x - box_.lo.x, 1e-300), h = std::max(box_.hi.y - box_.lo.y, 1e-300);
    const double n = std::clamp(std::sqrt(static_cast<double>(segments_.size())), 1.0, 2048.0);
    cell_ = std::max(w, h) / n;
    for (int k = 0; k < static_cast<int>(segments_.size()); ++k) {
      const Segment& s = segments_[k];
      const auto [x0, y0] = cell(Vec2{std::min(s.a.x, s.b.x), std::min(s.a.y, s.b.y)});
      const auto [x1, y1] = cell(Vec2{std::max(s.a.x, s.b.x), std::max(s.a.y, s.b.y)});
      for (long long x = x0; x <= x1; ++x)
        for (long long y = y0; y <= y1; ++y) cells_[key(x, y)].push_back(k);
    }
  }

  // True when a and b both lie within tol of one segment listed in the cells around their midpoint.
  bool on_one_segment(Vec2 a, Vec2 b, double tol) const {
    if (segments_.empty()) return false;
    const auto [x, y] = cell(0.5 * (a + b));
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy) {
        const auto it = cells_.find(key(x + dx, y + dy));
        if (it == cells_.end()) continue;
        for (const int k : it->second)
          if (distance(segments_[k], a) <= tol && distance(segments_[k], b) <= tol) return true;
      }
    return false;
  }

 private:
  static double distance(const Segment& s, Vec2 p) {
    const Vec2 d = s.b - s.a;
    const double len2 = dot(d, d);
    const double t = len2 > 0 ? std::clamp(dot(p - s.a, d) / len2, 0.0, 1.0) : 0.0;
    return dist(p, s.a + t * d);
  }
  std::pair<long long, long long> cell(Vec2 p) const {
    return {static_cast<long long>(std::floor((p.x - box_.lo.x) / cell_)),
            static_cast<long long>(std::floor((p.y - box_.lo.y) / cell_))};
  }
  static long long key(long long x, long long y) { return x * 4099 + y; }

  const std::vector<Segment>& segments_;
  Box box_;
  double cell_ = 1.0;
  std::unordered_map<long long, std::vector<int>> cells_;
};

bool contains(const Mesh& mesh, const std::array<int, 3>& t, Vec2 p) {
  for (int k = 0; k < 3; ++k)
    if (orient2d(mesh.points[t[k]], mesh.points[t[(k + 1) % 3]], p) < 0) return false;
  return true;
}

int seed_triangle(const Mesh& mesh, Vec2 p) {
  int nearest = -1;
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < static_cast<int>(mesh.triangles.size()); ++i) {
    const auto& t = mesh.triangles[i];
    if (contains(mesh, t, p)) return i;
    const Vec2 c = (1.0 / 3.0) * (mesh.points[t[0]] + mesh.points[t[1]] + mesh.points[t[2]]);
    const double d = dist(c, p);
    if (d < best) best = d, nearest = i;
  }
  return nearest;
}

}  // namespace

std::vector<double> region_tags(const Mesh& mesh, const std::vector<GeometryRegion>& regions,
                                const Geometry& geometry) {
  if (regions.empty()) return {};
  const int nt = static_cast<int>(mesh.triangles.size());
  std::vector<double> tag(nt, 0.0);
  if (nt == 0) return tag;

  // Neighbour across each triangle edge (edge k joins corners k and k+1), -1 on the boundary, and
  // whether the edge lies on a curve.
  std::vector<std::array<int, 3>> across(nt, {-1, -1, -1});
  std::vector<std::array<std::uint8_t, 3>> blocked(nt, {0, 0, 0});
  std::vector<std::array<long long, 2>> keys;  // (edge key, triangle * 3 + k)
  keys.reserve(3 * static_cast<std::size_t>(nt));
  const long long np = static_cast<long long>(mesh.points.size());
  for (int i = 0; i < nt; ++i)
    for (int k = 0; k < 3; ++k) {
      const long long a = mesh.triangles[i][k], b = mesh.triangles[i][(k + 1) % 3];
      keys.push_back({std::min(a, b) * np + std::max(a, b), 3LL * i + k});
    }
  std::sort(keys.begin(), keys.end());
  const SegmentGrid grid(geometry);
  for (std::size_t j = 0; j + 1 < keys.size(); ++j) {
    if (keys[j][0] != keys[j + 1][0]) continue;
    const int i0 = static_cast<int>(keys[j][1] / 3), k0 = static_cast<int>(keys[j][1] % 3);
    const int i1 = static_cast<int>(keys[j + 1][1] / 3), k1 = static_cast<int>(keys[j + 1][1] % 3);
    across[i0][k0] = i1;
    across[i1][k1] = i0;
    const Vec2 a = mesh.points[mesh.triangles[i0][k0]], b = mesh.points[mesh.triangles[i0][(k0 + 1) % 3]];
    const std::uint8_t on = grid.on_one_segment(a, b, 1e-6 * dist(a, b)) ? 1 : 0;
    blocked[i0][k0] = blocked[i1][k1] = on;
    ++j;
  }

  std::vector<int> seen(nt, -1), stack;
  for (int r = 0; r < static_cast<int>(regions.size()); ++r) {
    const int seed = seed_triangle(mesh, regions[r].p);
    stack.assign(1, seed);
    seen[seed] = r;
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      tag[i] = regions[r].attribute;
      for (int k = 0; k < 3; ++k) {
        const int n = across[i][k];
        if (n < 0 || blocked[i][k] || seen[n] == r) continue;
        seen[n] = r;
        stack.push_back(n);
      }
    }
  }
  return tag;
}

std::vector<RegionName> region_names_of(const std::vector<GeometryRegion>& regions) {
  std::map<double, std::string> names;
  for (const GeometryRegion& r : regions)
    if (!r.name.empty()) names.emplace(r.attribute, r.name);
  std::vector<RegionName> out;
  for (auto& [attribute, name] : names) out.push_back({attribute, std::move(name)});
  return out;
}

std::vector<CurveGroupTag> curve_groups_of(const std::vector<CurveGroup>& groups,
                                           const std::vector<std::string>& curve_names) {
  std::vector<CurveGroupTag> out;
  std::vector<std::uint8_t> grouped(curve_names.size(), 0);
  for (const CurveGroup& g : groups) {
    if (g.tag <= 0) continue;
    CurveGroupTag kept{g.tag, g.name, {}};
    for (std::size_t c = 0; c < curve_names.size(); ++c)
      if (!grouped[c] && std::find(g.curves.begin(), g.curves.end(), curve_names[c]) != g.curves.end()) {
        kept.curves.push_back(static_cast<int>(c));
        grouped[c] = 1;
      }
    if (!kept.curves.empty()) out.push_back(std::move(kept));
  }
  return out;
}

}  // namespace pdmesh
