// The editable mesh cut along an embedded constraint: Lawson flips reach the edges of a constraint
// node's fan on either side of the cut.
#include <catch2/catch.hpp>

#include <algorithm>
#include <vector>

#include "cleanup/editable_mesh.hpp"
#include "core/predicates.hpp"
#include "mesh/mesh.hpp"

using namespace pdmesh;

namespace {

// Whether a live triangle of m has both a and b as vertices.
bool has_edge(const cleanup::EditableMesh& m, int a, int b) {
  for (int t = 0; t < m.triangle_slots(); ++t) {
    if (!m.alive(t)) continue;
    const auto& tv = m.v[t];
    if (std::count(tv.begin(), tv.end(), a) + std::count(tv.begin(), tv.end(), b) == 2) return true;
  }
  return false;
}

}  // namespace

TEST_CASE("legalize flips a non-Delaunay edge at a constraint node in the fan its vertex record does not name",
          "[cleanup]") {
  //          Y            The constraint 0 - 1 - 2 (C0, C, C1) cuts the mesh: C has one fan above it and
  //         /|\           one below. Above, the edge C-Y of the kite C, R, Y, L is not Delaunay (L and R
  //        L | R          lie inside the other triangle's circumcircle). The triangles below come last,
  //       /  |  \         so C's vertex record (vt) names a triangle of the lower fan, where a walk
  //     C0---C---C1       around C does not find the edge C-Y.
  //        \ | /
  //          B
  enum { C0, C, C1, L, R, Y, B };
  Mesh mesh;
  mesh.points = {{0.5, 1.0}, {1.0, 1.0}, {1.5, 1.0}, {0.8, 1.5}, {1.2, 1.5}, {1.0, 2.0}, {1.0, 0.5}};
  mesh.kind = {NodeKind::Fixed,    NodeKind::Fixed,    NodeKind::Fixed,   NodeKind::Interior,
               NodeKind::Interior, NodeKind::Interior, NodeKind::Interior};
  mesh.triangles = {{C, R, Y}, {C, Y, L}, {C, C1, R}, {C, L, C0}, {C, C0, B}, {C, B, C1}};
  mesh.boundary_edges = {{C0, C, 0}, {C, C1, 0}};
  mesh.constraint_curves = {1};
  for (const auto& tv : mesh.triangles)
    REQUIRE(orient2d(mesh.points[tv[0]], mesh.points[tv[1]], mesh.points[tv[2]]) > 0.0);
  REQUIRE(incircle(mesh.points[C], mesh.points[R], mesh.points[Y], mesh.points[L]) > 0.0);

  cleanup::EditableMesh m(mesh, {{C0, C, C1}}, {{0.0, 0.5, 1.0}});
  REQUIRE(m.vt[C] >= 4);            // a triangle of the lower fan
  CHECK(m.find_edge(C, Y)[0] < 0);  // the walk around C stays in the lower fan
  // The edges opposite L: C-Y and the constraint edge C0-C, which is not flipped.
  std::vector<cleanup::EdgeRef> edges;
  m.push_link_edges(L, edges);
  m.legalize(edges);
  CHECK_FALSE(has_edge(m, C, Y));
  CHECK(has_edge(m, L, R));
  CHECK(has_edge(m, C0, C));
  CHECK(has_edge(m, C, C1));
  for (int t = 0; t < m.triangle_slots(); ++t) {
    const auto& tv = m.v[t];
    CHECK(orient2d(m.p[tv[0]], m.p[tv[1]], m.p[tv[2]]) > 0.0);
    // Every unconstrained interior edge is locally Delaunay now.
    for (int i = 0; i < 3; ++i) {
      const int u = m.n[t][i];
      if (u < 0) continue;
      const int q = m.v[u][cleanup::EditableMesh::index_of(m.n[u], t)];
      CHECK_FALSE(incircle(m.p[tv[0]], m.p[tv[1]], m.p[tv[2]], m.p[q]) > 0.0);
    }
  }
}
