// The cleanup's shortcuts around its sweeps (issue 41) against the serial ways they replace: the
// editable mesh's neighbours found on several threads against a map of half-edges, the Delaunay test
// of the whole mesh against Lawson flips over every edge, a sweep move given the star the strips' test
// walked against one that walks it, and the sweeps' skip of a vertex whose move failed on the star it
// still has against trying that move again.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <random>
#include <unordered_map>
#include <vector>

#include "cleanup/editable_mesh.hpp"
#include "cleanup/smoothing.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "nodes/boundary_arcs.hpp"
#include "spacing/spacing_field.hpp"
#include "holed_square_mesh.hpp"

using namespace pdmesh;
using cleanup::EditableMesh;

namespace {

// The holed square (holed_square_mesh.hpp), seeded 11.
struct Holed : fixtures::HoledSquareMesh {
  Holed() : HoledSquareMesh(11) {}
  EditableMesh editable(std::size_t threads) const {
    return EditableMesh(mesh, nodes.curve_nodes, boundary_arcs(g, nodes), threads);
  }
};

std::uint64_t key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// Lawson flips from every edge of the live triangles; true when any edge was flipped.
bool legalize_everything(EditableMesh& m) {
  const auto before = m.v;
  std::vector<cleanup::EdgeRef> edges;
  for (int t = 0; t < m.triangle_slots(); ++t)
    if (m.alive(t))
      for (int i = 0; i < 3; ++i) edges.push_back({m.v[t][pdmesh::next3(i)], m.v[t][pdmesh::prev3(i)], t});
  m.legalize(edges);
  return m.v != before;
}

}  // namespace

TEST_CASE("the editable mesh's neighbours and vertex records on 1 and 2 threads are a half-edge map's", "[cleanup]") {
  const Holed h;
  REQUIRE(h.mesh.triangles.size() > 16384);
  // The reference: each triangle's edges in a map of directed half-edges (the first one kept), every
  // edge looked up reversed; a vertex's record names the last triangle that has it.
  const auto& tri = h.mesh.triangles;
  std::unordered_map<std::uint64_t, int> half_edges;
  for (int t = 0; t < static_cast<int>(tri.size()); ++t)
    for (int i = 0; i < 3; ++i) half_edges.emplace(key(tri[t][pdmesh::next3(i)], tri[t][pdmesh::prev3(i)]), t);
  std::vector<std::array<int, 3>> n(tri.size(), {-1, -1, -1});
  std::vector<int> vt(h.mesh.points.size(), -1);
  for (int t = 0; t < static_cast<int>(tri.size()); ++t) {
    for (int i = 0; i < 3; ++i) {
      const auto it = half_edges.find(key(tri[t][pdmesh::prev3(i)], tri[t][pdmesh::next3(i)]));
      if (it != half_edges.end()) n[t][i] = it->second;
    }
    for (int a : tri[t]) vt[a] = t;
  }
  for (const std::size_t threads : {1, 2}) {
    INFO(threads << " threads");
    const EditableMesh m = h.editable(threads);
    CHECK(m.n == n);
    CHECK(m.vt == vt);
  }
}

TEST_CASE("the whole mesh's Delaunay test answers whether Lawson flips over every edge flip any", "[cleanup]") {
  const Holed h;
  {
    EditableMesh m = h.editable(2);
    CHECK(m.locally_delaunay(1));
    CHECK(m.locally_delaunay(2));
    CHECK_FALSE(legalize_everything(m));
  }
  // Interior nodes pushed about by up to `push` (no push: no illegal edge), a push kept only where no
  // triangle of the node's star inverts, so that the flips work on a valid mesh.
  std::mt19937_64 rng(5);
  for (const double push : {0.0, 0.002, 0.02}) {
    INFO("push " << push);
    EditableMesh m = h.editable(2);
    std::uniform_real_distribution<double> d(-push, push);
    for (int a = 0; a < m.vertex_slots(); ++a) {
      if (m.kind[a] != NodeKind::Interior) continue;
      const Vec2 was = m.p[a];
      m.p[a] = was + Vec2{d(rng), d(rng)};
      if (!m.star_valid(a)) m.p[a] = was;
    }
    const bool one = m.locally_delaunay(1), two = m.locally_delaunay(2);
    CHECK(one == two);
    CHECK(one == !legalize_everything(m));
    if (push > 0.01) CHECK_FALSE(one);  // so the test can fail both ways
  }
}

