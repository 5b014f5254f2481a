// Tests of `pdmesh smooth` (app/pipeline/smooth_pipeline): a jittered mesh of the unit square is lifted
// above 38 degrees with its node count and its boundary kept, and the refusals (a boundary node off
// the curves, a mesh of another geometry, an inverted or a zero-area triangle) name the file and the
// first offending element, exit 2 and write nothing.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "app/pipeline/smooth_pipeline.hpp"
#include "core/errors.hpp"
#include "error_message.hpp"
#include "geometry/geometry_files.hpp"
#include "io/mesh_formats.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
namespace fs = std::filesystem;
using pdmesh_test::error_message;
using pdmesh_test::run_pdmesh;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The unit square split into n x n cells of two triangles each (counter-clockwise), every interior
// node moved by up to `jitter` cell sizes in x and y (a fixed sequence, so the mesh is the same in
// every run). Point (i, j) is i + (n + 1) j.
Mesh square_mesh(int n, double jitter) {
  Mesh m;
  std::uint64_t state = 12345;
  auto next = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0 * 2.0 - 1.0;  // [-1, 1)
  };
  const double h = 1.0 / n;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      Vec2 p{i * h, j * h};
      if (i > 0 && i < n && j > 0 && j < n) {
        p.x += jitter * h * next();
        p.y += jitter * h * next();
      }
      m.points.push_back(p);
    }
  auto id = [n](int i, int j) { return i + (n + 1) * j; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

double min_angle_deg(const Mesh& m) {
  double best = 180.0;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const Vec2 a = m.points[t[k]], b = m.points[t[(k + 1) % 3]], c = m.points[t[(k + 2) % 3]];
      const Vec2 u = b - a, v = c - a;
      best = std::min(best, std::atan2(std::abs(cross(u, v)), dot(u, v)) * 180.0 / kPi);
    }
  return best;
}

// The largest distance of a node on a boundary edge (an edge of one triangle) to the square's sides.
double boundary_off_square(const Mesh& m) {
  std::vector<std::pair<int, int>> edges;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) edges.emplace_back(std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3]));
  std::sort(edges.begin(), edges.end());
  double worst = 0.0;
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const bool shared = (e > 0 && edges[e - 1] == edges[e]) || (e + 1 < edges.size() && edges[e + 1] == edges[e]);
    if (shared) continue;
    for (const int v : {edges[e].first, edges[e].second}) {
      const Vec2 p = m.points[v];
      worst = std::max(worst, std::min({std::abs(p.x), std::abs(p.y), std::abs(1.0 - p.x), std::abs(1.0 - p.y)}));
    }
  }
  return worst;
}

struct Files {
  fs::path dir, geometry, mesh, out;
};

Files write_case(const std::string& tag, const Mesh& mesh) {
  Files f;
  f.dir = pdmesh_test::fresh_dir("smooth_" + tag);
  f.geometry = f.dir / "square.crv";
  std::ofstream(f.geometry) << "5\n0 0\n1 0\n1 1\n0 1\n0 0\n";
  write_mesh(mesh, f.dir, "input", {"msh"});
  f.mesh = f.dir / "input.msh";
  f.out = f.dir / "out";
  return f;
}

std::string smooth_command(const Files& f) {
  return "smooth '" + f.mesh.string() + "' --geometry '" + f.geometry.string() + "' --out '" + f.out.string() +
         "' -q --formats msh";
}

// The message check_mesh_on_geometry gives `mesh` on the unit square ("" when it passes).
std::string geometry_refusal(const Mesh& mesh) {
  const Files f = write_case("geometry_check", mesh);
  const Geometry g = read_geometry({f.geometry.string()}, {});
  const GeometryTree tree(g);
  return error_message<InputError>([&] { check_mesh_on_geometry(mesh, "input.msh", g, tree); });
}

}  // namespace

TEST_CASE("pdmesh smooth lifts a jittered square mesh above 38 degrees, keeping its count and its boundary") {
  const Mesh input = square_mesh(16, 0.3);
  REQUIRE(min_angle_deg(input) < 20.0);  // the input is poor: the run has something to lift
  const Files f = write_case("jittered", input);
  const auto r = run_pdmesh(smooth_command(f));
  INFO(r.output);
  REQUIRE(r.status == 0);
  const Mesh out = read_mesh(f.out / "mesh.msh");
  CHECK(min_angle_deg(out) >= 38.0);
  const double ratio = static_cast<double>(out.points.size()) / static_cast<double>(input.points.size());
  INFO("nodes: " << input.points.size() << " -> " << out.points.size());
  CHECK(ratio >= 0.95);
  CHECK(ratio <= 1.05);
  CHECK(boundary_off_square(out) <= 1e-12);
}

