// Node set -> constrained Delaunay mesh: Delaunay, boundary recovery, outside removal; optionally
// then Delaunay in a metric.
#include "mesh/triangulate_nodes.hpp"

#include <fmt/format.h>

#include <cstring>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "mesh/constrain.hpp"
#include "mesh/delaunay.hpp"
#include "mesh/metric_delaunay.hpp"

namespace pdmesh {

namespace {

// Each curve's chain of nodes as constrained edges, in curve order; the embedded constraints' edges
// also in `open_edges`. Throws GeometryError for an edge claimed by two curves.
struct Chains {
  std::vector<ConstrainedEdge> edges;
  std::unordered_set<std::uint64_t> open_edges;
};

Chains curve_chains(const NodeSet& nodes, const std::vector<std::string>& curve_names) {
  if (curve_names.size() != nodes.curve_nodes.size()) {
    throw InputError(
        fmt::format("triangulate: {} curve names for {} node curves", curve_names.size(), nodes.curve_nodes.size()));
  }
  Chains chains;
  std::unordered_map<std::uint64_t, int> edge_curve;  // catches an edge claimed by two curves
  const auto& open = nodes.constraint_curves;
  for (std::size_t c = 0; c < nodes.curve_nodes.size(); ++c) {
    const auto& list = nodes.curve_nodes[c];
    for (std::size_t k = 0; k + 1 < list.size(); ++k) {
      const ConstrainedEdge e{list[k], list[k + 1], static_cast<int>(c)};
      const auto [it, fresh] = edge_curve.emplace(Triangulation::edge_key(e.a, e.b), e.curve);
      if (!fresh) {
        throw GeometryError(
            fmt::format("boundary edge between nodes {} and {} belongs to curve {} ('{}') and curve {} ('{}')", e.a,
                        e.b, it->second, curve_names[it->second], c, curve_names[c]));
      }
      chains.edges.push_back(e);
      if (c < open.size() && open[c]) chains.open_edges.insert(Triangulation::edge_key(e.a, e.b));
    }
  }
  return chains;
}

// The triangles of the nodes with the chains constrained; with metrics, flipped to the Delaunay
// triangulation in the metric (mesh/metric_delaunay.hpp). The Triangulation is freed on return.
std::vector<std::array<int, 3>> chain_triangles(const NodeSet& nodes, const Chains& chains,
                                                const std::vector<Metric>* metrics,
                                                const MetricDelaunayOptions& options, MetricDelaunayStats* stats) {
  Triangulation tri(nodes.x);
  if (!chains.edges.empty()) recover_edges(tri, chains.edges);
  if (metrics) {
    const MetricDelaunayStats s = make_metric_delaunay(tri, *metrics, options);
    if (stats) *stats = s;
  }
  return chains.edges.empty() ? tri.inner_triangles() : inside_triangles(std::move(tri), chains.open_edges);
}

Mesh chain_mesh(const NodeSet& nodes, const std::vector<std::string>& curve_names, const Chains& chains,
                std::vector<std::array<int, 3>> triangles) {
  Mesh mesh;
  mesh.triangles = std::move(triangles);
  mesh.points = nodes.x;
  mesh.kind = nodes.kind;
  mesh.curve_names = curve_names;
  const auto& open = nodes.constraint_curves;
  if (!chains.open_edges.empty()) mesh.constraint_curves.assign(open.begin(), open.end());
  mesh.boundary_edges.reserve(chains.edges.size());
  for (const auto& e : chains.edges) mesh.boundary_edges.push_back({e.a, e.b, e.curve});
  return mesh;
}

// The triangulation of the nodes with each curve's chain of nodes constrained, as a Mesh.
Mesh triangulate_nodes(const NodeSet& nodes, const std::vector<std::string>& curve_names,
                       const std::vector<Metric>* metrics, const MetricDelaunayOptions& options,
                       MetricDelaunayStats* stats) {
  const Chains chains = curve_chains(nodes, curve_names);
  return chain_mesh(nodes, curve_names, chains, chain_triangles(nodes, chains, metrics, options, stats));
}

}  // namespace

Mesh triangulate(const NodeSet& nodes, const std::vector<std::string>& curve_names) {
  return triangulate_nodes(nodes, curve_names, nullptr, {}, nullptr);
}

std::vector<std::array<int, 3>> triangulate_triangles(const NodeSet& nodes,
                                                      const std::vector<std::string>& curve_names) {
  return chain_triangles(nodes, curve_chains(nodes, curve_names), nullptr, {}, nullptr);
}

std::optional<std::vector<std::array<int, 3>>> triangulate_triangles_from(Triangulation tri, const NodeSet& nodes,
                                                                          const std::vector<std::string>& curve_names) {
  Triangulation& t = tri;
  const auto held = static_cast<std::size_t>(t.input_count);
  if (held > nodes.x.size() || t.points.size() != held + 3 || t.input_index.size() != held) return std::nullopt;
  for (std::size_t k = 0; k < held; ++k) {
    const Vec2 a = t.points[k], b = nodes.x[static_cast<std::size_t>(t.input_index[k])];
    if (std::memcmp(&a, &b, sizeof(Vec2)) != 0) return std::nullopt;
  }
  try {
    if (!t.add_points(nodes.x) || !t.unique_inner_triangles()) return std::nullopt;
    // The same Delaunay triangles as the construction's: recovery starts from the same set, and when
    // every boundary edge is an edge of it, only marks them. When it flips (a boundary edge that is no
    // Delaunay edge), the flips and the Lawson pass after them run in another order there; the
    // constrained Delaunay triangulation they reach is the same when it is the only one, which the
    // second check says.
    const Chains chains = curve_chains(nodes, curve_names);
    bool all_edges = true;
    for (const ConstrainedEdge& e : chains.edges) {
      if (e.a < 0 || e.b < 0 || e.a >= t.input_count || e.b >= t.input_count) return std::nullopt;
      const int a = t.vertex_of[static_cast<std::size_t>(e.a)], b = t.vertex_of[static_cast<std::size_t>(e.b)];
      if (t.find_edge(a, b)[0] < 0 && t.find_edge(b, a)[0] < 0) all_edges = false;
    }
    if (!chains.edges.empty()) recover_edges(t, chains.edges);
    if (!all_edges && !t.unique_inner_triangles()) return std::nullopt;
    return chains.edges.empty() ? t.inner_triangles() : inside_triangles(std::move(t), chains.open_edges);
  } catch (const Interrupted&) {
    throw;
  } catch (const Error&) {
    return std::nullopt;
  }
}

Mesh mesh_of_triangles(const NodeSet& nodes, const std::vector<std::string>& curve_names,
                       std::vector<std::array<int, 3>> triangles) {
  return chain_mesh(nodes, curve_names, curve_chains(nodes, curve_names), std::move(triangles));
}

Mesh triangulate_in_metric(const NodeSet& nodes, const std::vector<std::string>& curve_names,
                           const std::vector<Metric>& metrics, const MetricDelaunayOptions& options,
                           MetricDelaunayStats* stats) {
  return triangulate_nodes(nodes, curve_names, &metrics, options, stats);
}

Mesh triangulate_in_metric(const NodeSet& nodes, const std::vector<std::string>& curve_names, const MetricField& field,
                           const MetricDelaunayOptions& options, MetricDelaunayStats* stats) {
  std::vector<Metric> metrics;
  metrics.reserve(nodes.x.size());
  for (const Vec2& p : nodes.x) metrics.push_back(field.at(p));
  return triangulate_nodes(nodes, curve_names, &metrics, options, stats);
}

bool triangulates(const Mesh& mesh, const NodeSet& nodes) {
  // Positions bit for bit (== on doubles would also take -0.0 for 0.0).
  if (mesh.points.size() != nodes.x.size() || mesh.kind != nodes.kind ||
      (!mesh.points.empty() && std::memcmp(mesh.points.data(), nodes.x.data(), nodes.x.size() * sizeof(Vec2)) != 0))
    return false;
  std::size_t k = 0;  // the boundary edges are the curve chains' pairs, in curve order
  for (std::size_t c = 0; c < nodes.curve_nodes.size(); ++c) {
    const auto& list = nodes.curve_nodes[c];
    for (std::size_t i = 0; i + 1 < list.size(); ++i, ++k) {
      if (k >= mesh.boundary_edges.size()) return false;
      const BoundaryEdge& e = mesh.boundary_edges[k];
      if (e.a != list[i] || e.b != list[i + 1] || e.curve != static_cast<int>(c)) return false;
    }
  }
  return k == mesh.boundary_edges.size();
}

}  // namespace pdmesh
