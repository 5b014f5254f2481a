// Triangulation tests: Delaunay against brute force, degenerate inputs, boundary recovery,
// hole removal and typed errors; every mesh is re-checked by check_mesh.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <set>

#include "core/errors.hpp"
#include "core/predicates.hpp"
#include "mesh/constrain.hpp"
#include "mesh/delaunay.hpp"
#include "geometry/hilbert.hpp"
#include "mesh/mesh_check.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "seeded_random.hpp"

using namespace pdmesh;

namespace {

constexpr double kPi = 3.14159265358979323846;

using pdmesh_test::unit;

// Hilbert index by the textbook algorithm (rotating the coordinates), as an oracle.
std::uint32_t reference_hilbert(std::uint32_t x, std::uint32_t y) {
  const std::uint32_t n = 1u << 16;
  std::uint32_t d = 0;
  for (std::uint32_t s = n / 2; s > 0; s /= 2) {
    const std::uint32_t rx = (x & s) > 0, ry = (y & s) > 0;
    d += s * s * ((3 * rx) ^ ry);
    if (ry == 0) {
      if (rx == 1) {
        x = n - 1 - x;
        y = n - 1 - y;
      }
      std::swap(x, y);
    }
  }
  return d;
}

// Every triangle counter-clockwise and no input point strictly inside any circumcircle.
void require_delaunay_brute_force(const std::vector<Vec2>& pts, const std::vector<std::array<int, 3>>& tris) {
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const auto& tv = tris[t];
    REQUIRE(orient2d(pts[tv[0]], pts[tv[1]], pts[tv[2]]) > 0);
    for (std::size_t k = 0; k < pts.size(); ++k) {
      INFO("triangle " << t << " point " << k);
      REQUIRE(incircle(pts[tv[0]], pts[tv[1]], pts[tv[2]], pts[k]) <= 0);
    }
  }
}

double polygon_area(const std::vector<Vec2>& pts, const std::vector<int>& loop) {
  double area = 0;
  for (std::size_t k = 0; k + 1 < loop.size(); ++k) area += 0.5 * cross(pts[loop[k]], pts[loop[k + 1]]);
  return area;
}

// Adds a closed polygon loop as one curve (first node repeated at the end).
std::vector<int> add_loop(NodeSet& nodes, const std::vector<Vec2>& corners, int curve) {
  std::vector<int> loop;
  for (const Vec2& p : corners) loop.push_back(nodes.add(p, 0.1, NodeKind::Boundary, curve));
  loop.push_back(loop.front());
  nodes.curve_nodes.push_back(loop);
  return loop;
}

// The boundary of the axis-aligned square [lo, hi]^2 with `per_side` segments per side,
// counter-clockwise (reverse = clockwise, for holes: parity does not care, but test both).
std::vector<Vec2> square_loop(double lo, double hi, int per_side, bool reverse) {
  std::vector<Vec2> out;
  const double h = (hi - lo) / per_side;
  for (int k = 0; k < per_side; ++k) out.push_back({lo + k * h, lo});
  for (int k = 0; k < per_side; ++k) out.push_back({hi, lo + k * h});
  for (int k = 0; k < per_side; ++k) out.push_back({hi - k * h, hi});
  for (int k = 0; k < per_side; ++k) out.push_back({lo, hi - k * h});
  if (reverse) std::reverse(out.begin(), out.end());
  return out;
}

std::vector<Vec2> circle_loop(double r, int count) {
  std::vector<Vec2> out;
  for (int k = 0; k < count; ++k) out.push_back({r * std::cos(2 * kPi * k / count), r * std::sin(2 * kPi * k / count)});
  return out;
}

}  // namespace

TEST_CASE("hilbert_key matches the textbook algorithm, and hilbert_order is a permutation", "[mesh]") {
  std::mt19937_64 rng(3);
  for (int i = 0; i < 20000; ++i) {
    const auto x = static_cast<std::uint32_t>(rng() & 0xffff), y = static_cast<std::uint32_t>(rng() & 0xffff);
    REQUIRE(hilbert_key(x, y) == reference_hilbert(x, y));
  }
  std::vector<Vec2> pts;
  for (int k = 0; k < 1001; ++k) pts.push_back({unit(rng), unit(rng)});
  auto order = hilbert_order(pts);
  std::sort(order.begin(), order.end());
  std::vector<int> identity(pts.size());
  std::iota(identity.begin(), identity.end(), 0);
  CHECK(order == identity);
}

