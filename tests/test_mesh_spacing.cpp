// Spacing from data (spacing.field = "mesh"): TriangleLocator against a brute-force scan (points on
// edges and vertices included), MeshSpacing's interpolation (linear fields to rounding, vertices, edge
// midpoints, clamping outside and in holes, at_many = at bit for bit), every VTU encoding and both
// MSH versions read to the same field (fixtures written by VTK, meshio and Gmsh), and the checks of
// bad data. The command-line refusals (exit 2, nothing written) are in tests/data/bad/MANIFEST.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <string>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "core/errors.hpp"
#include "core/predicates.hpp"
#include "geometry/geometry_files.hpp"
#include "geometry_fixtures.hpp"
#include "io/msh_writer.hpp"
#include "io/vtu_writer.hpp"
#include "run_pdmesh.hpp"
#include "io/spacing_mesh_file.hpp"
#include "spacing/mesh_spacing.hpp"
#include "temp_files.hpp"
#include "seeded_random.hpp"

using namespace pdmesh;
namespace fs = std::filesystem;

namespace {

const fs::path kFixtures = fs::path(PDMESH_SOURCE_DIR) / "tests/data/spacing";

using pdmesh_test::unit;

double linear(Vec2 p) { return 1.0 + 0.5 * p.x + 0.25 * p.y; }

// An n x n grid of the unit square, two triangles per cell (the diagonal alternating), interior
// points jittered. With `dyadic` the coordinates are multiples of 2^-12, so every edge midpoint is
// exact and lies exactly on its edge.
MeshFieldData grid(int n, std::uint64_t seed, bool dyadic, const std::function<double(Vec2)>& q) {
  std::mt19937_64 rng(seed);
  MeshFieldData d;
  d.file = "grid";
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      Vec2 p{static_cast<double>(i) / (n - 1), static_cast<double>(j) / (n - 1)};
      if (i > 0 && i < n - 1 && j > 0 && j < n - 1) p = p + (0.3 / (n - 1)) * Vec2{unit(rng) - 0.5, unit(rng) - 0.5};
      if (dyadic) p = {std::round(p.x * 4096) / 4096, std::round(p.y * 4096) / 4096};
      d.points.push_back(p);
    }
  }
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n + 1, e = a + n;
      if ((i + j) % 2 == 0) {
        d.triangles.push_back({a, b, c});
        d.triangles.push_back({a, c, e});
      } else {
        d.triangles.push_back({a, b, e});
        d.triangles.push_back({b, c, e});
      }
    }
  }
  for (const Vec2 p : d.points) d.q.push_back(q(p));
  return d;
}

// Every triangle whose closed area holds p, by scanning all of them.
std::vector<int> brute_locate_all(const MeshFieldData& d, Vec2 p) {
  std::vector<int> out;
  for (std::size_t t = 0; t < d.triangles.size(); ++t) {
    const auto& v = d.triangles[t];
    const Vec2 a = d.points[static_cast<std::size_t>(v[0])], b = d.points[static_cast<std::size_t>(v[1])],
               c = d.points[static_cast<std::size_t>(v[2])];
    if (orient2d(b, c, p) >= 0 && orient2d(c, a, p) >= 0 && orient2d(a, b, p) >= 0) out.push_back(static_cast<int>(t));
  }
  return out;
}

int brute_locate(const MeshFieldData& d, Vec2 p) {
  const auto all = brute_locate_all(d, p);
  return all.empty() ? -1 : all.front();
}

// The distance from p to the nearest boundary edge, by scanning all of them.
double brute_boundary_distance(const MeshSpacing& field, Vec2 p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& e : field.locator().boundary_edges()) {
    const Vec2 a = field.data().points[static_cast<std::size_t>(e[0])],
               b = field.data().points[static_cast<std::size_t>(e[1])];
    const double t = std::clamp(dot(p - a, b - a) / norm2(b - a), 0.0, 1.0);
    best = std::min(best, dist(p, a + t * (b - a)));
  }
  return best;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

}  // namespace

