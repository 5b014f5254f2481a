// The cleanup's whole-mesh lists (host/cleanup/mesh_lists.hpp) on 1, 2 and 3 threads against one pass
// in slot order: the same vertices, the same sorted triangles, the same worst score, count and
// shortfall sum (to the bit).
#include <catch2/catch.hpp>

#include <cstdint>
#include <random>
#include <set>
#include <vector>

#include "cleanup/editable_mesh.hpp"
#include "cleanup/mesh_lists.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "nodes/boundary_arcs.hpp"
#include "spacing/spacing_field.hpp"
#include "holed_square_mesh.hpp"

using namespace pdmesh;
using cleanup::EditableMesh;

namespace {

// The holed square (holed_square_mesh.hpp), seeded 5.
struct Holed : fixtures::HoledSquareMesh {
  Holed() : HoledSquareMesh(5) {}
};

}  // namespace

TEST_CASE("the cleanup's lists on several threads are one slot-order pass's", "[cleanup]") {
  const Holed h;
  EditableMesh m(h.mesh, h.nodes.curve_nodes, boundary_arcs(h.g, h.nodes), 1);
  REQUIRE(m.triangle_slots() > 16384);
  // A dead triangle (its slot stays) and scores of every kind: the mesh's own, a few far below.
  m.v[7][0] = -1;
  std::vector<double> score(static_cast<std::size_t>(m.triangle_slots()), 0.0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int t = 0; t < m.triangle_slots(); ++t)
    if (m.alive(t)) score[static_cast<std::size_t>(t)] = unit(rng) < 0.05 ? 0.01 * unit(rng) : m.quality(t);
  auto keep = [](int t) { return t % 7 != 3; };
  const double limit = 0.8, target = 0.6;

  // One pass in slot order.
  std::set<int> vertex_set;
  std::vector<std::pair<double, int>> bad;
  double worst = 1.0, count = 0.0, deficit = 0.0;
  for (int t = 0; t < m.triangle_slots(); ++t) {
    if (!m.alive(t)) continue;
    const double q = score[static_cast<std::size_t>(t)];
    if (q < limit) {
      for (int a : m.v[t]) vertex_set.insert(a);
      if (keep(t)) bad.push_back({q, t});
    }
    worst = std::min(worst, q);
    if (q < target) deficit += target - q;
    count += 1.0;
  }
  std::sort(bad.begin(), bad.end());
  const std::vector<int> vertices(vertex_set.begin(), vertex_set.end());
  REQUIRE(!vertices.empty());
  REQUIRE(bad.size() > 100);

  for (const std::size_t threads : {std::size_t{1}, std::size_t{2}, std::size_t{3}}) {
    INFO("threads " << threads);
    std::vector<std::uint8_t> mark;
    CHECK(cleanup::vertices_of_bad_triangles(m, score, limit, mark, threads) == vertices);
    CHECK(cleanup::bad_triangles(m, score, limit, keep, threads) == bad);
    const cleanup::ScoreScan s = cleanup::scan_scores(m, score, target, threads);
    CHECK(s.worst == worst);
    CHECK(s.count == count);
    CHECK(s.deficit == deficit);
  }
}