TEST_CASE("random points: Delaunay by brute force", "[mesh]") {
  for (int n : {3, 4, 7, 93, 400}) {
    std::mt19937_64 rng(42 + n);
    std::vector<Vec2> pts;
    for (int k = 0; k < n; ++k) pts.push_back({unit(rng), unit(rng)});
    const auto tris = delaunay_triangles(pts);
    INFO("n = " << n);
    REQUIRE(tris.size() >= static_cast<std::size_t>(n) - 2);
    REQUIRE(tris.size() <= 2 * static_cast<std::size_t>(n) - 5);
    require_delaunay_brute_force(pts, tris);
  }
}

TEST_CASE("a triangulation just built is already Delaunay: the Lawson pass flips nothing", "[mesh]") {
  // recover_edges skips the pass when no boundary edge needed a flip; that is exact only if the
  // incremental insertion leaves no edge the pass would flip, degenerate inputs included.
  std::vector<std::vector<Vec2>> sets;
  for (int n : {3, 50, 2000, 20000}) {
    std::mt19937_64 rng(11 + n);
    std::vector<Vec2> pts;
    for (int k = 0; k < n; ++k) pts.push_back({unit(rng), unit(rng)});
    sets.push_back(pts);
  }
  std::vector<Vec2> grid, hex;  // every cell cocircular; a triangular lattice with sixfold ties
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 60; ++j) {
      grid.push_back({0.5 * i, 0.5 * j});
      hex.push_back({i + 0.5 * (j % 2), 0.8660254037844386 * j});
    }
  sets.push_back(grid);
  sets.push_back(hex);
  for (std::size_t k = 0; k < sets.size(); ++k) {
    INFO("set " << k);
    Triangulation tri(sets[k]);
    CHECK(tri.make_delaunay() == 0);
  }
  // constrain / is_constrained: either direction of a marked edge, not an edge between a marked vertex
  // and another (the per-vertex flags only short-cut the hash lookup).
  NodeSet nodes;
  std::vector<Vec2> loop = {{0, 0}, {10, 0}, {10, 0.02}, {0, 0.02}};
  add_loop(nodes, loop, 0);
  for (int k = 1; k < 40; ++k) nodes.add({0.25 * k, 0.001}, 0.1, NodeKind::Interior, -1);
  Triangulation strip(nodes.x);
  REQUIRE(strip.find_edge(strip.vertex_of[0], strip.vertex_of[1])[0] < 0);
  strip.constrain(strip.vertex_of[0], strip.vertex_of[1]);
  CHECK(strip.is_constrained(strip.vertex_of[1], strip.vertex_of[0]));
  CHECK_FALSE(strip.is_constrained(strip.vertex_of[1], strip.vertex_of[2]));
}

TEST_CASE("random points in a square domain: checker passes, area is 1", "[mesh]") {
  for (int n : {1, 17, 1000}) {
    NodeSet nodes;
    add_loop(nodes, square_loop(0, 1, 11, false), 0);
    std::mt19937_64 rng(7 + n);
    for (int k = 0; k < n; ++k)
      nodes.add({0.01 + 0.98 * unit(rng), 0.01 + 0.98 * unit(rng)}, 0.1, NodeKind::Interior, -1);
    const Mesh mesh = triangulate(nodes, {"square"});
    const auto report = check_mesh(mesh, 1.0);
    INFO(report.summary());
    REQUIRE(report.ok());
    // Euler for a disk: T = 2V - 2 - B with B boundary nodes.
    CHECK(mesh.triangles.size() == 2 * nodes.size() - 2 - 44);
    CHECK(mesh.kind == nodes.kind);
    CHECK(mesh.boundary_edges.size() == 44);
  }
}

