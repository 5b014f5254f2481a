// Keeping a mesh's nodes as they are; see kept_nodes.hpp.
#include "init/kept_nodes.hpp"

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <utility>

namespace pdmesh {

namespace {

std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// Per node: 1 on an edge of one triangle, 0 inside, -1 in no triangle.
std::vector<int> node_places(const Mesh& mesh) {
  std::unordered_map<std::uint64_t, int> count;
  count.reserve(mesh.triangles.size() * 2);
  std::vector<int> place(mesh.points.size(), -1);
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      ++count[edge_key(t[k], t[(k + 1) % 3])];
      place[static_cast<std::size_t>(t[k])] = 0;
    }
  for (const auto& [key, n] : count)
    if (n == 1) {
      place[static_cast<std::size_t>(key >> 32)] = 1;
      place[static_cast<std::size_t>(key & 0xffffffffu)] = 1;
    }
  return place;
}

}  // namespace

std::optional<KeptNodes> keep_mesh_nodes(const Mesh& mesh, const Geometry& geometry, const GeometryTree& tree,
                                         double tolerance) {
  if (!geometry.embedded_points.empty()) return std::nullopt;
  for (const Curve& c : geometry.curves)
    if (c.constraint) return std::nullopt;
  KeptNodes kept;
  kept.stations.resize(geometry.curves.size());
  // The curves' ends and critical vertices, which must each have a mesh node.
  struct Corner {
    Vec2 p;
    bool found = false;
  };
  std::vector<Corner> corners;
  for (std::size_t c = 0; c < geometry.curves.size(); ++c) {
    const Curve& curve = geometry.curves[c];
    const std::size_t n = curve.points.size();
    for (std::size_t i = 0; i < n; ++i) {
      const bool critical = i == 0 || i + 1 == n || (i < curve.critical.size() && curve.critical[i] != 0);
      if (!critical) continue;
      kept.stations[c].push_back({curve.points[i], static_cast<int>(i), curve.arc[i]});
      corners.push_back({curve.points[i]});
    }
  }
  const std::vector<int> place = node_places(mesh);
  for (std::size_t i = 0; i < mesh.points.size(); ++i) {
    const Vec2 p = mesh.points[i];
    if (place[i] == 0) kept.interior.push_back(p);
    if (place[i] != 1) continue;
    bool at_corner = false;
    for (Corner& k : corners)
      if (dist(k.p, p) <= tolerance) at_corner = k.found = true;
    if (at_corner) continue;
    const ClosestHit hit = tree.closest(p);
    if (hit.segment < 0) return std::nullopt;
    const Segment& s = geometry.segments[static_cast<std::size_t>(hit.segment)];
    const Curve& curve = geometry.curves[static_cast<std::size_t>(s.curve)];
    kept.stations[static_cast<std::size_t>(s.curve)].push_back(
        {p, -1, curve.arc[static_cast<std::size_t>(s.index)] + hit.t * s.length});
  }
  for (const Corner& k : corners)
    if (!k.found) return std::nullopt;
  for (auto& list : kept.stations) {
    // The ends at arc 0 and the curve's length stay first and last (assemble_boundary_nodes checks it).
    std::stable_sort(list.begin(), list.end(),
                     [](const BoundaryStation& a, const BoundaryStation& b) { return a.arc < b.arc; });
    for (std::size_t k = 1; k < list.size(); ++k)
      if (!(list[k].arc > list[k - 1].arc)) return std::nullopt;
  }
  return kept;
}

NodeSet kept_node_set(const KeptNodes& kept, const Geometry& geometry, const SpacingField& spacing) {
  NodeSet nodes = assemble_boundary_nodes(geometry, spacing, kept.stations);
  for (const Vec2 p : kept.interior) nodes.add(p, spacing.at(p), NodeKind::Interior, -1);
  return nodes;
}

}  // namespace pdmesh
