// Finds the periodic nodes among a mesh's points by their exact coordinates.
#include "mesh/periodic_links.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <set>
#include <string>
#include <unordered_map>

#include <fmt/format.h>

#include "core/errors.hpp"

namespace pdmesh {

namespace {

struct PointKey {
  std::uint64_t x, y;
  bool operator==(const PointKey&) const = default;
};
struct PointKeyHash {
  std::size_t operator()(const PointKey& k) const {
    return std::hash<std::uint64_t>()(k.x * 0x9e3779b97f4a7c15ULL ^ k.y);
  }
};
PointKey key_of(Vec2 p) { return {std::bit_cast<std::uint64_t>(p.x), std::bit_cast<std::uint64_t>(p.y)}; }

}  // namespace

std::vector<PeriodicLink> link_periodic_nodes(const Mesh& mesh, const std::vector<PeriodicNodes>& pairs) {
  const std::vector<Vec2>& points = mesh.points;
  const std::vector<std::string>& curve_names = mesh.curve_names;
  std::vector<PeriodicLink> links;
  if (pairs.empty()) return links;
  std::unordered_map<PointKey, int, PointKeyHash> index;
  index.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) index.emplace(key_of(points[i]), static_cast<int>(i));
  const auto find = [&](Vec2 p, int curve) {
    const auto it = index.find(key_of(p));
    if (it == index.end())
      throw SimulationError(fmt::format("periodic curve '{}': its node ({}, {}) is not a point of the mesh",
                                        curve_names.at(static_cast<std::size_t>(curve)), p.x, p.y));
    return it->second;
  };
  for (const PeriodicNodes& pair : pairs) {
    PeriodicLink link;
    link.curve = pair.image_curve;
    link.source_curve = pair.source_curve;
    link.affine = pair.transform.affine();
    for (std::size_t k = 0; k < pair.source.size(); ++k) {
      const int s = find(pair.source[k], pair.source_curve);
      const int i = find(pair.image[k], pair.image_curve);
      link.nodes.push_back({i, s});
      const Vec2 mapped = pair.transform.apply(points[static_cast<std::size_t>(s)]);
      link.max_mismatch = std::max(link.max_mismatch, dist(mapped, points[static_cast<std::size_t>(i)]));
    }
    // Every node on either curve's boundary edges is one of the pairs'.
    std::set<int> paired;
    for (const auto& [i, s] : link.nodes) paired.insert({i, s});
    for (const BoundaryEdge& e : mesh.boundary_edges) {
      if (e.curve != pair.source_curve && e.curve != pair.image_curve) continue;
      for (const int v : {e.a, e.b})
        if (paired.count(v) == 0)
          throw SimulationError(fmt::format(
              "periodic curve '{}': its mesh node ({}, {}) has no partner on '{}'",
              curve_names.at(static_cast<std::size_t>(e.curve)), points[static_cast<std::size_t>(v)].x,
              points[static_cast<std::size_t>(v)].y,
              curve_names.at(
                  static_cast<std::size_t>(e.curve == pair.source_curve ? pair.image_curve : pair.source_curve))));
    }
    links.push_back(std::move(link));
  }
  return links;
}

}  // namespace pdmesh