TEST_CASE("grid points (all cocircular quadruples) give a valid mesh", "[mesh]") {
  const int m = 21;  // 20 x 20 cells
  NodeSet nodes;
  std::vector<Vec2> pts;
  add_loop(nodes, square_loop(0, 2, m - 1, false), 0);
  for (int i = 1; i < m - 1; ++i)
    for (int j = 1; j < m - 1; ++j) nodes.add({2.0 * i / (m - 1), 2.0 * j / (m - 1)}, 0.1, NodeKind::Interior, -1);
  const Mesh mesh = triangulate(nodes, {"box"});
  const auto report = check_mesh(mesh, 4.0);
  INFO(report.summary());
  REQUIRE(report.ok());
  CHECK(mesh.triangles.size() == 2u * (m - 1) * (m - 1));
  // Unconstrained too: every triangle of the plain Delaunay triangulation is a half grid cell.
  std::vector<Vec2> grid;
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j) grid.push_back({0.1 * i, 0.1 * j});
  require_delaunay_brute_force(grid, delaunay_triangles(grid));
}

TEST_CASE("points on a circle: polygon triangulated, area is the polygon's", "[mesh]") {
  for (int count : {3, 5, 64, 257}) {
    NodeSet nodes;
    const auto loop = add_loop(nodes, circle_loop(3.0, count), 0);
    const Mesh mesh = triangulate(nodes, {"circle"});
    const auto report = check_mesh(mesh, polygon_area(nodes.x, loop));
    INFO("count " << count << "\n" << report.summary());
    REQUIRE(report.ok());
    CHECK(mesh.triangles.size() == static_cast<std::size_t>(count) - 2);
  }
}

TEST_CASE("degenerate input: collinear, duplicates, too few points, NaN", "[mesh]") {
  std::vector<Vec2> line;
  for (int k = 0; k < 10; ++k) line.push_back({0.5 * k, 1.5 * k});  // exactly collinear
  CHECK_THROWS_AS(delaunay_triangles(line), GeometryError);
  CHECK_THROWS_WITH(delaunay_triangles(line), Catch::Contains("collinear"));
  // 0.1 k and 0.3 k round differently: not exactly collinear, so no error.
  std::vector<Vec2> almost_line;
  for (int k = 0; k < 10; ++k) almost_line.push_back({0.1 * k, 0.3 * k});
  CHECK_NOTHROW(Triangulation(almost_line));
  std::vector<Vec2> dup = {{0, 0}, {1, 0}, {0.5, 0.25}, {0, 1}, {1, 0}};
  CHECK_THROWS_WITH(delaunay_triangles(dup), Catch::Contains("points 1 and 4") && Catch::Contains("(1, 0)"));
  CHECK_THROWS_AS(delaunay_triangles(dup), InputError);
  CHECK_THROWS_AS(delaunay_triangles({{0, 0}, {1, 1}}), InputError);
  CHECK_THROWS_AS(delaunay_triangles({{0, 0}, {0, 0}, {0, 0}}), InputError);
  CHECK_THROWS_AS(delaunay_triangles({{0, 0}, {1, 0}, {0, std::nan("")}}), InputError);
}

TEST_CASE("square with a square hole: hole removed, area right", "[mesh]") {
  for (bool reverse_hole : {false, true}) {
    NodeSet nodes;
    add_loop(nodes, square_loop(0, 1, 10, false), 0);
    add_loop(nodes, square_loop(0.4, 0.6, 2, reverse_hole), 1);
    std::mt19937_64 rng(17);
    for (int k = 0; k < 300; ++k) {
      const Vec2 p{0.02 + 0.96 * unit(rng), 0.02 + 0.96 * unit(rng)};
      if (p.x > 0.38 && p.x < 0.62 && p.y > 0.38 && p.y < 0.62) continue;
      nodes.add(p, 0.1, NodeKind::Interior, -1);
    }
    const Mesh mesh = triangulate(nodes, {"outer", "hole"});
    const auto report = check_mesh(mesh, 1.0 - 0.04);
    INFO(report.summary());
    REQUIRE(report.ok());
    for (const auto& t : mesh.triangles) {
      const Vec2 c = (1.0 / 3.0) * (mesh.points[t[0]] + mesh.points[t[1]] + mesh.points[t[2]]);
      REQUIRE_FALSE((c.x > 0.4 && c.x < 0.6 && c.y > 0.4 && c.y < 0.6));
    }
    for (const auto& e : mesh.boundary_edges) CHECK(e.curve == (nodes.curve[e.a] == 0 ? 0 : 1));
  }
}