// The mean aspect ratio R / (2 r) of the mesh's triangles (mesh/quality.cpp's formula).
double mean_aspect_ratio(const Mesh& m) {
  double sum = 0.0;
  for (const auto& t : m.triangles) {
    const Vec2 a = m.points[t[0]], b = m.points[t[1]], c = m.points[t[2]];
    const double la = dist(b, c), lb = dist(c, a), lc = dist(a, b), area = 0.5 * std::abs(cross(b - a, c - a));
    sum += la * lb * lc * 0.5 * (la + lb + lc) / (8.0 * area * area);
  }
  return sum / static_cast<double>(m.triangles.size());
}

TEST_CASE("pdmesh smooth keeps the nodes of a mesh at the target and never makes it worse") {
  // A grid of right triangles moved by up to 3 % of a cell: every angle above 40 degrees (the target
  // of the cleanup), so the run keeps its nodes and only polishes them.
  const Mesh input = square_mesh(12, 0.03);
  REQUIRE(min_angle_deg(input) > 40.0);
  REQUIRE(min_angle_apart_from_sharp_corners(input, 40.0) == Approx(min_angle_deg(input)));
  const Files f = write_case("at_target", input);
  const auto r = run_pdmesh(smooth_command(f));
  INFO(r.output);
  REQUIRE(r.status == 0);
  const Mesh out = read_mesh(f.out / "mesh.msh");
  CHECK(out.points.size() == input.points.size());
  CHECK(out.triangles.size() == input.triangles.size());
  CHECK(min_angle_deg(out) >= min_angle_deg(input) - 1e-9);
  INFO("mean aspect ratio " << mean_aspect_ratio(input) << " -> " << mean_aspect_ratio(out));
  CHECK(mean_aspect_ratio(out) <= mean_aspect_ratio(input) + 1e-12);
  CHECK(boundary_off_square(out) <= 1e-12);
  // Every input node is still there or moved by less than a cell (no node re-placed elsewhere).
  double farthest = 0.0;
  for (const Vec2 p : input.points) {
    double nearest = HUGE_VAL;
    for (const Vec2 q : out.points) nearest = std::min(nearest, dist(p, q));
    farthest = std::max(farthest, nearest);
  }
  CHECK(farthest < 0.5 / 12);
}

TEST_CASE("the smallest angle apart from sharp corners leaves out only a triangle alone at a sharp corner") {
  // A 20-degree wedge of two triangles: the tip's triangle alone at the tip, and its neighbour.
  Mesh m;
  const double a = 20.0 * kPi / 180.0;
  m.points = {{0, 0}, {1, 0}, {std::cos(a), std::sin(a)}, {1.25, 0.3}};
  m.triangles = {{0, 1, 2}, {1, 3, 2}};
  CHECK(min_angle_deg(m) == Approx(20.0));
  // Left out below 40 degrees: the neighbour's smallest angle remains.
  const double rest = min_angle_apart_from_sharp_corners(m, 40.0);
  CHECK(rest > 20.0);
  Mesh second = m;
  second.triangles = {m.triangles[1]};
  CHECK(rest == Approx(std::min(80.0, min_angle_deg(second))));
  // Below 15 degrees the tip counts.
  CHECK(min_angle_apart_from_sharp_corners(m, 15.0) == Approx(20.0));
}

TEST_CASE("the mesh's own spacing: its boundary edges on the boundary, its node density inside") {
  const Mesh m = square_mesh(4, 0.0);
  const std::vector<double> q = node_spacing(m);
  REQUIRE(q.size() == m.points.size());
  // Boundary nodes (0, 0) and (1, 0): the mean of their two boundary edges of 1/4 (not the diagonal).
  CHECK(q[0] == Approx(0.25));
  CHECK(q[1] == Approx(0.25));
  // Node (1, 1): six triangles of area 1/32, a third of each its own: A = 1/16, the edge of an
  // equilateral mesh of that density sqrt(2 A / sqrt(3)), not the mean of its edges (1.14 / 4).
  CHECK(q[6] == Approx(std::sqrt(2.0 / 16.0 / std::sqrt(3.0))));
}

