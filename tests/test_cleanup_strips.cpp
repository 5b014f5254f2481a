// The cleanup's sweeps in strips (host/cleanup/strip_sweeps.hpp, issue 41): the same mesh on any
// number of threads, the cleanup's guarantees kept, the strips doing the work (not the serial pass
// for the vertices they leave), small meshes in kSmallStrips strips, and the independence rule: what a
// strip may move touches nothing that a strip two or more away reads or writes.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "cleanup/cleanup.hpp"
#include "cleanup/editable_mesh.hpp"
#include "cleanup/strip_sweeps.hpp"
#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "mesh/mesh_check.hpp"
#include "mesh/quality.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "nodes/boundary_arcs.hpp"
#include "nodes/node_domain.hpp"
#include "spacing/spacing_field.hpp"
#include "geometry_fixtures.hpp"

using namespace pdmesh;

namespace {

// A square of side 8 with `n` segments a side, and a circular hole of `m` segments a half: about
// (n / 8)^2 x 60 nodes from the boundary spacing.
Geometry plate(int n, int m) {
  const Vec2 c[4] = {{0, 0}, {8, 0}, {8, 8}, {0, 8}};
  std::vector<Vec2> pts;
  for (int side = 0; side < 4; ++side)
    for (int k = 0; k < n; ++k) pts.push_back(c[side] + (static_cast<double>(k) / n) * (c[(side + 1) % 4] - c[side]));
  pts.push_back(c[0]);
  std::vector<RawCurve> raw = {fixtures::raw_polyline(pts, "square")};
  for (int half = 0; half < 2; ++half) {
    std::vector<Vec2> arc;
    for (int i = 0; i <= m; ++i) {
      const double t = M_PI * (half + static_cast<double>(i) / m);
      arc.push_back({4.3 + 1.5 * std::cos(t), 3.7 + 1.5 * std::sin(t)});
    }
    arc.front() = {half == 0 ? 5.8 : 2.8, 3.7};
    arc.back() = {half == 0 ? 2.8 : 5.8, 3.7};
    raw.push_back(fixtures::raw_polyline(arc, "hole" + std::to_string(half)));
  }
  return build_geometry(std::move(raw));
}

std::vector<std::string> names(const Geometry& g) {
  std::vector<std::string> out;
  for (const Curve& c : g.curves) out.push_back(c.name);
  return out;
}

struct Plate {
  Geometry g = plate(96, 60);
  GeometryTree tree{g};
  BoundarySpacing spacing{tree};
  NodeSet nodes;
  Mesh mesh;
  explicit Plate(InitMethod method) {
    nodes = make_initial_distribution(tree, spacing, {method, 7, {}, false}).nodes;
    mesh = triangulate(nodes, names(g));
  }
};

// A valid mesh of the domain, no lower smallest angle and no higher mean aspect ratio than the input's.
void check_guarantees(const Plate& p, const CleanupResult& r) {
  const CheckReport check = check_mesh(r.mesh, node_domain_area(r.nodes, p.g));
  INFO(check.summary());
  CHECK(check.ok());
  const QualitySummary before = summarize_quality(p.mesh), after = summarize_quality(r.mesh);
  CHECK(after.min_angle >= before.min_angle);
  CHECK(after.aspect_ratio_avg <= before.aspect_ratio_avg);
  CHECK(after.min_jacobian > 0.0);
}

CleanupOptions in_strips(std::size_t threads) {
  CleanupOptions o;
  o.min_angle = 40.0;
  o.iterations = 12;
  o.strip_vertices = 1000;
  o.threads = threads;
  return o;
}

}  // namespace

TEST_CASE("sweeps in strips give the same mesh on 1, 2 and 3 threads and keep the cleanup's guarantees", "[cleanup]") {
  for (const InitMethod method : {InitMethod::Random, InitMethod::Structured}) {
    INFO("init " << static_cast<int>(method));
    const Plate p(method);
    REQUIRE(p.mesh.points.size() >= CleanupOptions::kMinStrips * in_strips(1).strip_vertices);
    const CleanupResult one = clean_mesh(p.mesh, p.nodes, p.tree, p.spacing, in_strips(1));
    REQUIRE(one.stats.strips >= static_cast<int>(CleanupOptions::kMinStrips));
    // The strips take most of the sweeps' vertices; the serial pass some (the strips' edges, flips).
    CHECK(one.stats.strip_taken > 4 * one.stats.strip_left);
    CHECK(one.stats.strip_left > 0);
    CHECK(one.stats.moves > 0);
    check_guarantees(p, one);
    for (const std::size_t threads : {2, 3}) {
      INFO(threads << " threads");
      const CleanupResult r = clean_mesh(p.mesh, p.nodes, p.tree, p.spacing, in_strips(threads));
      CHECK(r.mesh.points == one.mesh.points);  // bit-identical (Vec2 == compares exactly)
      CHECK(r.mesh.triangles == one.mesh.triangles);
      CHECK(r.stats.moves == one.stats.moves);
      CHECK(r.stats.iterations_run == one.stats.iterations_run);
      REQUIRE(r.stats.per_iteration.size() == one.stats.per_iteration.size());
      for (std::size_t k = 0; k < r.stats.per_iteration.size(); ++k)
        CHECK(r.stats.per_iteration[k].aspect_drop == one.stats.per_iteration[k].aspect_drop);
    }
  }
}