TEST_CASE("triangulate in two halves: triangulate_triangles then mesh_of_triangles is triangulate", "[mesh]") {
  // A square with a square inner loop, as a hole and as a closed embedded constraint (a subdomain).
  for (bool constraint : {false, true}) {
    NodeSet nodes;
    add_loop(nodes, square_loop(0, 1, 10, false), 0);
    add_loop(nodes, square_loop(0.4, 0.6, 2, false), 1);
    if (constraint) nodes.constraint_curves = {0, 1};
    std::mt19937_64 rng(29);
    for (int k = 0; k < 300; ++k)
      nodes.add({0.02 + 0.96 * unit(rng), 0.02 + 0.96 * unit(rng)}, 0.1, NodeKind::Interior, -1);
    const std::vector<std::string> names = {"outer", "inner"};
    const Mesh whole = triangulate(nodes, names);
    const Mesh halves = mesh_of_triangles(nodes, names, triangulate_triangles(nodes, names));
    CHECK(halves.triangles == whole.triangles);
    CHECK(halves.points == whole.points);
    CHECK(halves.kind == whole.kind);
    CHECK(halves.curve_names == whole.curve_names);
    CHECK(halves.constraint_curves == whole.constraint_curves);
    CHECK(halves.constraint_curves.empty() == !constraint);
    REQUIRE(halves.boundary_edges.size() == whole.boundary_edges.size());
    for (std::size_t k = 0; k < whole.boundary_edges.size(); ++k) {
      CHECK(halves.boundary_edges[k].a == whole.boundary_edges[k].a);
      CHECK(halves.boundary_edges[k].b == whole.boundary_edges[k].b);
      CHECK(halves.boundary_edges[k].curve == whole.boundary_edges[k].curve);
    }
  }
  // The same errors: a curve name count that does not match.
  NodeSet nodes;
  add_loop(nodes, square_loop(0, 1, 4, false), 0);
  CHECK_THROWS_AS(triangulate_triangles(nodes, {}), InputError);
}

namespace {

// A list of triangles as a set: each rotated to start at its smallest index, sorted.
std::vector<std::array<int, 3>> triangle_set(std::vector<std::array<int, 3>> tris) {
  for (auto& t : tris) std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  std::sort(tris.begin(), tris.end());
  return tris;
}

}  // namespace

TEST_CASE("add_points: a prefix's triangulation with the rest inserted is the construction's triangles", "[mesh]") {
  // Random points in a square whose corners come first (the box of every prefix).
  std::mt19937_64 rng(17);
  std::vector<Vec2> pts = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int k = 0; k < 3000; ++k) pts.push_back({unit(rng), unit(rng)});
  const std::vector<std::array<int, 3>> whole = triangle_set(Triangulation(pts).inner_triangles());
  for (std::size_t held : {std::size_t{4}, std::size_t{2900}, std::size_t{3004}}) {
    INFO("held " << held);
    Triangulation tri(std::vector<Vec2>(pts.begin(), pts.begin() + static_cast<std::ptrdiff_t>(held)));
    REQUIRE(tri.add_points(pts));
    CHECK(tri.input_count == static_cast<int>(pts.size()));
    CHECK(tri.unique_inner_triangles());
    CHECK(tri.make_delaunay() == 0);
    CHECK(triangle_set(tri.inner_triangles()) == whole);
    for (std::size_t i = 0; i < pts.size(); ++i)
      CHECK(tri.input_index[static_cast<std::size_t>(tri.vertex_of[i])] == static_cast<int>(i));
  }
  // A new point outside the held points' box would change the super-triangle: refused, nothing changed.
  Triangulation tri(std::vector<Vec2>(pts.begin(), pts.begin() + 100));
  const auto before = tri.inner_triangles();
  std::vector<Vec2> outside(pts.begin(), pts.begin() + 100);
  outside.push_back({0.5, 1.0 + 1e-9});
  CHECK_FALSE(tri.add_points(outside));
  CHECK(tri.inner_triangles() == before);
  CHECK(tri.input_count == 100);
  outside.back() = {0.5, std::nan("")};
  CHECK_FALSE(tri.add_points(outside));
  // A new point on a held one.
  std::vector<Vec2> twice(pts.begin(), pts.begin() + 100);
  twice.push_back(pts[50]);
  CHECK_THROWS_AS(tri.add_points(twice), InputError);
  // A grid's cells are cocircular: its Delaunay triangulations differ inside; random points (whose box
  // corners tie with two super vertices) have one inside.
  std::vector<Vec2> grid;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) grid.push_back({0.5 * i, 0.5 * j});
  CHECK_FALSE(Triangulation(grid).unique_inner_triangles());
  CHECK(Triangulation(pts).unique_inner_triangles());
}