TEST_CASE("TriangleLocator agrees with a brute-force scan, on edges and vertices too", "[mesh_spacing]") {
  const MeshFieldData d = grid(24, 11, true, linear);
  const MeshSpacing field(d);
  const TriangleLocator& loc = field.locator();
  std::mt19937_64 rng(5);
  std::vector<Vec2> points;
  for (int i = 0; i < 3000; ++i) points.push_back({1.2 * unit(rng) - 0.1, 1.2 * unit(rng) - 0.1});
  for (const Vec2 p : d.points) points.push_back(p);
  std::size_t on_edges = 0;
  for (const auto& t : d.triangles) {
    for (int k = 0; k < 3; ++k) {
      const Vec2 a = d.points[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])];
      const Vec2 b = d.points[static_cast<std::size_t>(t[static_cast<std::size_t>((k + 1) % 3)])];
      const Vec2 m{0.5 * (a.x + b.x), 0.5 * (a.y + b.y)};
      REQUIRE(orient2d(a, b, m) == 0.0);  // exactly on the edge (dyadic coordinates)
      points.push_back(m);
      ++on_edges;
    }
  }
  std::size_t inside = 0, shared = 0;
  for (const Vec2 p : points) {
    INFO("(" << p.x << ", " << p.y << ")");
    const std::vector<int> want = brute_locate_all(d, p);
    const Located got = loc.locate(p);
    // None: outside. One: that one. Several (p on a shared edge or vertex): one of them, always the same.
    if (want.empty()) {
      REQUIRE(got.triangle == -1);
      continue;
    }
    REQUIRE(std::find(want.begin(), want.end(), got.triangle) != want.end());
    REQUIRE(loc.locate(p).triangle == got.triangle);
    ++inside;
    shared += want.size() > 1;
  }
  CHECK(inside > d.points.size() + on_edges + 2000);  // vertices, midpoints and most random points are inside
  CHECK(shared >= on_edges - 4 * 23);                 // the midpoints of interior edges are in two triangles
  CHECK(loc.stats().boundary_edges == 4u * 23u);
  // Outside: the nearest boundary point is as near as the nearest of all boundary edges.
  for (int i = 0; i < 300; ++i) {
    const Vec2 p{4 * unit(rng) - 1.5, 4 * unit(rng) - 1.5};
    if (loc.locate(p).triangle >= 0) continue;
    CHECK(loc.nearest_boundary(p).distance == brute_boundary_distance(field, p));
  }
}

TEST_CASE("a linear field is reproduced to rounding at random points inside", "[mesh_spacing]") {
  const MeshSpacing field(grid(17, 3, false, linear));
  std::mt19937_64 rng(9);
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec2 p{unit(rng), unit(rng)};
    worst = std::max(worst, std::fabs(field.at(p) - linear(p)) / linear(p));
  }
  INFO("worst relative error " << worst);
  CHECK(worst < 1e-14);
}

TEST_CASE("a piecewise-linear field matches at vertices and edge midpoints", "[mesh_spacing]") {
  std::mt19937_64 rng(21);
  MeshFieldData d = grid(12, 4, true, linear);
  for (double& q : d.q) q = 0.5 + 1.5 * unit(rng);
  const MeshSpacing field(d);
  for (std::size_t i = 0; i < d.points.size(); ++i) CHECK(field.at(d.points[i]) == Approx(d.q[i]).epsilon(1e-15));
  for (const auto& t : d.triangles) {
    for (std::size_t k = 0; k < 3; ++k) {
      const auto a = static_cast<std::size_t>(t[k]), b = static_cast<std::size_t>(t[(k + 1) % 3]);
      const Vec2 m{0.5 * (d.points[a].x + d.points[b].x), 0.5 * (d.points[a].y + d.points[b].y)};
      CHECK(field.at(m) == Approx(0.5 * (d.q[a] + d.q[b])).epsilon(1e-14));
    }
  }
  // Inside a triangle the value is the barycentric mix, never outside the vertices' range.
  for (int i = 0; i < 2000; ++i) {
    const Vec2 p{unit(rng), unit(rng)};
    const auto& t = d.triangles[static_cast<std::size_t>(brute_locate(d, p))];
    const double lo = std::min({d.q[static_cast<std::size_t>(t[0])], d.q[static_cast<std::size_t>(t[1])],
                                d.q[static_cast<std::size_t>(t[2])]});
    const double hi = std::max({d.q[static_cast<std::size_t>(t[0])], d.q[static_cast<std::size_t>(t[1])],
                                d.q[static_cast<std::size_t>(t[2])]});
    const double v = field.at(p);
    CHECK((v >= lo && v <= hi));
  }
}

