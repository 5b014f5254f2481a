// `pdmesh adapt` (app/cli/adapt_command): the mesh follows a solution's layer and the solution is
// carried onto it; the command is pdmesh mesh on the case with field = "hessian", bit for bit; several
// arrays are intersected before one scale to the complexity (intersected_hessian_metrics_on_mesh) and
// the mesh refines each array's layer; bad inputs are refused naming the option, with nothing written.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "error_message.hpp"
#include "io/mesh_formats.hpp"
#include "io/mixed_mesh.hpp"
#include "io/vtu_reader.hpp"
#include "io/vtu_writer.hpp"
#include "mesh_measures.hpp"
#include "run_pdmesh.hpp"
#include "spacing/hessian.hpp"
#include "spacing/hessian_metric.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

const std::string kSquare = std::string(PDMESH_SOURCE_DIR) + "/tests/data/geometry/unit_square.crv";

// The curve of the layer, y = 0.5 + 0.25 sin 2 pi x, and u = tanh(k (y - curve)).
double curve(double x) { return 0.5 + 0.25 * std::sin(2.0 * M_PI * x); }
double layer_u(Vec2 p, double k) { return std::tanh(k * (p.y - curve(p.x))); }
// A second array in other units: 100 tanh(k (x - 0.7)), a layer across x = 0.7.
double across_v(Vec2 p, double k) { return 100.0 * std::tanh(k * (p.x - 0.7)); }

// An n x n grid of the unit square as a layered mesh's file holds it: the rows below y = `quads_below`
// quadrilaterals (the layer), the rest two triangles per cell.
MixedMesh mixed_grid(int n, double quads_below) {
  MixedMesh m;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) m.points.push_back({i / (n - 1.0), j / (n - 1.0)});
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i;
      if ((j + 1) / (n - 1.0) <= quads_below) {
        m.cells.push_back({a, a + 1, a + n + 1, a + n});
        m.layer.push_back(1);
      } else {
        m.cells.push_back({a, a + 1, a + n + 1, -1});
        m.cells.push_back({a, a + n + 1, a + n, -1});
        m.layer.insert(m.layer.end(), {0, 0});
      }
    }
  return m;
}

// An n x n grid of points on the unit square, two triangles per cell.
Mesh unit_grid(int n) { return triangulated(mixed_grid(n, -1.0)); }

std::vector<double> values_at(const std::vector<Vec2>& points, const std::function<double(Vec2)>& f) {
  std::vector<double> out;
  for (const Vec2 p : points) out.push_back(f(p));
  return out;
}

// The solution file: u (the curved layer) and v (the straight one) on an 81 x 81 grid, k = 20.
fs::path write_solution(const fs::path& dir) {
  Mesh m = unit_grid(81);
  m.point_data.push_back({"u", 1, values_at(m.points, [](Vec2 p) { return layer_u(p, 20.0); }), false});
  m.point_data.push_back({"v", 1, values_at(m.points, [](Vec2 p) { return across_v(p, 20.0); }), false});
  const fs::path path = dir / "sol.vtu";
  write_file_atomically(path, vtu_string(m));
  return path;
}

// Points per unit area where `in` holds, the area measured on a 400 x 400 grid of cell centres.
double density(const std::vector<Vec2>& points, const std::function<bool(Vec2)>& in) {
  std::size_t count = 0, cells = 0;
  for (const Vec2 p : points) count += in(p) ? 1 : 0;
  for (int j = 0; j < 400; ++j)
    for (int i = 0; i < 400; ++i) cells += in({(i + 0.5) / 400.0, (j + 0.5) / 400.0}) ? 1 : 0;
  REQUIRE(cells > 0);
  return static_cast<double>(count) / (cells / 160000.0);
}

// The node density near the layer's curve (within 0.02 of it, vertically) and far from it (beyond
// 0.15), where `where` holds.
struct AroundCurve {
  double near = 0.0, far = 0.0;
};
AroundCurve around_curve(
    const Mesh& mesh, const std::function<bool(Vec2)>& where = [](Vec2) { return true; }) {
  return {density(mesh.points, [&](Vec2 p) { return where(p) && std::fabs(p.y - curve(p.x)) < 0.02; }),
          density(mesh.points, [&](Vec2 p) { return where(p) && std::fabs(p.y - curve(p.x)) > 0.15; })};
}