TEST_CASE("triangulate_triangles_from: the set triangulate_triangles makes, or nothing", "[mesh]") {
  // Boundary nodes close enough that every boundary edge is a Delaunay edge (no interior node within
  // its diametral circle): no recovery flip.
  NodeSet nodes;
  // (Not an empty hole's square: its cocircular nodes would tie inside it.)
  add_loop(nodes, square_loop(0, 1, 40, false), 0);
  add_loop(nodes, {{0.4, 0.4}, {0.61, 0.41}, {0.6, 0.6}, {0.41, 0.58}}, 1);
  nodes.constraint_curves = {0, 1};
  std::mt19937_64 rng(31);
  const auto interior = [&] { return Vec2{0.02 + 0.96 * unit(rng), 0.02 + 0.96 * unit(rng)}; };
  for (int k = 0; k < 400; ++k) {
    const Vec2 p = interior();
    if (!(p.x > 0.3 && p.x < 0.7 && p.y > 0.3 && p.y < 0.7)) nodes.add(p, 0.1, NodeKind::Interior, -1);
  }
  const std::vector<std::string> names = {"outer", "inner"};
  const std::vector<Vec2> before = nodes.x;
  for (int k = 0; k < 30; ++k) {
    const Vec2 p = interior();
    if (!(p.x > 0.3 && p.x < 0.7 && p.y > 0.3 && p.y < 0.7)) nodes.add(p, 0.1, NodeKind::Interior, -1);
  }
  const auto scratch = triangle_set(triangulate_triangles(nodes, names));
  const auto made = triangulate_triangles_from(Triangulation(before), nodes, names);
  REQUIRE(made);
  CHECK(triangle_set(*made) == scratch);
  // A constrained edge that is no Delaunay edge (a node near its middle on either side): recovered by
  // flips from either triangulation, the same constrained triangles.
  {
    NodeSet near = nodes;
    const std::vector<Vec2> near_before = near.x;
    near.add({0.505, 0.402}, 0.1, NodeKind::Interior, -1);  // either side of (0.4, 0.4)-(0.61, 0.41)
    near.add({0.505, 0.408}, 0.1, NodeKind::Interior, -1);
    const auto from = triangulate_triangles_from(Triangulation(near_before), near, names);
    REQUIRE(from);
    CHECK(triangle_set(*from) == triangle_set(triangulate_triangles(near, names)));
    Triangulation plain(near.x);
    REQUIRE(plain.find_edge(plain.vertex_of[160], plain.vertex_of[161])[0] < 0);
    REQUIRE(plain.find_edge(plain.vertex_of[161], plain.vertex_of[160])[0] < 0);
  }
  // Nothing appended: the same.
  const auto same = triangulate_triangles_from(Triangulation(nodes.x), nodes, names);
  REQUIRE(same);
  CHECK(triangle_set(*same) == scratch);
  // A held node that moved since (one ulp), or a prefix that is not the nodes': nothing.
  std::vector<Vec2> moved = before;
  moved[200].x = std::nextafter(moved[200].x, 2.0);
  CHECK_FALSE(triangulate_triangles_from(Triangulation(moved), nodes, names));
  std::vector<Vec2> other(before.rbegin(), before.rend());
  CHECK_FALSE(triangulate_triangles_from(Triangulation(other), nodes, names));
  // Cocircular nodes (a grid): two Delaunay triangulations, so nothing.
  NodeSet grid;
  add_loop(grid, square_loop(0, 1, 10, false), 0);
  for (int i = 1; i < 10; ++i)
    for (int j = 1; j < 10; ++j) grid.add({0.1 * i, 0.1 * j}, 0.1, NodeKind::Interior, -1);
  const std::vector<Vec2> grid_before = grid.x;
  grid.add({0.55, 0.55}, 0.1, NodeKind::Interior, -1);
  CHECK_FALSE(triangulate_triangles_from(Triangulation(grid_before), grid, {"outer"}));
}

