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

// The passes of check_mesh, run in its order: later passes read what the earlier ones collected (the
// valid triangles, the edge uses, the boundary edges), and the problems come in a fixed order.
class MeshChecker {
 public:
  MeshChecker(const Mesh& mesh, CheckReport& report)
      : mesh_(mesh),
        P_(mesh.points),
        np_(static_cast<int>(mesh.points.size())),
        problems_(report.problems),
        valid_(mesh.triangles.size(), true),
        components_(mesh.triangles.size()),
        loops_(static_cast<std::size_t>(np_)) {}

  void check_triangles();
  void collect_edges();
  void check_boundary_edges();
  void check_edges();
  void check_euler();
  void check_area(double domain_area);

 private:
  std::string pt(int i) const { return fmt::format("{} ({}, {})", i, P_[i].x, P_[i].y); }
  void check_interior_edge(const EdgeUse& u0, const EdgeUse& u1, bool is_constrained);
  // The edge a-b is a boundary edge of an embedded constraint (Mesh::constraint_curves).
  bool open_constraint(int a, int b) const {
    if (mesh_.constraint_curves.empty()) return false;
    const auto it = constrained_.find(edge_key(a, b));
    if (it == constrained_.end()) return false;
    const auto c = static_cast<std::size_t>(mesh_.boundary_edges[static_cast<std::size_t>(it->second)].curve);
    return c < mesh_.constraint_curves.size() && mesh_.constraint_curves[c] != 0;
  }

  const Mesh& mesh_;
  const std::vector<Vec2>& P_;
  const int np_;
  Problems problems_;
  std::vector<bool> valid_;  // per triangle: its indices are in range and distinct
  std::unordered_map<std::uint64_t, std::vector<EdgeUse>> edges_;  // the valid triangles' edges
  std::unordered_map<std::uint64_t, int> constrained_;             // edge -> index in boundary_edges
  DisjointSets components_;                                        // triangles joined across their interior edges
  DisjointSets loops_;                                             // vertices joined along the mesh boundary
  std::unordered_set<int> boundary_vertices_;
  std::size_t boundary_edge_count_ = 0;
};

// Indices, degenerate and duplicate triangles, orientation.
void MeshChecker::check_triangles() {
  std::set<std::array<int, 3>> seen;
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
    const auto& tv = mesh_.triangles[t];
    if (std::any_of(tv.begin(), tv.end(), [&](int i) { return i < 0 || i >= np_; })) {
      problems_.add("index", "triangle {} = ({}, {}, {}) names a point outside 0..{}", t, tv[0], tv[1], tv[2], np_ - 1);
      valid_[t] = false;
      continue;
    }
    if (tv[0] == tv[1] || tv[1] == tv[2] || tv[0] == tv[2]) {
      problems_.add("degenerate", "triangle {} repeats a vertex: ({}, {}, {})", t, tv[0], tv[1], tv[2]);
      valid_[t] = false;
      continue;
    }
    auto sorted = tv;
    std::sort(sorted.begin(), sorted.end());
    if (!seen.insert(sorted).second)
      problems_.add("duplicate", "triangle {} repeats vertices {}, {}, {}", t, pt(tv[0]), pt(tv[1]), pt(tv[2]));
    if (!(orient2d(P_[tv[0]], P_[tv[1]], P_[tv[2]]) > 0.0))
      problems_.add("orientation", "triangle {} is not counter-clockwise: {}, {}, {}", t, pt(tv[0]), pt(tv[1]),
                    pt(tv[2]));
  }
}

// The uses of every edge of the valid triangles.
void MeshChecker::collect_edges() {
  edges_.reserve(3 * mesh_.triangles.size());
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
    if (!valid_[t]) continue;
    const auto& tv = mesh_.triangles[t];
    for (int i = 0; i < 3; ++i) {
      const int a = tv[(i + 1) % 3], b = tv[(i + 2) % 3];
      edges_[edge_key(a, b)].push_back({static_cast<int>(t), i, a, b});
    }
  }
}

// Every boundary edge names points of the mesh and is an edge of it.
void MeshChecker::check_boundary_edges() {
  for (std::size_t k = 0; k < mesh_.boundary_edges.size(); ++k) {
    const auto& e = mesh_.boundary_edges[k];
    if (e.a < 0 || e.a >= np_ || e.b < 0 || e.b >= np_) {
      problems_.add("index", "boundary edge {} ({}-{}) names a point outside 0..{}", k, e.a, e.b, np_ - 1);
      continue;
    }
    constrained_.emplace(edge_key(e.a, e.b), static_cast<int>(k));
    if (edges_.find(edge_key(e.a, e.b)) == edges_.end())
      problems_.add("boundary", "boundary edge {} of curve {} from {} to {} is not in the mesh", k, e.curve, pt(e.a),
                    pt(e.b));
  }
}