// mixed_grid with point data `name` = f.
MixedMesh mixed_grid(int n, double quads_below, const std::string& name, const std::function<double(Vec2)>& f) {
  MixedMesh m = mixed_grid(n, quads_below);
  m.point_data.push_back({name, 1, values_at(m.points, f), false});
  return m;
}

std::string adapt_command(const fs::path& domain, const fs::path& sol, const std::string& rest, const fs::path& out) {
  return fmt::format("adapt '{}' --solution '{}' {} --out '{}' -q", domain.string(), sol.string(), rest, out.string());
}

}  // namespace

TEST_CASE("pdmesh adapt refines at the solution's layer and carries the solution onto the new mesh", "[adapt][cli]") {
  const fs::path dir = pdmesh_test::fresh_dir("adapt_layer");
  const fs::path sol = write_solution(dir);
  // The domain as a curve file, and as the solution's own mesh (its cells: io/mesh_geometry).
  for (const fs::path& domain : {fs::path(kSquare), sol}) {
    INFO("domain " << domain);
    const fs::path out = dir / ("out_" + domain.extension().string().substr(1));
    const auto r =
        pdmesh_test::run_pdmesh(adapt_command(domain, sol, "--array u --complexity 300 --hmax 0.3 --formats msh", out));
    INFO(r.output);
    REQUIRE(r.status == 0);
    const Mesh mesh = read_mesh(out / "mesh.msh");
    CHECK(pdmesh_test::mesh_area(mesh) == Approx(1.0).epsilon(1e-12));
    const AroundCurve d = around_curve(mesh);
    INFO("near " << d.near << " far " << d.far);
    CHECK(d.near > 8.0 * d.far);
    CHECK_THAT(pdmesh_test::slurp(out / "quality.json"), Contains("\"metric\": {\"edges\": "));
    // solution.vtu: the mesh's points, each with u (and v) interpolated from the 81 x 81 grid.
    MeshReadReport report;
    MeshPointData u;
    u.wanted = "u";
    const Mesh carried = read_vtu(out / "solution.vtu", report, &u);
    // kind is the writer's own (-1: not known), as in every pdmesh .vtu.
    CHECK(u.point_arrays == std::vector<std::string>{"kind", "u", "v"});
    REQUIRE(carried.points.size() == mesh.points.size());
    REQUIRE(u.array);
    REQUIRE(u.array->values.size() == mesh.points.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < mesh.points.size(); ++i) {
      CHECK(carried.points[i].x == mesh.points[i].x);
      CHECK(carried.points[i].y == mesh.points[i].y);
      worst = std::max(worst, std::fabs(u.array->values[i] - layer_u(mesh.points[i], 20.0)));
    }
    // P1 interpolation on the grid of step 1/80: |u''| h² / 8 is at most about 0.03 here.
    CHECK(worst < 0.05);
    CHECK(carried.triangles.size() == mesh.triangles.size());
  }
}

TEST_CASE("pdmesh adapt carries the solution onto the first format it reads back, past openfoam", "[adapt][cli]") {
  const fs::path dir = pdmesh_test::fresh_dir("adapt_openfoam");
  const fs::path sol = write_solution(dir);
  const fs::path out = dir / "out";
  const auto r = pdmesh_test::run_pdmesh(
      adapt_command(kSquare, sol, "--array u --complexity 300 --hmax 0.3 --formats openfoam,msh", out));
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(fs::exists(out / "mesh_openfoam" / "constant" / "polyMesh" / "faces"));
  // solution.vtu is on the msh file's points, u carried onto each.
  MeshReadReport report;
  MeshPointData u;
  u.wanted = "u";
  const Mesh carried = read_vtu(out / "solution.vtu", report, &u);
  CHECK(carried.points.size() == read_mesh(out / "mesh.msh").points.size());
  REQUIRE(u.array);
  CHECK(u.array->values.size() == carried.points.size());
  fs::remove_all(dir);
}