TEST_CASE("outside the mesh, and in its holes, q is the value at the nearest point of the mesh", "[mesh_spacing]") {
  MeshFieldData d = grid(9, 2, true, linear);
  const MeshSpacing square(d);
  // Beside a side: the value on the side; beyond a corner: the corner's value.
  CHECK(square.at({1.5, 0.3}) == Approx(linear({1.0, 0.3})).epsilon(1e-15));
  CHECK(square.at({0.4, 7.0}) == Approx(linear({0.4, 1.0})).epsilon(1e-15));
  CHECK(square.at({-0.25, 0.5}) == Approx(linear({0.0, 0.5})).epsilon(1e-15));
  CHECK(square.at({-2.0, -3.0}) == linear({0.0, 0.0}));
  CHECK(square.at({1e6, 1e6}) == linear({1.0, 1.0}));
  // A hole: remove the triangles of the 4 central cells (a square hole around (0.5, 0.5)).
  std::vector<std::array<int, 3>> kept;
  for (const auto& t : d.triangles) {
    Vec2 c{0, 0};
    for (int v : t) c = c + (1.0 / 3.0) * d.points[static_cast<std::size_t>(v)];
    if (!(std::fabs(c.x - 0.5) < 0.25 && std::fabs(c.y - 0.5) < 0.25)) kept.push_back(t);
  }
  REQUIRE(kept.size() + 8 <= d.triangles.size());
  d.triangles = kept;
  const MeshSpacing holed(d);
  std::mt19937_64 rng(8);
  int in_hole = 0;
  for (int i = 0; i < 500; ++i) {
    const Vec2 p{0.35 + 0.3 * unit(rng), 0.35 + 0.3 * unit(rng)};
    if (holed.locator().locate(p).triangle >= 0) continue;
    ++in_hole;
    // The hole's boundary is made of grid edges; on them the field is linear, so q is the linear
    // field at the nearest boundary point, which lies at the brute-force distance.
    const BoundaryHit hit = holed.locator().nearest_boundary(p);
    CHECK(hit.distance == brute_boundary_distance(holed, p));
    const auto& e = holed.locator().boundary_edges()[static_cast<std::size_t>(hit.edge)];
    const Vec2 a = d.points[static_cast<std::size_t>(e[0])], b = d.points[static_cast<std::size_t>(e[1])];
    CHECK(holed.at(p) == Approx(linear(a + hit.t * (b - a))).epsilon(1e-14));
  }
  CHECK(in_hole > 100);
}

TEST_CASE("at_many gives what at gives, bit for bit", "[mesh_spacing]") {
  const MeshSpacing field(grid(20, 6, false, [](Vec2 p) { return 0.1 + p.x * p.x + std::sin(3 * p.y) + 1.0; }));
  std::mt19937_64 rng(1);
  std::vector<Vec2> points;
  // A coherent sweep (rows, as the background quadtree samples) then random points in and out.
  for (int j = 0; j <= 60; ++j)
    for (int i = 0; i <= 60; ++i) points.push_back({-0.05 + 1.1 * i / 60.0, -0.05 + 1.1 * j / 60.0});
  for (int i = 0; i < 3000; ++i) points.push_back({1.4 * unit(rng) - 0.2, 1.4 * unit(rng) - 0.2});
  std::vector<double> q;
  field.at_many(points, q);
  REQUIRE(q.size() == points.size());
  for (std::size_t i = 0; i < points.size(); ++i) REQUIRE(q[i] == field.at(points[i]));
}