TEST_CASE("a sweep move given the star the strips' test walked is the move that walks it", "[cleanup]") {
  const Holed h;
  EditableMesh walked = h.editable(1), given = h.editable(2);
  cleanup::Smoother walks(walked, h.g, 0.5), takes(given, h.g, 0.5);
  std::size_t moved = 0;
  for (int sweep = 0; sweep < 2; ++sweep)
    for (int a = 0; a < walked.vertex_slots(); ++a) {
      const bool climb = (a + sweep) % 2 == 1;
      given.star(a, takes.star_buffer());
      const bool x = climb ? walks.climb(a) : walks.relax(a);
      const bool y = climb ? takes.climb_with_star(a) : takes.relax_with_star(a);
      REQUIRE(x == y);
      moved += x;
    }
  CHECK(moved > 1000);
  CHECK(walked.p == given.p);
  CHECK(walked.v == given.v);
}

TEST_CASE(
    "the marks' epochs: a vertex is marked when its star changed since the epoch began, a triangle when its points did",
    "[cleanup]") {
  const Holed h;
  EditableMesh m = h.editable(2);
  // Every vertex is new to the first epoch; none is marked in the next one until an edit marks it.
  const std::uint32_t first = m.epoch();
  CHECK(m.marked_in(0, first));
  m.next_epoch();
  const std::uint32_t e = m.epoch();
  for (int a = 0; a < m.vertex_slots(); ++a) REQUIRE_FALSE(m.marked_in(a, e));
  // An interior vertex moved a little outside a transaction: its star's vertices are marked, and only they.
  int a = 0;
  while (m.kind[a] != NodeKind::Interior) ++a;
  std::vector<int> star, ring;
  m.star(a, star);
  m.ring(a, ring);
  m.move(a, m.p[a] + Vec2{1e-6, 0.0}, m.arc[a]);
  int marked = 0;
  for (int b = 0; b < m.vertex_slots(); ++b) marked += m.marked_in(b, e) ? 1 : 0;
  CHECK(m.marked_in(a, e));
  for (int b : ring) CHECK(m.marked_in(b, e));
  CHECK(marked == 1 + static_cast<int>(ring.size()));
  // Of the triangle slots, exactly the star's are marked (the only ones whose points changed).
  CHECK(m.any_marked_in(e));
  std::vector<int> marked_slots;
  for (int t = 0; t < m.triangle_slots(); ++t)
    if (m.triangle_marked_in(t, e)) marked_slots.push_back(t);
  std::vector<int> sorted_star = star;
  std::sort(sorted_star.begin(), sorted_star.end());
  CHECK(marked_slots == sorted_star);
  // take_dirty() clears the dirty flags, not the epochs' marks.
  m.take_dirty();
  CHECK(m.marked_in(a, e));
  // In a new epoch: an edit rolled back marks nothing, a committed one marks its triangles' vertices.
  m.next_epoch();
  const std::uint32_t e2 = m.epoch();
  m.begin();
  m.move(a, m.p[a] + Vec2{1e-6, 0.0}, m.arc[a]);
  m.rollback();
  for (int b = 0; b < m.vertex_slots(); ++b) REQUIRE_FALSE(m.marked_in(b, e2));
  for (int t = 0; t < m.triangle_slots(); ++t) REQUIRE_FALSE(m.triangle_marked_in(t, e2));
  // Nor does an insertion rolled back (its new slots and vertex are gone).
  m.begin();
  m.insert_in_triangle(star[0], (1.0 / 3.0) * (m.p[m.v[star[0]][0]] + m.p[m.v[star[0]][1]] + m.p[m.v[star[0]][2]]));
  m.rollback();
  CHECK_FALSE(m.any_marked_in(e2));
  m.begin();
  m.move(a, m.p[a] + Vec2{1e-6, 0.0}, m.arc[a]);
  m.commit();
  CHECK(m.any_marked_in(e2));
  CHECK(m.marked_in(a, e2));
  for (int b : ring) CHECK(m.marked_in(b, e2));
  for (int t : star) CHECK(m.triangle_marked_in(t, e2));
  // An insertion outside a transaction: its triangle's slot and the new ones are marked.
  m.next_epoch();
  const std::uint32_t e3 = m.epoch();
  const int slots = m.triangle_slots();
  const int t0 = star[0];
  m.insert_in_triangle(t0, (1.0 / 3.0) * (m.p[m.v[t0][0]] + m.p[m.v[t0][1]] + m.p[m.v[t0][2]]));
  CHECK(m.any_marked_in(e3));
  CHECK(m.triangle_marked_in(t0, e3));
  for (int t = slots; t < m.triangle_slots(); ++t) CHECK(m.triangle_marked_in(t, e3));
}