TEST_CASE("circle in a circle: annulus area, boundary edges present", "[mesh]") {
  NodeSet nodes;
  const auto outer = add_loop(nodes, circle_loop(1.0, 96), 0);
  const auto inner = add_loop(nodes, circle_loop(0.5, 48), 1);
  std::mt19937_64 rng(23);
  while (nodes.size() < 600) {
    const Vec2 p{2 * unit(rng) - 1, 2 * unit(rng) - 1};
    if (norm(p) > 0.55 && norm(p) < 0.95) nodes.add(p, 0.1, NodeKind::Interior, -1);
  }
  const Mesh mesh = triangulate(nodes, {"outer", "inner"});
  const auto report = check_mesh(mesh, polygon_area(nodes.x, outer) - polygon_area(nodes.x, inner));
  INFO(report.summary());
  REQUIRE(report.ok());
  CHECK(mesh.boundary_edges.size() == 96 + 48);
}

TEST_CASE("thin domain: non-Delaunay boundary edges are recovered", "[mesh]") {
  // A 10 x 0.02 strip with staggered nodes on the long sides: the long bottom and top edges
  // between far-apart nodes are not in the Delaunay triangulation of the points.
  NodeSet nodes;
  std::vector<Vec2> loop = {{0, 0}, {10, 0}, {10, 0.02}};
  for (int k = 1; k < 40; ++k) loop.push_back({10 - 0.25 * k - 0.01, 0.02});
  loop.push_back({0, 0.02});
  add_loop(nodes, loop, 0);
  // Interior nodes just above the bottom edge make its Delaunay circle non-empty.
  for (int k = 1; k < 40; ++k) nodes.add({0.25 * k, 0.001}, 0.1, NodeKind::Interior, -1);
  Triangulation raw(nodes.x);
  CHECK(raw.find_edge(raw.vertex_of[0], raw.vertex_of[1])[0] < 0);
  CHECK(raw.find_edge(raw.vertex_of[1], raw.vertex_of[0])[0] < 0);
  const Mesh mesh = triangulate(nodes, {"strip"});
  const auto report = check_mesh(mesh, 10 * 0.02);
  INFO(report.summary());
  REQUIRE(report.ok());
}

TEST_CASE("boundary errors: point inside a boundary edge, crossing edges, zero length", "[mesh]") {
  {
    NodeSet nodes;
    add_loop(nodes, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 0);
    nodes.add({0.5, 0.0}, 0.1, NodeKind::Interior, -1);  // exactly on edge 0-1
    nodes.add({0.5, 0.5}, 0.1, NodeKind::Interior, -1);
    CHECK_THROWS_AS(triangulate(nodes, {"box"}), GeometryError);
    CHECK_THROWS_WITH(triangulate(nodes, {"box"}), Catch::Contains("point 4 (0.5, 0)"));
  }
  {
    NodeSet nodes;  // a bow tie: edges 0-1 and 2-3 cross
    add_loop(nodes, {{0, 0}, {1, 1}, {1, 0}, {0, 1}}, 0);
    CHECK_THROWS_AS(triangulate(nodes, {"bow tie"}), GeometryError);
  }
  {
    NodeSet nodes;
    add_loop(nodes, {{0, 0}, {1, 0}, {1, 1}}, 0);
    nodes.curve_nodes[0].insert(nodes.curve_nodes[0].begin() + 1, 0);  // 0 -> 0
    CHECK_THROWS_AS(triangulate(nodes, {"box"}), GeometryError);
  }
  {
    NodeSet nodes;
    add_loop(nodes, {{0, 0}, {1, 0}, {1, 1}}, 0);
    CHECK_THROWS_AS(triangulate(nodes, {}), InputError);  // curve name count mismatch
  }
}

TEST_CASE("large random domain mesh passes the checker", "[mesh]") {
  NodeSet nodes;
  add_loop(nodes, circle_loop(1.0, 500), 0);
  std::mt19937_64 rng(1234);
  while (nodes.size() < 30000) {
    const Vec2 p{2 * unit(rng) - 1, 2 * unit(rng) - 1};
    if (norm(p) < 0.99) nodes.add(p, 0.1, NodeKind::Interior, -1);
  }
  const Mesh mesh = triangulate(nodes, {"disk"});
  const auto report = check_mesh(mesh, polygon_area(nodes.x, nodes.curve_nodes[0]));
  INFO(report.summary());
  REQUIRE(report.ok());
  CHECK(mesh.triangles.size() == 2 * nodes.size() - 2 - 500);
}