TEST_CASE("every VTU encoding and both MSH versions read the same field", "[mesh_spacing]") {
  // expected.txt: x y q per point, as make_fixtures.py generated them.
  std::ifstream in(kFixtures / "expected.txt");
  std::vector<std::array<double, 3>> expected;
  for (std::array<double, 3> row; in >> row[0] >> row[1] >> row[2];) expected.push_back(row);
  REQUIRE(expected.size() == 25);
  std::mt19937_64 rng(3);
  std::vector<Vec2> probes;
  for (int i = 0; i < 200; ++i) probes.push_back({1.2 * unit(rng) - 0.1, 1.2 * unit(rng) - 0.1});
  std::vector<double> reference;
  for (const char* name : {"vtk_ascii.vtu", "vtk_default.vtu", "vtk_appended_raw_zlib.vtu", "vtk_appended_raw_u64.vtu",
                           "vtk_binary_zlib.vtu", "vtk_binary_bigendian.vtu", "meshio_binary_zlib.vtu",
                           "gmsh_view_22.msh", "gmsh_view_41.msh"}) {
    INFO(name);
    const auto field = load_mesh_spacing(kFixtures / name, "q");
    const MeshFieldData& d = field->data();
    REQUIRE(d.points.size() == expected.size());
    REQUIRE(d.triangles.size() == 32);
    // Gmsh writes 16 significant digits, VTK and meshio every bit.
    const double tol = std::string(name).find("gmsh") == 0 ? 1e-15 : 0.0;
    for (std::size_t i = 0; i < expected.size(); ++i) {
      CHECK(std::fabs(d.points[i].x - expected[i][0]) <= tol);
      CHECK(std::fabs(d.points[i].y - expected[i][1]) <= tol);
      CHECK(std::fabs(d.q[i] - expected[i][2]) <= tol * expected[i][2]);
    }
    std::vector<double> q;
    field->at_many(probes, q);
    if (reference.empty()) reference = q;
    for (std::size_t i = 0; i < q.size(); ++i) CHECK(q[i] == Approx(reference[i]).epsilon(1e-14));
    // The background mesh covers the unit square exactly: q is the linear field inside it.
    CHECK(field->at({0.3, 0.6}) == Approx(linear({0.3, 0.6})).epsilon(1e-14));
  }
}

TEST_CASE("a written mesh with spacing reads back as the same field", "[mesh_spacing]") {
  const MeshFieldData d = grid(6, 12, false, [](Vec2 p) { return 0.3 + std::exp(p.x - p.y); });
  Mesh mesh;
  mesh.points = d.points;
  mesh.triangles = d.triangles;
  mesh.spacing = d.q;
  const fs::path dir = pdmesh_test::fresh_dir("mesh_spacing_write");
  const std::pair<const char*, std::string> files[] = {{"a.vtu", vtu_string(mesh)},
                                                       {"ascii.vtu", vtu_string(mesh, VtuFormat::Ascii)},
                                                       {"a.msh", msh41_string(mesh)},
                                                       {"b.msh", msh22_string(mesh)}};
  for (const auto& [name, text] : files) {
    INFO(name);
    std::ofstream(dir / name) << text;
    const auto field = load_mesh_spacing(dir / name, "q");
    CHECK(field->data().q == d.q);  // binary, or 17 digits: bit for bit
    CHECK(field->data().points.size() == d.points.size());
  }
  fs::remove_all(dir);
}