TEST_CASE("sweeps in strips repair a perturbed lattice as well as the serial sweeps", "[cleanup]") {
  // A hexagonal fill with its interior nodes moved by up to 0.2 q along each axis: a lattice like the
  // simulation's, with bad triangles everywhere (the strips' edges cross many of them).
  Plate p(InitMethod::Hexagonal);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t i = 0; i < p.nodes.size(); ++i)
    if (p.nodes.kind[i] == NodeKind::Interior)
      p.nodes.x[i] = p.nodes.x[i] + (0.2 * p.nodes.q[i]) * Vec2{u(rng), u(rng)};
  p.mesh = triangulate(p.nodes, names(p.g));
  CleanupOptions serial = in_strips(0);
  serial.iterations = 32;
  serial.strip_vertices = 0;
  CleanupOptions strips = serial;
  strips.strip_vertices = 1000;
  const CleanupResult s = clean_mesh(p.mesh, p.nodes, p.tree, p.spacing, serial);
  const CleanupResult r = clean_mesh(p.mesh, p.nodes, p.tree, p.spacing, strips);
  CHECK(s.stats.strips == 0);
  REQUIRE(r.stats.strips >= static_cast<int>(CleanupOptions::kMinStrips));
  check_guarantees(p, r);
  QualityOptions qo;
  qo.small_angle_deg = strips.min_angle;
  const QualitySummary qs = summarize_quality(s.mesh, {}, qo), qr = summarize_quality(r.mesh, {}, qo);
  INFO("serial: min " << qs.min_angle << ", AR " << qs.aspect_ratio_avg << "; strips: min " << qr.min_angle << ", AR "
                      << qr.aspect_ratio_avg);
  REQUIRE(qs.small_angle_triangles == 0);  // the serial sweeps reach the target here ...
  CHECK(qr.small_angle_triangles == 0);    // ... and so do the strips
  CHECK(qr.min_angle >= strips.min_angle);
  CHECK(qr.aspect_ratio_avg <= qs.aspect_ratio_avg + 1e-3);
}

TEST_CASE("strips narrower than a star leave their vertices to the serial pass, which keeps every guarantee",
          "[cleanup]") {
  const Plate p(InitMethod::Random);
  CleanupOptions narrow = in_strips(2);
  narrow.strip_vertices = 10;  // kMaxStrips strips of ~170 vertices: a few nodes wide
  const CleanupResult r = clean_mesh(p.mesh, p.nodes, p.tree, p.spacing, narrow);
  CHECK(r.stats.strips == CleanupOptions::kMaxStrips);
  CHECK(r.stats.strip_left > 0);
  check_guarantees(p, r);
  const CleanupResult one = clean_mesh(p.mesh, p.nodes, p.tree, p.spacing, [&] {
    CleanupOptions o = narrow;
    o.threads = 1;
    return o;
  }());
  CHECK(one.mesh.points == r.mesh.points);
  CHECK(one.mesh.triangles == r.mesh.triangles);
}