TEST_CASE("pdmesh adapt is pdmesh mesh on the case with field = hessian, bit for bit", "[adapt][cli]") {
  const fs::path dir = pdmesh_test::fresh_dir("adapt_same");
  const fs::path sol = write_solution(dir);
  // The domain's case has its own [spacing], which the command replaces.
  std::ofstream(dir / "domain.toml") << fmt::format(
      "name = \"square\"\n[geometry]\nfiles = [\"{}\"]\n[spacing]\nsize = 0.05\ngradation = 0.5\n", kSquare);
  std::ofstream(dir / "hessian.toml") << fmt::format(
      "name = \"square\"\n[geometry]\nfiles = [\"{}\"]\n[spacing]\nfield = \"hessian\"\nfile = \"{}\"\n"
      "array = \"u\"\ncomplexity = 300\nhmax = 0.3\nmetric_gradation = 1.5\n",
      kSquare, sol.string());
  const auto a = pdmesh_test::run_pdmesh(adapt_command(
      dir / "domain.toml", sol, "--array u --complexity 300 --hmax 0.3 --gradation 1.5 --formats msh", dir / "a"));
  INFO(a.output);
  REQUIRE(a.status == 0);
  const auto m = pdmesh_test::run_pdmesh(
      fmt::format("mesh '{}' --out '{}' --formats msh -q", (dir / "hessian.toml").string(), (dir / "m").string()));
  INFO(m.output);
  REQUIRE(m.status == 0);
  const std::string adapted = pdmesh_test::slurp(dir / "a" / "mesh.msh");
  CHECK(adapted.size() > 1000);
  CHECK(adapted == pdmesh_test::slurp(dir / "m" / "mesh.msh"));
  CHECK(fs::exists(dir / "a" / "solution.vtu"));
  CHECK_FALSE(fs::exists(dir / "m" / "solution.vtu"));
}

TEST_CASE("pdmesh adapt --norm sets the L^p exponent: another norm, another mesh", "[adapt][cli]") {
  const fs::path dir = pdmesh_test::fresh_dir("adapt_norm");
  const fs::path sol = write_solution(dir);
  std::vector<std::string> meshes;
  for (const char* norm : {"2", "4"}) {
    const auto r = pdmesh_test::run_pdmesh(adapt_command(
        kSquare, sol, fmt::format("--array u --complexity 300 --norm {} --formats msh --no-transfer", norm),
        dir / norm));
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK_FALSE(fs::exists(dir / norm / "solution.vtu"));
    meshes.push_back(pdmesh_test::slurp(dir / norm / "mesh.msh"));
  }
  // --norm 2 is the default.
  const auto d = pdmesh_test::run_pdmesh(
      adapt_command(kSquare, sol, "--array u --complexity 300 --formats msh --no-transfer", dir / "default"));
  REQUIRE(d.status == 0);
  CHECK(pdmesh_test::slurp(dir / "default" / "mesh.msh") == meshes[0]);
  CHECK(meshes[0] != meshes[1]);
}