TEST_CASE("smooth refuses a boundary node off the curves, naming the node, its position and distance") {
  Mesh m = square_mesh(8, 0.0);
  m.points[3].y = -0.05;  // node (3, 0) on the bottom side, moved 0.4 of its edges off it
  const std::string message = geometry_refusal(m);
  CHECK_THAT(message, Catch::Contains("input.msh: boundary node 3 (0.375, -0.05) lies 0.05 from"));
  CHECK(geometry_refusal(square_mesh(8, 0.0)).empty());
}

TEST_CASE("smooth refuses a mesh of another geometry") {
  Mesh shifted = square_mesh(8, 0.0);
  for (Vec2& p : shifted.points) p = p + Vec2{5.0, 5.0};
  CHECK_THAT(geometry_refusal(shifted), Catch::Contains("does not overlap the geometry"));
  Mesh smaller = square_mesh(8, 0.0);
  for (Vec2& p : smaller.points) p = p * 0.5 + Vec2{0.25, 0.25};
  CHECK_THAT(geometry_refusal(smaller), Catch::Contains("input.msh: boundary node 0 (0.25, 0.25) lies 0.25"));
  // A mesh of the square's left half: its nodes on the cut x = 0.5 lie inside, the first above the
  // bottom side (node 17) an edge from it.
  Mesh half = square_mesh(8, 0.0);
  for (Vec2& p : half.points) p.x *= 0.5;
  CHECK_THAT(geometry_refusal(half), Catch::Contains("boundary node 17 (0.5, 0.125) lies 0.125 from"));
}

TEST_CASE("smooth refuses inverted and zero-area triangles, naming the first with its nodes") {
  Mesh inverted = square_mesh(4, 0.0);
  std::swap(inverted.triangles[5][1], inverted.triangles[5][2]);
  std::swap(inverted.triangles[9][1], inverted.triangles[9][2]);
  CHECK_THAT(error_message<InputError>([&] { check_smooth_mesh(inverted, "in.msh"); }),
             Catch::Contains("in.msh: triangle 5 (nodes 2 (0.5, 0), 8 (0.75, 0.25), 7 (0.5, 0.25)) is inverted"));
  // All clockwise is an orientation, not an inversion.
  Mesh clockwise = square_mesh(4, 0.0);
  for (auto& t : clockwise.triangles) std::swap(t[1], t[2]);
  CHECK(error_message<InputError>([&] { check_smooth_mesh(clockwise, "in.msh"); }).empty());
  // Node (1, 1) moved to the midpoint of nodes 1 (1, 0) and 7 (2, 1): triangle 3 (1, 7, 6) is flat, the
  // other triangles at node 6 keep their orientation.
  Mesh flat = square_mesh(4, 0.0);
  flat.points[6] = {0.375, 0.125};
  CHECK_THAT(error_message<InputError>([&] { check_smooth_mesh(flat, "in.msh"); }),
             Catch::Contains("in.msh: triangle 3 (nodes 1 (0.25, 0), 7 (0.5, 0.25), 6 (0.375, 0.125)) has zero area"));
}

TEST_CASE("pdmesh smooth: a refused mesh exits 2 naming the file and writes nothing") {
  Mesh inverted = square_mesh(8, 0.0);
  std::swap(inverted.triangles[7][1], inverted.triangles[7][2]);
  // write_mesh writes what it is given; the reader turns the triangle back and the check names it.
  const Files a = write_case("inverted", inverted);
  auto r = run_pdmesh(smooth_command(a));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Catch::Contains(a.mesh.string() + ": triangle 7"));
  CHECK_THAT(r.output, Catch::Contains("is inverted"));
  CHECK(!fs::exists(a.out));

  Mesh off = square_mesh(8, 0.0);
  off.points[3].y = -0.05;
  const Files b = write_case("off", off);
  r = run_pdmesh(smooth_command(b));
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Catch::Contains(b.mesh.string() + ": boundary node 3"));
  CHECK(!fs::exists(b.out));
}

TEST_CASE("pdmesh mesh --start is init.file") {
  const Files f = write_case("start", square_mesh(8, 0.2));
  const auto r = run_pdmesh("mesh '" + f.geometry.string() + "' --start '" + (f.dir / "missing.msh").string() +
                            "' --out '" + f.out.string() + "' -q");
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Catch::Contains("missing.msh"));
  CHECK(!fs::exists(f.out));
  const auto ok = run_pdmesh("mesh '" + f.geometry.string() + "' --start '" + f.mesh.string() + "' --out '" +
                             f.out.string() + "' -q --formats msh");
  INFO(ok.output);
  CHECK(ok.status == 0);
  CHECK(fs::exists(f.out / "mesh.msh"));
}