TEST_CASE("bad background meshes are refused naming the file and the value", "[mesh_spacing]") {
  const MeshFieldData good = grid(5, 1, true, linear);
  SECTION("no triangles") {
    MeshFieldData d = good;
    d.triangles.clear();
    CHECK_THAT(error_of([&] { MeshSpacing f(d); }), Catch::Contains("grid: the mesh has no triangles"));
  }
  SECTION("non-positive, non-finite and missing values at vertices") {
    MeshFieldData d = good;
    d.q[7] = -0.5;
    CHECK_THAT(error_of([&] { MeshSpacing f(d); }),
               Catch::Contains("'q' is -0.5 at point 7 (") && Catch::Contains("finite positive"));
    d.q[7] = std::numeric_limits<double>::quiet_NaN();
    CHECK_THAT(error_of([&] { MeshSpacing f(d); }), Catch::Contains("'q' is nan at point 7"));
    d.q[7] = std::numeric_limits<double>::infinity();
    CHECK_THAT(error_of([&] { MeshSpacing f(d); }), Catch::Contains("'q' is inf at point 7"));
    d.q[7] = 0.0;
    CHECK_THAT(error_of([&] { MeshSpacing f(d); }), Catch::Contains("'q' is 0 at point 7"));
    d.q[7] = 1.0;
    d.given.assign(d.points.size(), 1);
    d.given[7] = 0;
    d.point_ids.resize(d.points.size());
    for (std::size_t i = 0; i < d.point_ids.size(); ++i) d.point_ids[i] = static_cast<long long>(i) + 100;
    CHECK_THAT(error_of([&] { MeshSpacing f(d); }), Catch::Contains("has no value for node 107"));
    // A bad value at a point that no triangle uses is never interpolated: accepted.
    d.given.clear();
    d.points.push_back({5, 5});
    d.q.push_back(-1);
    d.point_ids.push_back(999);
    CHECK_NOTHROW(MeshSpacing(d));
  }
  SECTION("a triangle of zero area") {
    MeshFieldData d = good;
    d.points.push_back({2, 0});
    d.points.push_back({3, 0});
    d.q.push_back(1);
    d.q.push_back(1);
    d.triangles.push_back({4, 25, 26});  // (1, 0), (2, 0), (3, 0)
    CHECK_THAT(error_of([&] { MeshSpacing f(d); }),
               Catch::Contains("(point 4, point 25, point 26)") && Catch::Contains("has zero area"));
  }
  SECTION("an inverted (folded) triangle, an edge of three triangles, overlapping meshes") {
    MeshFieldData d = good;
    // Move an interior vertex across its neighbours: its triangles fold over the others. The
    // reader would turn a clockwise triangle around, so the data holds it counter-clockwise.
    d.points[6] = {0.6, 0.6};
    for (auto& t : d.triangles)
      if (orient2d(d.points[static_cast<std::size_t>(t[0])], d.points[static_cast<std::size_t>(t[1])],
                   d.points[static_cast<std::size_t>(t[2])]) < 0)
        std::swap(t[1], t[2]);
    CHECK_THAT(error_of([&] { MeshSpacing f(d); }), Catch::Contains("lie on the same side of their shared edge"));
    d = good;
    // Two counter-clockwise triangles below the boundary edge 0-1: with the one above, three use it.
    d.points.push_back({0.125, -0.5});
    d.points.push_back({0.125, -1.0});
    d.q.push_back(1);
    d.q.push_back(1);
    d.triangles.push_back({1, 0, 25});
    d.triangles.push_back({1, 0, 26});
    CHECK_THAT(error_of([&] { MeshSpacing f(d); }), Catch::Contains("belongs to more than two triangles"));
    // Two meshes laid over each other (no shared points): the centroid test finds it.
    d = good;
    const auto n = static_cast<int>(d.points.size());
    for (std::size_t i = 0; i < good.points.size(); ++i) {
      d.points.push_back(good.points[i] + Vec2{0.01, 0.02});
      d.q.push_back(good.q[i]);
    }
    for (const auto& t : good.triangles) d.triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
    CHECK_THAT(error_of([&] { MeshSpacing f(d); }), Catch::Contains("overlap"));
  }
  SECTION("a mesh that does not cover the domain") {
    const MeshSpacing field(good);
    const Geometry inside = fixtures::make_geometry({fixtures::rectangle({0, 0}, {1, 1}, 8, true)});
    CHECK_NOTHROW(field.check_covers(inside));
    const Geometry bigger = fixtures::make_geometry({fixtures::rectangle({0, 0}, {2, 1}, 8, true)});
    CHECK_THAT(error_of([&] { field.check_covers(bigger); }),
               Catch::Contains("grid: the background mesh does not cover the domain: point 5 (1.25, 0) of curve "
                               "'curve0'") &&
                   Catch::Contains("lies 0.25 outside"));
  }
  SECTION("chords that cut the corners of a curved boundary are accepted") {
    // A fan of 16 triangles inside a circle of radius 1; the geometry has 64 points on the circle.
    MeshFieldData d;
    d.file = "fan";
    d.points.push_back({0, 0});
    for (int k = 0; k < 16; ++k) d.points.push_back({std::cos(k * M_PI / 8), std::sin(k * M_PI / 8)});
    for (int k = 0; k < 16; ++k) d.triangles.push_back({0, 1 + k, 1 + (k + 1) % 16});
    d.q.assign(d.points.size(), 0.2);
    const MeshSpacing fan(d);
    std::vector<Vec2> circle;
    for (int k = 0; k <= 64; ++k) circle.push_back({std::cos(k * M_PI / 32), std::sin(k * M_PI / 32)});
    CHECK_NOTHROW(fan.check_covers(fixtures::make_geometry({circle})));
    // The same circle 10% larger is not the same domain.
    for (Vec2& p : circle) p = 1.1 * p;
    CHECK_THAT(error_of([&] { fan.check_covers(fixtures::make_geometry({circle})); }),
               Catch::Contains("does not cover the domain"));
  }
}