TEST_CASE("several arrays: one scale over the intersection of their unscaled metrics", "[adapt][metric][hessian]") {
  const Mesh g = unit_grid(41);
  const std::vector<double> u = values_at(g.points, [](Vec2 p) { return std::tanh(10.0 * (p.y - 0.3)); });
  const std::vector<double> v = values_at(g.points, [](Vec2 p) { return 50.0 * std::tanh(10.0 * (p.x - 0.7)); });
  HessianMetricOptions o;
  o.complexity = 500.0;
  const std::vector<Metric> m = intersected_hessian_metrics_on_mesh(g.points, g.triangles, {u, v}, o, {"u", "v"});
  REQUIRE(m.size() == g.points.size());
  // The complexity is C.
  CHECK(complexity_scale(g.points, g.triangles, m, o.complexity, "m") == Approx(1.0).epsilon(1e-12));
  // Each array's metric before its scale, from the array divided by its range.
  std::vector<std::vector<Metric>> each;
  for (const auto* a : {&u, &v}) {
    const std::vector<Hessian> h = recover_hessians(g.points, g.triangles, divided_by_range(*a), "a");
    each.emplace_back();
    for (const Hessian& hi : h) each.back().push_back(lp_unscaled_metric(hi, o));
  }
  // One factor D makes the result the intersection at every point (scaling each array's metric to
  // C before intersecting gives no single factor), and the result is at least as fine as each
  // array's metric at that factor.
  const Metric first = intersect(each[0][0], each[1][0]);
  const double scale = m[0].m11 / first.m11;
  std::size_t finer_than_u = 0, finer_than_v = 0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const Metric both = scale * intersect(each[0][i], each[1][i]);
    const double size = std::fabs(both.m11) + std::fabs(both.m22);
    REQUIRE(std::fabs(m[i].m11 - both.m11) <= 1e-12 * size);
    REQUIRE(std::fabs(m[i].m12 - both.m12) <= 1e-12 * size);
    REQUIRE(std::fabs(m[i].m22 - both.m22) <= 1e-12 * size);
    // intersect() contains both up to rounding in its eigen decompositions.
    REQUIRE(largest_metric_ratio(m[i], scale * each[0][i]) <= 1.0 + 1e-6);
    REQUIRE(largest_metric_ratio(m[i], scale * each[1][i]) <= 1.0 + 1e-6);
    finer_than_u += largest_metric_ratio(scale * each[0][i], m[i]) > 1.5 ? 1 : 0;
    finer_than_v += largest_metric_ratio(scale * each[1][i], m[i]) > 1.5 ? 1 : 0;
  }
  // Each array adds to the other somewhere: the intersection is neither array's metric alone.
  CHECK(finer_than_u > 0);
  CHECK(finer_than_v > 0);
  // The arrays' units do not matter: v in other units gives the same metrics.
  std::vector<double> v_scaled = v;
  for (double& x : v_scaled) x *= 1e-3;
  const std::vector<Metric> m2 =
      intersected_hessian_metrics_on_mesh(g.points, g.triangles, {u, v_scaled}, o, {"u", "v"});
  for (std::size_t i = 0; i < m.size(); ++i) {
    const double size = std::fabs(m[i].m11) + std::fabs(m[i].m22);
    REQUIRE(std::fabs(m2[i].m11 - m[i].m11) <= 1e-9 * size);
    REQUIRE(std::fabs(m2[i].m22 - m[i].m22) <= 1e-9 * size);
  }
  // One array is the single-array metric.
  const std::vector<Metric> one = intersected_hessian_metrics_on_mesh(g.points, g.triangles, {u}, o, {"u"});
  const std::vector<Metric> single = hessian_metrics_on_mesh(g.points, g.triangles, u, o, "u");
  for (std::size_t i = 0; i < m.size(); ++i) REQUIRE((one[i].m11 == single[i].m11 && one[i].m22 == single[i].m22));
  CHECK_THAT(pdmesh_test::error_message<InputError>([&] {
               intersected_hessian_metrics_on_mesh(g.points, g.triangles, {u, v}, o, {"u"});
             }),
             Contains("2 arrays with 1 names"));
}

TEST_CASE("pdmesh adapt with two arrays refines both layers", "[adapt][cli]") {
  const fs::path dir = pdmesh_test::fresh_dir("adapt_two");
  const fs::path sol = write_solution(dir);
  const fs::path out = dir / "out";
  const auto r = pdmesh_test::run_pdmesh(
      adapt_command(kSquare, sol, "--array u,v --complexity 600 --hmax 0.3 --formats msh", out));
  INFO(r.output);
  REQUIRE(r.status == 0);
  const Mesh mesh = read_mesh(out / "mesh.msh");
  const auto from_u = [](Vec2 p) { return std::fabs(p.y - curve(p.x)); };
  const auto from_v = [](Vec2 p) { return std::fabs(p.x - 0.7); };
  const double far = density(mesh.points, [&](Vec2 p) { return from_u(p) > 0.15 && from_v(p) > 0.15; });
  const double near_u = density(mesh.points, [&](Vec2 p) { return from_u(p) < 0.02 && from_v(p) > 0.1; });
  const double near_v = density(mesh.points, [&](Vec2 p) { return from_v(p) < 0.02 && from_u(p) > 0.1; });
  INFO("near u " << near_u << " near v " << near_v << " far " << far);
  CHECK(near_u > 4.0 * far);
  CHECK(near_v > 4.0 * far);
  // The case-file form gives the same mesh.
  std::ofstream(dir / "case.toml") << fmt::format(
      "[geometry]\nfiles = [\"{}\"]\n[spacing]\nfield = \"hessian\"\nfile = \"{}\"\narray = [\"u\", \"v\"]\n"
      "complexity = 600\nhmax = 0.3\n",
      kSquare, sol.string());
  const CaseConfig c = load_case_file(dir / "case.toml");
  CHECK(c.spacing.arrays == std::vector<std::string>{"u", "v"});
  CHECK(c.spacing.array == "u");
}

