// The smoother's line search (cleanup/smoothing.cpp, Smoother::try_move) scores first, at each halved
// step, the triangle whose score rejected the step before, and takes the sides it does not move from
// the star once; here against the plain form of its rule, one pass over the star that checks each
// triangle's orientation, score and aspect ratio in turn: the same step taken, or none, at every
// interior vertex of a random mesh.
#include <catch2/catch.hpp>

#include <algorithm>
#include <limits>
#include <optional>
#include <vector>

#include "cleanup/editable_mesh.hpp"
#include "cleanup/measures.hpp"
#include "cleanup/smoothing.hpp"
#include "core/predicates.hpp"
#include "nodes/boundary_arcs.hpp"
#include "holed_square_mesh.hpp"

using namespace pdmesh;
using cleanup::EditableMesh;

namespace {

constexpr double kStepCap = 0.5;

// Smoother::relax of an interior vertex with the plain rule: the ODT step capped at kStepCap x the
// smallest inradius, halved up to three times; the first step with every triangle counter-clockwise,
// no score below the star's smallest, an aspect-ratio sum not above the star's and one of the two
// strictly better is taken. Returns where it puts a, or nothing.
std::optional<Vec2> plain_relax(const EditableMesh& m, int a) {
  std::vector<int> fan;
  m.star(a, fan);
  double old_min = std::numeric_limits<double>::infinity(), old_sum = 0.0, area_sum = 0.0;
  double r_min = std::numeric_limits<double>::infinity();
  Vec2 weighted{};
  for (int t : fan) {
    const auto& tv = m.v[t];
    const Vec2 x = m.p[tv[0]], y = m.p[tv[1]], z = m.p[tv[2]];
    old_min = std::min(old_min, m.score_of(t, x, y, z));
    double r = 0.0;
    old_sum += cleanup::aspect_ratio_and_inradius(x, y, z, r);
    const double area = 0.5 * cross(y - x, z - x);
    weighted = weighted + area * cleanup::circumcentre(x, y, z);
    area_sum += area;
    r_min = std::min(r_min, r);
  }
  if (!(area_sum > 0.0)) return std::nullopt;
  Vec2 d = (1.0 / area_sum) * weighted - m.p[a];
  const double length = norm(d), cap = kStepCap * r_min;
  if (!(length > 0.0)) return std::nullopt;
  if (length > cap) d = (cap / length) * d;
  const Vec2 from = m.p[a];
  for (int k = 0; k < 4; ++k, d = 0.5 * d) {
    const Vec2 to = from + d;
    if (to == from) return std::nullopt;
    double new_min = std::numeric_limits<double>::infinity(), new_sum = 0.0;
    bool valid = true;
    for (int t : fan) {
      const auto& tv = m.v[t];
      const Vec2 x = tv[0] == a ? to : m.p[tv[0]], y = tv[1] == a ? to : m.p[tv[1]], z = tv[2] == a ? to : m.p[tv[2]];
      if (!(orient2d(x, y, z) > 0.0)) {
        valid = false;
        break;
      }
      new_min = std::min(new_min, m.score_of(t, x, y, z));
      new_sum += cleanup::aspect_ratio(x, y, z);
    }
    if (!valid || new_min < old_min || new_sum > old_sum) continue;
    if (!(new_min - old_min > 0.0 || old_sum - new_sum > 0.0)) continue;
    return to;
  }
  return std::nullopt;
}

}  // namespace

TEST_CASE("the smoother's line search takes the step the plain one-pass rule takes", "[cleanup]") {
  const fixtures::HoledSquareMesh h(7);
  EditableMesh m(h.mesh, h.nodes.curve_nodes, boundary_arcs(h.g, h.nodes), 1);
  cleanup::Smoother smoother(m, h.g, kStepCap);
  // A move that needs Lawson flips is left out (deferred), so the mesh keeps its triangles and each
  // vertex is judged on the stars the plain rule sees.
  smoother.set_defer_flips(true);
  std::size_t moved = 0, refused = 0, deferred = 0;
  for (int sweep = 0; sweep < 3; ++sweep)
    for (int a = 0; a < m.vertex_slots(); ++a) {
      if (m.kind[a] != NodeKind::Interior) continue;
      const std::optional<Vec2> plain = plain_relax(m, a);
      const Vec2 before = m.p[a];
      const bool x = smoother.relax(a);
      INFO("sweep " << sweep << ", vertex " << a);
      if (x) {
        ++moved;
        REQUIRE(plain.has_value());
        REQUIRE(m.p[a].x == plain->x);
        REQUIRE(m.p[a].y == plain->y);
      } else if (smoother.deferred()) {
        ++deferred;
        REQUIRE(plain.has_value());
        REQUIRE(m.p[a] == before);
      } else {
        ++refused;
        REQUIRE_FALSE(plain.has_value());
        REQUIRE(m.p[a] == before);
      }
    }
  // A random start: many moves, many refusals and some that would flip, so each way is compared.
  CHECK(moved > 1000);
  CHECK(refused > 1000);
  CHECK(deferred > 10);
}