// An edge used by two triangles: opposite orientations, not a boundary edge, and (unless constrained)
// locally Delaunay.
void MeshChecker::check_interior_edge(const EdgeUse& u0, const EdgeUse& u1, bool is_constrained) {
  const int a = u0.from, b = u0.to;
  if (!(u0.from == u1.to && u0.to == u1.from)) {
    problems_.add("topology", "triangles {} and {} traverse edge {} - {} in the same direction", u0.triangle,
                  u1.triangle, pt(a), pt(b));
    return;
  }
  if (is_constrained && !open_constraint(a, b)) {
    problems_.add("boundary", "boundary edge {} - {} has triangles {} and {} on both sides", pt(a), pt(b), u0.triangle,
                  u1.triangle);
  }
  components_.unite(u0.triangle, u1.triangle);
  if (is_constrained) return;  // constrained Delaunay: boundary edges need not be Delaunay
  const auto& t0 = mesh_.triangles[u0.triangle];
  const int q = mesh_.triangles[u1.triangle][u1.opposite];
  if (incircle(P_[t0[0]], P_[t0[1]], P_[t0[2]], P_[q]) > 0.0) {
    problems_.add("delaunay", "edge {} - {} is not Delaunay: {} lies inside the circumcircle of triangle {}", pt(a),
                  pt(b), pt(q), u0.triangle);
  }
}

// Every edge: on the mesh boundary (one use) only if it is a boundary edge, else used twice.
void MeshChecker::check_edges() {
  for (const auto& [key, uses] : edges_) {
    const int a = uses[0].from, b = uses[0].to;
    const bool is_constrained = constrained_.count(key) > 0;
    if (uses.size() == 1) {
      ++boundary_edge_count_;
      boundary_vertices_.insert(a);
      boundary_vertices_.insert(b);
      loops_.unite(a, b);
      if (!is_constrained)
        problems_.add("boundary", "edge {} - {} of triangle {} is on the mesh boundary but is no boundary edge", pt(a),
                      pt(b), uses[0].triangle);
      else if (open_constraint(a, b))
        problems_.add("boundary", "edge {} - {} of an embedded constraint has triangle {} on one side only", pt(a),
                      pt(b), uses[0].triangle);
    } else if (uses.size() == 2) {
      check_interior_edge(uses[0], uses[1], is_constrained);
    } else {
      problems_.add("topology", "edge {} - {} is shared by {} triangles", pt(a), pt(b), uses.size());
    }
  }
}

// Euler characteristic of a triangulated surface with C disk-like components and B boundary loops.
void MeshChecker::check_euler() {
  std::unordered_set<int> used_vertices;
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t)
    if (valid_[t]) used_vertices.insert(mesh_.triangles[t].begin(), mesh_.triangles[t].end());
  std::unordered_set<int> component_roots, loop_roots;
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t)
    if (valid_[t]) component_roots.insert(components_.find(static_cast<int>(t)));
  for (int vtx : boundary_vertices_) loop_roots.insert(loops_.find(vtx));
  const long long euler = static_cast<long long>(used_vertices.size()) - static_cast<long long>(edges_.size()) +
                          static_cast<long long>(std::count(valid_.begin(), valid_.end(), true));
  const long long expected =
      2 * static_cast<long long>(component_roots.size()) - static_cast<long long>(loop_roots.size());
  if (euler != expected) {
    problems_.add(
        "euler",
        "V - E + F = {} but 2 * components - boundary loops = 2 * {} - {} (V {}, E {}, F {}, {} boundary edges)", euler,
        component_roots.size(), loop_roots.size(), used_vertices.size(), edges_.size(),
        std::count(valid_.begin(), valid_.end(), true), boundary_edge_count_);
  }
}

// The valid triangles' areas sum to the domain's.
void MeshChecker::check_area(double domain_area) {
  double area = 0.0;
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
    if (!valid_[t]) continue;
    const auto& tv = mesh_.triangles[t];
    area += 0.5 * cross(P_[tv[1]] - P_[tv[0]], P_[tv[2]] - P_[tv[0]]);
  }
  if (!(std::fabs(area - domain_area) <= 1e-9 * std::fabs(domain_area)))
    problems_.add("area", "triangle areas sum to {} but the domain area is {}", area, domain_area);
}

}  // namespace

std::string CheckReport::summary() const {
  if (problems.empty()) return "ok";
  std::string s;
  for (const auto& p : problems) s += p + "\n";
  return s;
}

CheckReport check_mesh(const Mesh& mesh, std::optional<double> domain_area) {
  CheckReport report;
  MeshChecker checker(mesh, report);
  checker.check_triangles();
  checker.collect_edges();
  checker.check_boundary_edges();
  checker.check_edges();
  checker.check_euler();
  if (domain_area) checker.check_area(*domain_area);
  return report;
}

}  // namespace pdmesh