TEST_CASE("spacing.array as a list: only for a Hessian metric of a file, each name once", "[adapt][case]") {
  const fs::path dir = pdmesh_test::fresh_dir("adapt_keys");
  const auto error_of = [&](const std::string& spacing) {
    return pdmesh_test::error_message<InputError>([&] {
      parse_case_text(fmt::format("[geometry]\nfiles = [\"{}\"]\n[spacing]\n{}", kSquare, spacing), dir / "case.toml");
    });
  };
  CHECK_THAT(error_of("field = \"mesh\"\nfile = \"q.vtu\"\narray = [\"a\", \"b\"]\n"),
             Contains("spacing.array is a list"));
  CHECK_THAT(error_of("field = \"hessian\"\nfile = \"u.vtu\"\ncomplexity = 10\narray = [\"a\", \"a\"]\n"),
             Contains("names 'a' twice"));
  CHECK_THAT(error_of("field = \"hessian\"\nfile = \"u.vtu\"\ncomplexity = 10\narray = []\n"),
             Contains("must not be an empty list"));
  CHECK_THAT(error_of("field = \"hessian\"\nfile = \"u.vtu\"\ncomplexity = 10\narray = [\"a\", 3]\n"),
             Contains("spacing.array"));
  const CaseConfig c = parse_case_text(
      fmt::format("[geometry]\nfiles = [\"{}\"]\n[spacing]\nfield = \"hessian\"\nfile = \"u.vtu\"\ncomplexity = 10\n",
                  kSquare),
      dir / "case.toml", {{"spacing.array", "[\"rho\", \"mach\"]", "--set spacing.array=[\"rho\", \"mach\"]"}});
  CHECK(c.spacing.arrays == std::vector<std::string>{"rho", "mach"});
  CHECK(c.spacing.norm == 2.0);
  // spacing.norm: the L^p exponent of a Hessian metric.
  const CaseConfig p4 = parse_case_text(
      fmt::format("[geometry]\nfiles = [\"{}\"]\n[spacing]\nfield = \"hessian\"\nfunction = \"x*x\"\ncomplexity = 10\n"
                  "norm = 4\n",
                  kSquare),
      dir / "case.toml");
  CHECK(p4.spacing.norm == 4.0);
  CHECK_THAT(error_of("field = \"hessian\"\nfunction = \"x*x\"\ncomplexity = 10\nnorm = 0.5\n"),
             Contains("spacing.norm must be a finite number >= 1, got 0.5"));
  CHECK_THAT(error_of("size = 0.1\nnorm = 2\n"), Contains("spacing.norm is set but spacing.field is 'boundary'"));
}

