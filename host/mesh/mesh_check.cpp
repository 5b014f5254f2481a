// Mesh invariant checker: topology, orientation, constrained Delaunay, boundary conformity, area.
#include "mesh/mesh_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include "core/predicates.hpp"

namespace pdmesh {
namespace {

std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint32_t>(std::min(a, b)), hi = static_cast<std::uint32_t>(std::max(a, b));
  return (static_cast<std::uint64_t>(hi) << 32) | lo;
}

struct EdgeUse {
  int triangle;
  int opposite;  // local index of the vertex opposite the edge
  int from;      // the edge in the triangle's orientation: from -> to
  int to;
};

struct DisjointSets {
  std::vector<int> parent;
  explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b) { parent[find(a)] = find(b); }
};

// Adds problems, but at most `kMaxPerKind` of each kind so a broken mesh gives a readable report.
class Problems {
 public:
  explicit Problems(std::vector<std::string>& out) : out_(out) {}
  template <typename... Args>
  void add(const std::string& kind, fmt::format_string<Args...> format, Args&&... args) {
    const int seen = ++count_[kind];
    if (seen <= kMaxPerKind) out_.push_back(kind + ": " + fmt::format(format, std::forward<Args>(args)...));
    if (seen == kMaxPerKind + 1) out_.push_back(kind + ": further problems of this kind not listed");
  }

 private:
  static constexpr int kMaxPerKind = 50;
  std::vector<std::string>& out_;
  std::unordered_map<std::string, int> count_;
};

}  // namespace

std::string CheckReport::summary() const {
  if (problems.empty()) return "ok";
  std::string s;
  for (const auto& p : problems) s += p + "\n";
  return s;
}

