// The subdomains of a geometry (subdomains.hpp).
#include "spacing/subdomains.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include "core/predicates.hpp"

namespace pdmesh {

Subdomains::Subdomains(const Geometry& geometry) {
  std::map<std::pair<double, double>, int> vertex_of;
  const auto vertex = [&](Vec2 p) {
    const auto [it, fresh] = vertex_of.emplace(std::pair{p.x, p.y}, static_cast<int>(vertices_.size()));
    if (fresh) vertices_.push_back(p);
    return it->second;
  };
  std::set<std::pair<int, int>> seen;
  for (const Segment& s : geometry.segments) {
    const int a = vertex(s.a), b = vertex(s.b);
    if (a == b || !seen.emplace(std::min(a, b), std::max(a, b)).second) continue;
    edges_.push_back({a, b});
  }
  faces_ = planar_faces(vertices_, edges_);
  for (const std::vector<int>& cycle : faces_.outer) cycles_.push_back(index_cycle(vertices_, cycle));
  region_.assign(faces_.outer.size(), std::nullopt);
  regions_ = geometry.regions;
  for (std::size_t k = 0; k < regions_.size(); ++k) {
    const int f = face_at(regions_[k].p);
    if (f >= 0) region_[static_cast<std::size_t>(f)] = k;
  }
}

Subdomains::IndexedCycle Subdomains::index_cycle(const std::vector<Vec2>& vertices, const std::vector<int>& cycle) {
  IndexedCycle c;
  for (std::size_t k = 0; k < cycle.size(); ++k) {
    const Vec2 a = vertices[cycle[k]], b = vertices[cycle[(k + 1) % cycle.size()]];
    c.edges.push_back({a, b});
    c.box.add(a);
  }
  // About four edges a slab; a flat cycle is one slab.
  const double height = c.box.hi.y - c.box.lo.y;
  const int slabs = height > 0.0 ? std::clamp(static_cast<int>(c.edges.size() / 4), 1, 4096) : 1;
  c.slab_height = height > 0.0 ? height / slabs : 1.0;
  c.slabs.resize(static_cast<std::size_t>(slabs));
  const auto slab = [&](double y) {
    return std::clamp(static_cast<int>(std::floor((y - c.box.lo.y) / c.slab_height)), 0, slabs - 1);
  };
  for (int e = 0; e < static_cast<int>(c.edges.size()); ++e) {
    const auto& [a, b] = c.edges[e];
    for (int s = slab(std::min(a.y, b.y)); s <= slab(std::max(a.y, b.y)); ++s) c.slabs[s].push_back(e);
  }
  return c;
}

Subdomains::Side Subdomains::side_of(const IndexedCycle& c, Vec2 p) {
  if (!c.box.contains(p)) return Side::Outside;
  const int s = std::clamp(static_cast<int>(std::floor((p.y - c.box.lo.y) / c.slab_height)), 0,
                           static_cast<int>(c.slabs.size()) - 1);
  bool in = false;
  for (const int e : c.slabs[s]) {
    const auto& [a, b] = c.edges[e];
    const double o = orient2d(a, b, p);
    if (o == 0.0 && std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
        p.y <= std::max(a.y, b.y))
      return Side::On;
    // Crossing parity of the ray towards +x (the rule of geometry/planar_faces' inside test).
    if ((a.y > p.y) == (b.y > p.y)) continue;
    if (b.y > a.y ? o > 0 : o < 0) in = !in;
  }
  return in ? Side::Inside : Side::Outside;
}

int Subdomains::face_at(Vec2 p) const {
  int best = -1;
  for (int k = 0; k < face_count(); ++k) {
    if (best >= 0 && faces_.outer_area[k] >= faces_.outer_area[best]) continue;
    const Side side = side_of(cycles_[k], p);
    if (side == Side::On) return -1;
    if (side == Side::Inside) best = k;
  }
  return best;
}

std::vector<int> Subdomains::faces_with_attribute(double attribute) const {
  std::vector<int> out;
  for (int k = 0; k < face_count(); ++k)
    if (region_[k] && regions_[*region_[k]].attribute == attribute) out.push_back(k);
  return out;
}

std::vector<int> Subdomains::faces_named(const std::string& name) const {
  // A name stands for its attribute (geometry.region_names names attributes, not points).
  std::set<double> attributes;
  for (const GeometryRegion& r : regions_)
    if (r.name == name) attributes.insert(r.attribute);
  std::vector<int> out;
  for (int k = 0; k < face_count(); ++k)
    if (region_[k] && attributes.count(regions_[*region_[k]].attribute) > 0) out.push_back(k);
  return out;
}

bool Subdomains::in_any(const std::vector<int>& faces, Vec2 p) const {
  for (const int f : faces) {
    if (side_of(cycles_[f], p) == Side::Outside) continue;
    // A smaller face holding p strictly inside is nested in f (cycles do not cross): p is in it, not in f.
    bool nested = false;
    for (int j = 0; j < face_count() && !nested; ++j)
      nested = j != f && faces_.outer_area[j] < faces_.outer_area[f] && side_of(cycles_[j], p) == Side::Inside;
    if (!nested) return true;
  }
  return false;
}

}  // namespace pdmesh