TEST_CASE("pdmesh adapt refuses bad inputs naming the option, and writes nothing", "[adapt][cli]") {
  const fs::path dir = pdmesh_test::fresh_dir("adapt_bad");
  const fs::path sol = write_solution(dir);
  const fs::path out = dir / "out";
  const auto refused = [&](const fs::path& solution, const std::string& rest, const std::string& says) {
    const auto r = pdmesh_test::run_pdmesh(adapt_command(kSquare, solution, rest, out));
    INFO(rest << "\n" << r.output);
    CHECK(r.status == 2);
    CHECK_THAT(r.output, Contains(says));
    CHECK_FALSE(fs::exists(out));
  };
  refused(dir / "missing.vtu", "--array u --complexity 100", "missing.vtu");
  refused(sol, "--array w --complexity 100", "no point array 'w' (point arrays: kind, u, v)");
  refused(sol, "--array u,w --complexity 100", "no point array 'w' (point arrays: kind, u, v)");
  refused(sol, "--array u --complexity 0", "--complexity 0");
  refused(sol, "--array u --complexity -5", "--complexity -5");
  refused(sol, "--array u --complexity many", "--complexity many");
  refused(sol, "--array u --complexity 100 --hmin 0.5 --hmax 0.1", "spacing.hmax must be larger than spacing.hmin");
  refused(sol, "--array u --complexity 100 --gradation 0.5", "--gradation 0.5");
  refused(sol, "--array u --complexity 100 --max-anisotropy 0.5", "--max-anisotropy 0.5");
  refused(sol, "--array u --complexity 100 --norm 0.5", "--norm 0.5");
  refused(sol, "--array u --complexity 100 --formats png", "--no-transfer");
  // The solution where solution.vtu would go.
  fs::create_directories(dir / "loop");
  fs::copy_file(sol, dir / "loop" / "solution.vtu");
  const auto r = pdmesh_test::run_pdmesh(
      adapt_command(kSquare, dir / "loop" / "solution.vtu", "--array u --complexity 100", dir / "loop"));
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("give another --out"));
  CHECK(pdmesh_test::entries(dir / "loop") == 1);
}

TEST_CASE("a layered solution: transfer and adapt interpolate in its quads, and a layered target keeps them",
          "[adapt][cli]") {
  const fs::path dir = pdmesh_test::fresh_dir("adapt_quads");
  // transfer: a linear function from a mesh whose lower half is quads onto another such mesh is exact
  // at every point, those inside the quads included, and the written mesh has the target's quads.
  const auto linear = [](Vec2 p) { return 2.0 * p.x - 3.0 * p.y + 0.5; };
  const fs::path from = dir / "from.vtu", to = dir / "to.vtu", moved = dir / "moved.vtu";
  write_file_atomically(from, mixed_vtu_string(mixed_grid(21, 0.5, "f", linear)));
  const MixedMesh target = mixed_grid(13, 0.6, "g", [](Vec2) { return 0.0; });
  write_file_atomically(to, mixed_vtu_string(target));
  const auto t = pdmesh_test::run_pdmesh(
      fmt::format("transfer '{}' '{}' --arrays f --out '{}'", from.string(), to.string(), moved.string()));
  INFO(t.output);
  REQUIRE(t.status == 0);
  MeshReadReport report;
  MeshPointData f;
  f.wanted = "f";
  SurfaceCells cells;
  const Mesh got = read_vtu(moved, report, &f, &cells);
  REQUIRE(got.points.size() == target.points.size());
  CHECK(cells.quads.size() == target.quads());
  CHECK(got.triangles.size() == target.cells.size() - target.quads());
  REQUIRE(f.array);
  for (std::size_t i = 0; i < got.points.size(); ++i) {
    INFO("point " << i << " (" << got.points[i].x << ", " << got.points[i].y << ")");
    CHECK(f.array->values[i] == Approx(linear(got.points[i])).margin(1e-12));
  }
  // adapt: the layer's lower half lies in the solution's quads (y < 0.5), and is refined there too.
  const fs::path sol = dir / "sol.vtu", out = dir / "out";
  write_file_atomically(sol, mixed_vtu_string(mixed_grid(81, 0.5, "u", [](Vec2 p) { return layer_u(p, 20.0); })));
  const auto r =
      pdmesh_test::run_pdmesh(adapt_command(kSquare, sol, "--array u --complexity 300 --hmax 0.3 --formats msh", out));
  INFO(r.output);
  REQUIRE(r.status == 0);
  const Mesh mesh = read_mesh(out / "mesh.msh");
  // Where the curve is below y = 0.4, in the solution's quads.
  const AroundCurve d = around_curve(mesh, [](Vec2 p) { return p.x > 0.55 && p.x < 0.95; });
  INFO("near " << d.near << " far " << d.far);
  CHECK(d.near > 8.0 * d.far);
}
