// boundary_strings(): chains each curve's boundary edges, orients them by the triangle beside them
// and classifies them by the signed area of the boundary loop they lie on.
#include "io/boundary_strings.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>
#include <unordered_map>

#include "io/mesh_io_common.hpp"

namespace pdmesh {

namespace {

std::uint64_t edge_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// The directed edges of the triangles (counter-clockwise, so each has the domain on its left) whose
// reverse no triangle has: the mesh's boundary, as a map from start node to end node.
std::unordered_map<std::uint64_t, int> boundary_directed_edges(const Mesh& mesh) {
  std::unordered_map<std::uint64_t, int> directed;  // (a, b) -> count
  directed.reserve(mesh.triangles.size() * 3);
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++directed[edge_key(t[k], t[(k + 1) % 3])];
  std::unordered_map<std::uint64_t, int> boundary;
  for (const auto& [key, count] : directed) {
    const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
    if (directed.find(edge_key(b, a)) == directed.end()) boundary.emplace(key, count);
  }
  return boundary;
}

// For every boundary directed edge, whether its loop (followed from edge to edge, domain on the
// left) has negative signed area, i.e. runs around a hole.
std::unordered_map<std::uint64_t, bool> loop_is_hole(const Mesh& mesh,
                                                     const std::unordered_map<std::uint64_t, int>& boundary) {
  std::unordered_multimap<int, int> next;  // start node -> end node
  for (const auto& [key, count] : boundary)
    next.emplace(static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffu));
  std::unordered_map<std::uint64_t, bool> hole;
  for (const auto& [key, count] : boundary) {
    if (hole.count(key)) continue;
    std::vector<std::uint64_t> loop;
    double twice_area = 0.0;
    int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
    const int start = a;
    while (true) {
      const std::uint64_t k = edge_key(a, b);
      if (hole.count(k)) break;
      hole.emplace(k, false);
      loop.push_back(k);
      const Vec2 p = mesh.points[static_cast<std::size_t>(a)], q = mesh.points[static_cast<std::size_t>(b)];
      twice_area += p.x * q.y - q.x * p.y;
      if (b == start) break;
      // At a node where the boundary touches itself, take an unused outgoing edge.
      int c = -1;
      const auto range = next.equal_range(b);
      for (auto it = range.first; it != range.second; ++it)
        if (!hole.count(edge_key(b, it->second))) c = it->second;
      if (c < 0) break;
      a = b;
      b = c;
    }
    for (const std::uint64_t k : loop) hole[k] = twice_area < 0.0;
  }
  return hole;
}

}  // namespace

std::vector<BoundaryString> boundary_strings(const Mesh& mesh) {
  check_mesh_for_writing(mesh, "boundary strings");
  const auto boundary = boundary_directed_edges(mesh);
  const auto hole = loop_is_hole(mesh, boundary);
  std::vector<BoundaryString> strings;
  BoundaryString current;
  const auto flush = [&] {
    if (current.nodes.size() >= 2) {
      current.closed = current.nodes.front() == current.nodes.back();
      strings.push_back(std::move(current));
    }
    current = BoundaryString{};
  };
  for (const std::size_t e : boundary_edges_by_curve(mesh)) {
    const BoundaryEdge& be = mesh.boundary_edges[e];
    // The edge as the domain runs: a -> b if a triangle has it so, else b -> a; neither: interior.
    int a = be.a, b = be.b;
    if (boundary.find(edge_key(a, b)) == boundary.end()) std::swap(a, b);
    const auto h = hole.find(edge_key(a, b));
    if (h == hole.end()) {
      flush();
      continue;
    }
    const bool continues = !current.nodes.empty() && current.curve == be.curve && current.internal == h->second &&
                           current.nodes.back() == be.a;
    if (!continues) {
      flush();
      current.curve = be.curve;
      current.internal = h->second;
      current.nodes.push_back(be.a);
    }
    current.nodes.push_back(be.b);
  }
  flush();
  // Orient: a chain stored in curve order runs with the domain on its left iff its first edge does
  // (along one curve the domain stays on one side).
  for (BoundaryString& s : strings) {
    const int a = s.nodes[0], b = s.nodes[1];
    if (boundary.find(edge_key(a, b)) == boundary.end()) std::reverse(s.nodes.begin(), s.nodes.end());
    s.closed = s.nodes.front() == s.nodes.back();
  }
  return strings;
}

}  // namespace pdmesh