TEST_CASE("a sweep move's unmoved bit stays until a mark of its vertex, and trying the move again finds nothing",
          "[cleanup]") {
  const Holed h;
  EditableMesh m = h.editable(1);
  cleanup::Smoother s(m, h.g, 0.5);
  constexpr std::uint8_t kRelax = 1, kClimb = 2;
  // Sweeps as the cleanup makes them (relax, then climb, over every vertex) from a random start mesh,
  // skipping the vertices whose bit is set: a bit set in one sweep is cleared when a later move marks
  // the vertex, or stays.
  int set = 0, skipped = 0;
  for (int sweep = 0; sweep < 24; ++sweep)
    for (int a = 0; a < m.vertex_slots(); ++a) {
      const std::uint8_t bit = sweep % 2 == 1 ? kClimb : kRelax;
      if (m.unmoved(a, bit)) {
        ++skipped;
        continue;
      }
      if (!(bit == kClimb ? s.climb(a) : s.relax(a))) {
        m.set_unmoved(a, bit);
        ++set;
      }
    }
  int stayed = 0;
  for (int a = 0; a < m.vertex_slots(); ++a) stayed += m.unmoved(a, kRelax) && m.unmoved(a, kClimb) ? 1 : 0;
  INFO("set " << set << ", skipped " << skipped << ", both bits " << stayed);
  REQUIRE(set > 1000);
  REQUIRE(skipped > 100);
  REQUIRE(skipped < set);
  REQUIRE(stayed > 100);
  // Where a bit stayed, the star is the one the move failed on: trying it again moves nothing.
  const auto p = m.p;
  for (int a = 0; a < m.vertex_slots(); ++a) {
    if (m.unmoved(a, kRelax)) REQUIRE_FALSE(s.relax(a));
    if (m.unmoved(a, kClimb)) REQUIRE_FALSE(s.climb(a));
  }
  CHECK(m.p == p);
  // A move of an interior vertex clears the bits of its star's vertices, and only theirs; a move
  // rolled back clears none; a new vertex has none.
  int a = 0;
  while (m.kind[a] != NodeKind::Interior) ++a;
  for (int b = 0; b < m.vertex_slots(); ++b) m.set_unmoved(b, kRelax | kClimb);
  m.begin();
  m.move(a, m.p[a] + Vec2{1e-6, 0.0}, m.arc[a]);
  m.rollback();
  for (int b = 0; b < m.vertex_slots(); ++b) REQUIRE(m.unmoved(b, kRelax));
  std::vector<int> ring;
  m.ring(a, ring);
  m.move(a, m.p[a] + Vec2{1e-6, 0.0}, m.arc[a]);
  int clear = 0;
  for (int b = 0; b < m.vertex_slots(); ++b) clear += m.unmoved(b, kRelax) || m.unmoved(b, kClimb) ? 0 : 1;
  CHECK_FALSE(m.unmoved(a, kClimb));
  for (int b : ring) CHECK_FALSE(m.unmoved(b, kRelax));
  CHECK(clear == 1 + static_cast<int>(ring.size()));
  int t = 0;
  while (!m.alive(t)) ++t;
  const Vec2 centroid = (1.0 / 3.0) * (m.p[m.v[t][0]] + m.p[m.v[t][1]] + m.p[m.v[t][2]]);
  const int w = m.insert_in_triangle(t, centroid);
  CHECK_FALSE(m.unmoved(w, kRelax));
  CHECK_FALSE(m.unmoved(w, kClimb));
}