CheckReport check_mesh(const Mesh& mesh, std::optional<double> domain_area) {
  CheckReport report;
  Problems problems(report.problems);
  const auto& P = mesh.points;
  const int np = static_cast<int>(P.size());
  auto pt = [&](int i) { return fmt::format("{} ({}, {})", i, P[i].x, P[i].y); };

  // Indices, degenerate and duplicate triangles, orientation.
  std::vector<bool> valid(mesh.triangles.size(), true);
  std::set<std::array<int, 3>> seen;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tv = mesh.triangles[t];
    if (std::any_of(tv.begin(), tv.end(), [&](int i) { return i < 0 || i >= np; })) {
      problems.add("index", "triangle {} = ({}, {}, {}) names a point outside 0..{}", t, tv[0], tv[1], tv[2], np - 1);
      valid[t] = false;
      continue;
    }
    if (tv[0] == tv[1] || tv[1] == tv[2] || tv[0] == tv[2]) {
      problems.add("degenerate", "triangle {} repeats a vertex: ({}, {}, {})", t, tv[0], tv[1], tv[2]);
      valid[t] = false;
      continue;
    }
    auto sorted = tv;
    std::sort(sorted.begin(), sorted.end());
    if (!seen.insert(sorted).second)
      problems.add("duplicate", "triangle {} repeats vertices {}, {}, {}", t, pt(tv[0]), pt(tv[1]), pt(tv[2]));
    if (!(orient2d(P[tv[0]], P[tv[1]], P[tv[2]]) > 0.0))
      problems.add("orientation", "triangle {} is not counter-clockwise: {}, {}, {}", t, pt(tv[0]), pt(tv[1]), pt(tv[2]));
  }

  // Edge uses.
  std::unordered_map<std::uint64_t, std::vector<EdgeUse>> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!valid[t]) continue;
    const auto& tv = mesh.triangles[t];
    for (int i = 0; i < 3; ++i) {
      const int a = tv[(i + 1) % 3], b = tv[(i + 2) % 3];
      edges[edge_key(a, b)].push_back({static_cast<int>(t), i, a, b});
    }
  }
  std::unordered_map<std::uint64_t, int> constrained;  // edge -> index in boundary_edges
  for (std::size_t k = 0; k < mesh.boundary_edges.size(); ++k) {
    const auto& e = mesh.boundary_edges[k];
    if (e.a < 0 || e.a >= np || e.b < 0 || e.b >= np) {
      problems.add("index", "boundary edge {} ({}-{}) names a point outside 0..{}", k, e.a, e.b, np - 1);
      continue;
    }
    constrained.emplace(edge_key(e.a, e.b), static_cast<int>(k));
    if (edges.find(edge_key(e.a, e.b)) == edges.end())
      problems.add("boundary", "boundary edge {} of curve {} from {} to {} is not in the mesh", k, e.curve, pt(e.a), pt(e.b));
  }

  DisjointSets components(mesh.triangles.size());
  DisjointSets loops(static_cast<std::size_t>(np));
  std::unordered_set<int> boundary_vertices, used_vertices;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    if (valid[t]) used_vertices.insert(mesh.triangles[t].begin(), mesh.triangles[t].end());
  std::size_t boundary_edge_count = 0;
  for (const auto& [key, uses] : edges) {
    const int a = uses[0].from, b = uses[0].to;
    const bool is_constrained = constrained.count(key) > 0;
    if (uses.size() == 1) {
      ++boundary_edge_count;
      boundary_vertices.insert(a);
      boundary_vertices.insert(b);
      loops.unite(a, b);
      if (!is_constrained)
        problems.add("boundary", "edge {} - {} of triangle {} is on the mesh boundary but is no boundary edge", pt(a),
                     pt(b), uses[0].triangle);
    } else if (uses.size() == 2) {
      const EdgeUse &u0 = uses[0], &u1 = uses[1];
      if (!(u0.from == u1.to && u0.to == u1.from)) {
        problems.add("topology", "triangles {} and {} traverse edge {} - {} in the same direction", u0.triangle,
                     u1.triangle, pt(a), pt(b));
        continue;
      }
      if (is_constrained) {
        problems.add("boundary", "boundary edge {} - {} has triangles {} and {} on both sides", pt(a), pt(b),
                     u0.triangle, u1.triangle);
      }
      components.unite(u0.triangle, u1.triangle);
      if (is_constrained) continue;  // constrained Delaunay: boundary edges need not be Delaunay
      const auto& t0 = mesh.triangles[u0.triangle];
      const int q = mesh.triangles[u1.triangle][u1.opposite];
      if (incircle(P[t0[0]], P[t0[1]], P[t0[2]], P[q]) > 0.0) {
        problems.add("delaunay", "edge {} - {} is not Delaunay: {} lies inside the circumcircle of triangle {}", pt(a),
                     pt(b), pt(q), u0.triangle);
      }
    } else {
      problems.add("topology", "edge {} - {} is shared by {} triangles", pt(a), pt(b), uses.size());
    }
  }

  // Euler characteristic of a triangulated surface with C disk-like components and B boundary loops.
  std::unordered_set<int> component_roots, loop_roots;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    if (valid[t]) component_roots.insert(components.find(static_cast<int>(t)));
  for (int vtx : boundary_vertices) loop_roots.insert(loops.find(vtx));
  const long long euler = static_cast<long long>(used_vertices.size()) - static_cast<long long>(edges.size()) +
                          static_cast<long long>(std::count(valid.begin(), valid.end(), true));
  const long long expected = 2 * static_cast<long long>(component_roots.size()) - static_cast<long long>(loop_roots.size());
  if (euler != expected) {
    problems.add("euler", "V - E + F = {} but 2 * components - boundary loops = 2 * {} - {} (V {}, E {}, F {}, {} boundary edges)",
                 euler, component_roots.size(), loop_roots.size(), used_vertices.size(), edges.size(),
                 std::count(valid.begin(), valid.end(), true), boundary_edge_count);
  }

  if (domain_area) {
    double area = 0.0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      if (!valid[t]) continue;
      const auto& tv = mesh.triangles[t];
      area += 0.5 * cross(P[tv[1]] - P[tv[0]], P[tv[2]] - P[tv[0]]);
    }
    if (!(std::fabs(area - *domain_area) <= 1e-9 * std::fabs(*domain_area)))
      problems.add("area", "triangle areas sum to {} but the domain area is {}", area, *domain_area);
  }
  return report;
}

}  // namespace pdmesh