TEST_CASE("with small_strip_vertices a small mesh sweeps in kSmallStrips strips, the same mesh on 1 and 2 threads",
          "[cleanup]") {
  const Plate p(InitMethod::Random);
  // Below kMinStrips x strip_vertices (the default), at least kSmallStrips x small_strip_vertices.
  CleanupOptions o;
  o.min_angle = 40.0;
  o.iterations = 12;
  CHECK(clean_mesh(p.mesh, p.nodes, p.tree, p.spacing, o).stats.strips == 0);  // off by default
  o.small_strip_vertices = 1000;
  REQUIRE(p.mesh.points.size() < CleanupOptions::kMinStrips * o.strip_vertices);
  REQUIRE(p.mesh.points.size() >= CleanupOptions::kSmallStrips * o.small_strip_vertices);
  o.threads = 1;
  const CleanupResult one = clean_mesh(p.mesh, p.nodes, p.tree, p.spacing, o);
  CHECK(one.stats.strips == CleanupOptions::kSmallStrips);
  CHECK(one.stats.strip_taken > 4 * one.stats.strip_left);
  CHECK(one.stats.strip_left > 0);
  check_guarantees(p, one);
  o.threads = 2;
  const CleanupResult two = clean_mesh(p.mesh, p.nodes, p.tree, p.spacing, o);
  CHECK(two.mesh.points == one.mesh.points);  // bit-identical
  CHECK(two.mesh.triangles == one.mesh.triangles);
  CHECK(two.stats.moves == one.stats.moves);
  REQUIRE(two.stats.per_iteration.size() == one.stats.per_iteration.size());
  for (std::size_t k = 0; k < two.stats.per_iteration.size(); ++k)
    CHECK(two.stats.per_iteration[k].aspect_drop == one.stats.per_iteration[k].aspect_drop);
  // Below kSmallStrips x small_strip_vertices, or with small_strip_vertices 0, the sweeps are serial.
  // Below kSmallStrips x small_strip_vertices the sweeps are serial.
  o.small_strip_vertices = p.mesh.points.size() / CleanupOptions::kSmallStrips + 1;
  CHECK(clean_mesh(p.mesh, p.nodes, p.tree, p.spacing, o).stats.strips == 0);
}

TEST_CASE("what a strip may move touches nothing a strip two or more away reads or writes", "[cleanup]") {
  // Strips s and t may run at the same time when |s - t| >= 2 (strip_schedule.hpp). A move of a
  // vertex a writes a's position and the dirty marks and kept data of a's star, so its vertices {a} +
  // link(a); it reads those, the vertices across its link edges and its curve neighbours. So for every
  // vertex x, every strip that may write x lies within one strip of every strip that reads or writes x.
  const Plate p(InitMethod::Random);
  for (const int strips : {CleanupOptions::kSmallStrips, CleanupOptions::kMaxStrips}) {
    INFO(strips << " strips");
    const cleanup::EditableMesh m(p.mesh, p.nodes.curve_nodes, boundary_arcs(p.g, p.nodes), 1);
    const cleanup::StripSweeps sweeps(m, strips, 1);
    REQUIRE(sweeps.strips() == strips);
    const auto n = static_cast<std::size_t>(m.vertex_slots());
    // Per vertex: the lowest and highest strip that may write it, and that may read or write it.
    std::vector<int> write_lo(n, strips), write_hi(n, -1), touch_lo(n, strips), touch_hi(n, -1);
    std::size_t taken = 0, left = 0;
    std::vector<int> fan, star;
    for (int a = 0; a < m.vertex_slots(); ++a) {
      if (m.removed(a) || !m.movable(a)) continue;
      const int s = sweeps.strip_of_vertex(a);
      if (!sweeps.inside(m, a, s, fan)) {
        ++left;
        continue;
      }
      ++taken;
      std::vector<int> writes = {a}, reads;
      m.star(a, star);
      for (int t : star) {
        const auto& tv = m.v[t];
        const int k = cleanup::EditableMesh::index_of(tv, a);
        writes.push_back(tv[pdmesh::next3(k)]);
        writes.push_back(tv[pdmesh::prev3(k)]);
        const int u = m.n[t][k];
        if (u >= 0) reads.push_back(m.v[u][cleanup::EditableMesh::index_of(m.n[u], t)]);
      }
      if (m.prev[a] >= 0) reads.push_back(m.prev[a]);
      if (m.next[a] >= 0) reads.push_back(m.next[a]);
      for (int x : writes) {
        const auto i = static_cast<std::size_t>(x);
        write_lo[i] = std::min(write_lo[i], s);
        write_hi[i] = std::max(write_hi[i], s);
      }
      reads.insert(reads.end(), writes.begin(), writes.end());
      for (int x : reads) {
        const auto i = static_cast<std::size_t>(x);
        touch_lo[i] = std::min(touch_lo[i], s);
        touch_hi[i] = std::max(touch_hi[i], s);
      }
    }
    std::size_t clashes = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (write_hi[i] >= 0 && (touch_hi[i] - write_lo[i] > 1 || write_hi[i] - touch_lo[i] > 1)) ++clashes;
    INFO(taken << " vertices the strips may move, " << left << " left to the serial pass");
    CHECK(clashes == 0);
    CHECK(taken > 0);  // not an empty check ...
    CHECK(left > 0);
    if (strips == CleanupOptions::kSmallStrips) CHECK(taken > 4 * left);  // ... and wide strips take most
  }
}