TEST_CASE("reading a background mesh: missing arrays are listed, vectors and odd files refused", "[mesh_spacing]") {
  CHECK_THAT(error_of([&] { load_mesh_spacing(kFixtures / "vtk_default.vtu", "h"); }),
             Catch::Contains(
                 "vtk_default.vtu: no point-data array 'h' (spacing.array); its point-data arrays are: q, velocity"));
  CHECK_THAT(error_of([&] { load_mesh_spacing(kFixtures / "vtk_appended_raw_zlib.vtu", "velocity"); }),
             Catch::Contains("vtk_appended_raw_zlib.vtu:") && Catch::Contains("'velocity' has 3 components"));
  CHECK_THAT(error_of([&] { load_mesh_spacing(kFixtures / "gmsh_view_41.msh", "h"); }),
             Catch::Contains("its point-data arrays are: q"));
  CHECK_THAT(error_of([&] { load_mesh_spacing(kFixtures / "no_such_file.vtu", "q"); }),
             Catch::Contains("no_such_file.vtu"));
  CHECK_THAT(error_of([&] { load_mesh_spacing(kFixtures / "expected.txt", "q"); }),
             Catch::Contains("must be a .vtu or .msh file"));
  // A damaged zlib stream and cut base64 data name the file, line and array.
  std::string text = pdmesh_test::slurp(kFixtures / "vtk_binary_zlib.vtu");
  const fs::path dir = pdmesh_test::fresh_dir("mesh_spacing_corrupt");
  const auto q_at = text.find("Name=\"q\"");
  const auto data_at = text.find('>', q_at) + 40;
  std::string corrupt = text;
  corrupt[data_at] = corrupt[data_at] == 'A' ? 'B' : 'A';
  std::ofstream(dir / "corrupt.vtu") << corrupt;
  CHECK_THAT(error_of([&] { load_mesh_spacing(dir / "corrupt.vtu", "q"); }),
             Catch::Contains("corrupt.vtu:") && Catch::Contains("DataArray 'q'"));
  std::string cut = text;
  cut.insert(data_at, "!");
  std::ofstream(dir / "cut.vtu") << cut;
  CHECK_THAT(error_of([&] { load_mesh_spacing(dir / "cut.vtu", "q"); }),
             Catch::Contains("invalid base64 character '!'"));
  fs::remove_all(dir);
}

TEST_CASE("pdmesh mesh runs with a background-mesh field and writes it back as point data", "[mesh_spacing][cli]") {
  // A square of side 1 segmented at 0.1; the background field grades from 0.05 to 0.15 across it.
  const fs::path dir = pdmesh_test::fresh_dir("mesh_spacing_cli");
  {
    std::ofstream crv(dir / "square.crv");
    crv << "41\n";
    for (const Vec2 p : fixtures::rectangle({0, 0}, {1, 1}, 10, true)) crv << p.x << ' ' << p.y << '\n';
  }
  const MeshFieldData d = grid(9, 4, false, [](Vec2 p) { return 0.05 + 0.1 * p.x; });
  Mesh background;
  background.points = d.points;
  background.triangles = d.triangles;
  background.spacing = d.q;
  std::ofstream(dir / "field.vtu") << vtu_string(background);
  std::ofstream(dir / "case.toml") << "[geometry]\nfiles = [\"square.crv\"]\n[spacing]\nfile = \"field.vtu\"\n"
                                      "[simulation]\niterations = 30\n[output]\nformats = [\"vtu\"]\n";
  const fs::path out = dir / "out";
  const auto r = pdmesh_test::run_pdmesh("mesh '" + (dir / "case.toml").string() + "' --out '" + out.string() + "'");
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(r.output.find("spacing: 'q' on ") != std::string::npos);
  // The output's point data q is the run's final field at the nodes, as asked: the background data
  // through the spacing pipeline (its floor lifts q toward the 0.1 segments next to the boundary),
  // not the relax_scale x it the nodes relaxed at.
  const CaseConfig config = load_case_file(dir / "case.toml");
  const MeshInputs inputs(config);
  const SpacingStage spacing(config, inputs, SpacingStage::Build::FieldOnly);
  const SpacingField& field = spacing.asked();
  const auto written = load_mesh_spacing(out / "mesh.vtu", "q");
  const MeshFieldData& w = written->data();
  REQUIRE(w.points.size() > 100);  // about 154 by hexagonal packing
  for (std::size_t i = 0; i < w.points.size(); ++i) REQUIRE(w.q[i] == field.at(w.points[i]));
  // Finer on the left than on the right: more nodes in x < 0.5.
  const auto left = std::count_if(w.points.begin(), w.points.end(), [](Vec2 p) { return p.x < 0.5; });
  CHECK(static_cast<double>(left) > 1.5 * static_cast<double>(w.points.size() - static_cast<std::size_t>(left)));
  fs::remove_all(dir);
}

TEST_CASE("the shock_data example reads as thesis eq. 7.2 and covers its square", "[mesh_spacing]") {
  const CaseConfig c = load_case_file(fs::path(PDMESH_SOURCE_DIR) / "cases/shock_data/case.toml");
  REQUIRE(c.spacing.field == SpacingKind::Mesh);
  const auto field = load_mesh_spacing(c.spacing.file, c.spacing.array);
  const Geometry g = read_geometry({c.geometry.files[0].string()}, c.geometry.curve_names);
  CHECK_NOTHROW(field->check_covers(g));
  std::mt19937_64 rng(4);
  double worst = 0;
  for (int i = 0; i < 5000; ++i) {
    const Vec2 p{200 * unit(rng) - 100, 200 * unit(rng) - 100};
    const double exact = 0.5 + 19.5 * std::pow(std::tanh(p.x / 16), 2);
    worst = std::max(worst, std::fabs(field->at(p) - exact) / exact);
  }
  INFO("worst relative difference from eq. 7.2: " << worst);
  CHECK(worst < 0.05);
}

TEST_CASE("damaged background meshes give InputError or a field, nothing else", "[mesh_spacing]") {
  // A small deterministic fuzz of the binary decoding (tools/check/fuzz.sh runs the real one): random byte
  // changes and truncations of every fixture. Under the sanitizer build this also checks memory.
  const fs::path dir = pdmesh_test::fresh_dir("mesh_spacing_mutants");
  std::mt19937_64 rng(99);
  int refused = 0, read = 0;
  for (const char* name :
       {"vtk_default.vtu", "vtk_appended_raw_zlib.vtu", "vtk_appended_raw_u64.vtu", "vtk_binary_zlib.vtu",
        "vtk_binary_bigendian.vtu", "meshio_binary_zlib.vtu", "gmsh_view_41.msh"}) {
    const std::string original = pdmesh_test::slurp(kFixtures / name);
    const std::string ext = fs::path(name).extension().string();
    for (int m = 0; m < 60; ++m) {
      std::string text = original;
      if (m % 3 == 0) {
        text.resize(rng() % text.size());
      } else {
        for (int k = 0; k < 1 + m % 4; ++k) text[rng() % text.size()] = static_cast<char>(rng() & 0xff);
      }
      const fs::path file = dir / ("m" + ext);
      std::ofstream(file, std::ios::binary | std::ios::trunc) << text;
      INFO(name << " mutant " << m);
      try {
        const auto field = load_mesh_spacing(file, "q");
        CHECK(field->at({0.5, 0.5}) > 0);
        ++read;
      } catch (const InputError&) {
        ++refused;
      }
    }
  }
  CHECK(refused > 100);
  fs::remove_all(dir);
}
