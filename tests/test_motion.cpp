// Moving geometry ([motion], docs/motion.md): persistent node ids, the carry, the steps' meshes, the
// .pvd/.json outputs, solution transfer, and the [motion] keys' errors.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <string>

#include "app/config/case_file.hpp"
#include "app/pipeline/motion_pipeline.hpp"
#include "cleanup/cleanup.hpp"
#include "core/errors.hpp"
#include "geometry/geometry_files.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "mesh/mesh_check.hpp"
#include "mesh/transfer.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "motion/carry.hpp"
#include "nodes/node_ids.hpp"
#include "run_pdmesh.hpp"
#include "sim/boundary_handling.hpp"
#include "spacing/spacing_field.hpp"
#include "spacing/triangle_locator.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
namespace fs = std::filesystem;

namespace {

struct ConstantSpacing final : SpacingField {
  explicit ConstantSpacing(double v) : q(v) {}
  double at(Vec2) const override { return q; }
  double q;
};

// A square far field [-3, 3]^2 and an ellipse (semi-axes 0.8, 0.3) cut into an upper and a lower curve.
void write_geometry(const fs::path& dir) {
  std::ofstream far(dir / "far.crv");
  far << "5\n-3 -3\n3 -3\n3 3\n-3 3\n-3 -3\n";
  std::ofstream body(dir / "body.crv");
  const int n = 16;
  for (int half = 0; half < 2; ++half) {
    body << n + 1 << "\n";
    for (int k = 0; k <= n; ++k) {
      const double a = M_PI * (half + static_cast<double>(k) / n);
      body << 0.8 * std::cos(a) << " " << 0.3 * std::sin(a) << "\n";
    }
  }
}

std::string case_text(const std::string& motion) {
  return "name = \"moving\"\n[geometry]\nfiles = [\"far.crv\", \"body.crv\"]\ncurve_names = [\"far\", \"upper\", "
         "\"lower\"]\n[spacing]\nexpression = \"0.12 + 0.1 * sqrt(x*x + y*y)\"\n[simulation]\niterations = 300\n"
         "device = \"host\"\n[output]\nformats = [\"vtu\"]\n" +
         motion;
}

CaseConfig motion_case(const fs::path& dir, const std::string& motion) {
  write_geometry(dir);
  CaseConfig c = parse_case_text(case_text(motion), dir / "case.toml", {});
  c.quiet = true;
  c.write_outputs = false;
  c.out_dir = dir / "out";
  return c;
}

double distance_to_polyline(Vec2 p, const std::vector<Vec2>& pts) {
  double best = 1e300;
  for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
    const Vec2 a = pts[k], ab = pts[k + 1] - a;
    const double t = std::clamp(dot(p - a, ab) / norm2(ab), 0.0, 1.0);
    best = std::min(best, std::sqrt(norm2(p - (a + t * ab))));
  }
  return best;
}

}  // namespace

TEST_CASE("node ids: NodeSet::add appends a new id, remove_nodes drops the removed ones, new ones are numbered") {
  const fs::path dir = pdmesh_test::fresh_dir("motion_ids");
  write_geometry(dir);
  const Geometry g =
      read_geometry({(dir / "far.crv").string(), (dir / "body.crv").string()}, {"far", "upper", "lower"});
  const GeometryTree tree(g);
  const ConstantSpacing spacing(0.5);
  NodeSet nodes = make_boundary_nodes(g, spacing);
  std::int64_t next = 100;
  number_new_nodes(nodes, next);
  REQUIRE(nodes.has_ids());
  REQUIRE(nodes.id.front() == 100);
  BoundaryHandler handler(tree, nodes);
  const int a = handler.add_interior(nodes, {2.0, 2.0}, 0.5);
  const int b = handler.add_interior(nodes, {-2.0, 2.0}, 0.5);
  REQUIRE(nodes.id.size() == nodes.size());
  CHECK(nodes.id[static_cast<std::size_t>(a)] == -1);
  const std::vector<std::int64_t> before = nodes.id;
  std::vector<char> remove(nodes.size(), 0);
  remove[static_cast<std::size_t>(a)] = 1;
  handler.remove_nodes(nodes, remove);
  REQUIRE(nodes.id.size() == nodes.size());
  CHECK(nodes.id.back() == -1);  // b, renumbered, still new
  CHECK(nodes.x.back().x == -2.0);
  number_new_nodes(nodes, next);
  CHECK(nodes.id.back() == next - 1);
  CHECK(ids_kept(before, nodes.id) == nodes.size() - 1);
  (void)b;
}

TEST_CASE("node ids: the cleanup keeps the ids of the nodes it keeps") {
  const fs::path dir = pdmesh_test::fresh_dir("motion_cleanup_ids");
  write_geometry(dir);
  const Geometry g =
      read_geometry({(dir / "far.crv").string(), (dir / "body.crv").string()}, {"far", "upper", "lower"});
  const GeometryTree tree(g);
  const ConstantSpacing spacing(0.4);
  NodeSet nodes = make_boundary_nodes(g, spacing);
  // A coarse, irregular interior so that the cleanup has work to do.
  for (int i = -6; i <= 6; ++i)
    for (int j = -6; j <= 6; ++j) {
      const Vec2 p{0.45 * i + 0.07 * (j % 3), 0.45 * j + 0.05 * (i % 2)};
      if (std::fabs(p.x) < 2.8 && std::fabs(p.y) < 2.8 && (p.x * p.x / 0.9 + p.y * p.y / 0.16) > 1.6)
        nodes.add(p, 0.4, NodeKind::Interior, -1);
    }
  std::int64_t next = 0;
  number_new_nodes(nodes, next);
  const Mesh mesh = triangulate(nodes, {"far", "upper", "lower"});
  CleanupOptions options;
  options.min_angle = 35.0;
  const CleanupResult cleaned = clean_mesh(mesh, nodes, tree, spacing, options);
  REQUIRE(cleaned.nodes.id.size() == cleaned.nodes.size());
  std::set<std::int64_t> seen;
  for (std::size_t i = 0; i < cleaned.nodes.size(); ++i) {
    const std::int64_t id = cleaned.nodes.id[i];
    if (id < 0) continue;
    CHECK(seen.insert(id).second);  // an id at most once
    // A kept node's id is the id of that node in the input.
    const auto at = static_cast<std::size_t>(id);
    CHECK(nodes.kind[at] == cleaned.nodes.kind[i]);
  }
  CHECK(seen.size() > nodes.size() / 2);
}

TEST_CASE("carry: a large rotation is split into sub-steps and never inverts a triangle") {
  const fs::path dir = pdmesh_test::fresh_dir("motion_carry");
  write_geometry(dir);
  const Geometry g =
      read_geometry({(dir / "far.crv").string(), (dir / "body.crv").string()}, {"far", "upper", "lower"});
  const GeometryTree tree(g);
  const ConstantSpacing spacing(0.25);
  NodeSet nodes = make_boundary_nodes(g, spacing);
  for (int i = -11; i <= 11; ++i)
    for (int j = -11; j <= 11; ++j) {
      const Vec2 p{0.25 * i + 0.125 * (j & 1), 0.25 * j * std::sqrt(0.75)};
      if (std::fabs(p.x) < 2.85 && std::fabs(p.y) < 2.85 && (p.x * p.x / 0.81 + p.y * p.y / 0.1225) > 1.4)
        nodes.add(p, 0.25, NodeKind::Interior, -1);
    }
  const Mesh mesh = triangulate(nodes, {"far", "upper", "lower"});
  REQUIRE(first_inverted(mesh.triangles, mesh.points) < 0);
  CarryRequest r;
  r.nodes = &nodes;
  r.triangles = &mesh.triangles;
  r.tree = &tree;
  r.moving = {0, 1, 1};
  r.radius = 1.5;
  r.to.angle = 70.0 * M_PI / 180.0;
  const CarryResult out = carry_nodes(r);
  CHECK(out.substeps > 1);
  CHECK(first_inverted(mesh.triangles, out.x) < 0);
  // The body's nodes turned rigidly, the far field's stayed.
  const std::vector<char> rigid = moving_nodes(nodes, r.moving);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (rigid[i]) {
      const Vec2 e = r.to.apply(nodes.x[i]);
      CHECK(std::hypot(out.x[i].x - e.x, out.x[i].y - e.y) < 1e-12);
    } else if (nodes.kind[i] != NodeKind::Interior) {
      CHECK(out.x[i] == nodes.x[i]);
    }
  }
  CHECK(carry_weight(0.0, 2.0) == 1.0);
  CHECK(carry_weight(2.0, 2.0) == 0.0);
}

TEST_CASE("motion: a step with zero motion keeps every id and a valid mesh") {
  const fs::path dir = pdmesh_test::fresh_dir("motion_zero");
  CaseConfig c =
      motion_case(dir, "[motion]\ncurves = [\"upper\", \"lower\"]\nrotate = \"0\"\nsteps = 1\niterations = 0\n");
  std::vector<MotionStep> steps;
  run_motion_steps(c, [&](const MotionStep& s) { steps.push_back(s); });
  REQUIRE(steps.size() == 2);
  CHECK(steps[1].record.ids_kept == 1.0);
  CHECK(steps[1].nodes.id == steps[0].nodes.id);
  CHECK(steps[1].record.inverted == 0);
  CHECK(check_mesh(steps[1].mesh).ok());
}

TEST_CASE("motion: a rigid rotation keeps the body's nodes on the moved curves and the ids mostly kept") {
  const fs::path dir = pdmesh_test::fresh_dir("motion_rotate");
  CaseConfig c =
      motion_case(dir, "[motion]\ncurves = [\"upper\", \"lower\"]\nrotate = \"30*t\"\npivot = [0.2, 0.0]\nsteps = 3\n");
  c.check = true;  // every step's mesh through the invariant checker (a SimulationError if one fails)
  const Geometry g =
      read_geometry({(dir / "far.crv").string(), (dir / "body.crv").string()}, {"far", "upper", "lower"});
  std::vector<MotionStep> steps;
  run_motion_steps(c, [&](const MotionStep& s) { steps.push_back(s); });
  REQUIRE(steps.size() == 4);
  for (const MotionStep& s : steps) {
    INFO("step " << s.record.step);
    CHECK(s.record.inverted == 0);
    CHECK(check_mesh(s.mesh).ok());
    RigidPose pose;
    pose.pivot = {0.2, 0.0};
    pose.angle = 30.0 * s.record.t * M_PI / 180.0;
    for (std::size_t i = 0; i < s.nodes.size(); ++i) {
      if (s.nodes.kind[i] == NodeKind::Interior || s.nodes.curve[i] == 0) continue;
      std::vector<Vec2> moved;
      for (const Vec2& p : g.curves[static_cast<std::size_t>(s.nodes.curve[i])].points) moved.push_back(pose.apply(p));
      CHECK(distance_to_polyline(s.nodes.x[i], moved) < 1e-9);
    }
    // node_id point data: one id per point, each once.
    REQUIRE(s.mesh.point_data.size() == 1);
    CHECK(s.mesh.point_data[0].name == "node_id");
    const std::set<double> ids(s.mesh.point_data[0].values.begin(), s.mesh.point_data[0].values.end());
    CHECK(ids.size() == s.mesh.points.size());
    if (s.record.step > 0) CHECK(s.record.ids_kept > 0.8);
  }
}

TEST_CASE("transfer: a linear function is interpolated exactly, also outside the source mesh") {
  const fs::path dir = pdmesh_test::fresh_dir("motion_transfer");
  write_geometry(dir);
  const Geometry g =
      read_geometry({(dir / "far.crv").string(), (dir / "body.crv").string()}, {"far", "upper", "lower"});
  const ConstantSpacing spacing(0.3);
  NodeSet nodes = make_boundary_nodes(g, spacing);
  for (int i = -9; i <= 9; ++i)
    for (int j = -9; j <= 9; ++j) {
      const Vec2 p{0.3 * i + 0.15 * (j & 1), 0.3 * j * std::sqrt(0.75)};
      if (std::fabs(p.x) < 2.85 && std::fabs(p.y) < 2.85 && (p.x * p.x / 0.81 + p.y * p.y / 0.1225) > 1.5)
        nodes.add(p, 0.3, NodeKind::Interior, -1);
    }
  const Mesh from = triangulate(nodes, {"far", "upper", "lower"});
  const auto f = [](Vec2 p) { return 2.0 * p.x - 3.0 * p.y + 0.5; };
  std::vector<double> values;  // two components: f and 1
  for (const Vec2& p : from.points) values.insert(values.end(), {f(p), 1.0});
  std::vector<Vec2> at{{0.1, 2.0}, {-2.5, -2.5}, {1.7, 0.4}, {2.99, -2.99}, {0.0, 0.25}};
  for (int k = 0; k < 200; ++k) at.push_back({-2.9 + 0.029 * k, 1.3 - 0.011 * k});
  TransferCounts counts;
  const std::vector<double> out = transfer_point_values(from, values, 2, at, &counts);
  REQUIRE(out.size() == 2 * at.size());
  std::size_t inside = 0;
  const TriangleLocator locator(from.points, from.triangles);
  for (std::size_t i = 0; i < at.size(); ++i) {
    if (locator.locate(at[i]).triangle < 0) continue;  // inside the body's hole: the nearest boundary value
    ++inside;
    CHECK(out[2 * i] == Approx(f(at[i])).margin(1e-12));
    CHECK(out[2 * i + 1] == Approx(1.0).margin(1e-12));
  }
  CHECK(inside > 150);
  CHECK(counts.outside > 0);  // (0, 0.25) is inside the ellipse, outside the mesh
  CHECK(counts.inside + counts.outside == at.size());
}

TEST_CASE(
    "pdmesh mesh with [motion] writes the step meshes, motion.pvd and motion.json, and pdmesh transfer reads them") {
  const fs::path dir = pdmesh_test::fresh_dir("motion_cli");
  write_geometry(dir);
  {
    std::ofstream(dir / "case.toml") << case_text(
        "[motion]\ncurves = [\"upper\", \"lower\"]\nrotate = \"10*sin(2*_pi*t)\"\npivot = [0.2, 0.0]\nsteps = 2\n");
  }
  const fs::path out = dir / "out";
  const auto r = pdmesh_test::run_pdmesh("mesh '" + (dir / "case.toml").string() + "' --out '" + out.string() + "' -q");
  INFO(r.output);
  REQUIRE(r.status == 0);
  const std::string pvd = pdmesh_test::slurp(out / "motion.pvd");
  const std::regex dataset(R"re(<DataSet timestep="([^"]+)" group="" part="0" file="(step_\d{4}/mesh\.vtu)"/>)re");
  std::vector<std::string> files;
  for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), dataset); it != std::sregex_iterator(); ++it)
    files.push_back((*it)[2]);
  REQUIRE(files.size() == 3);
  for (const std::string& f : files) CHECK(fs::exists(out / f));
  CHECK(pvd.find("timestep=\"0.5\"") != std::string::npos);
  const std::string json = pdmesh_test::slurp(out / "motion.json");
  const std::regex row(
      R"re(\{"step": (\d+), "t": [^,]+, "wall_s": [^,]+, "cpu_s": [^,]+, "iterations": \d+, "nodes": \d+, "ids_kept": [^,]+, "min_angle": [^,]+, "inverted": 0,)re");
  std::size_t rows = 0;
  for (auto it = std::sregex_iterator(json.begin(), json.end(), row); it != std::sregex_iterator(); ++it) ++rows;
  CHECK(rows == 3);
  CHECK(pdmesh_test::slurp(out / "step_0001/mesh.vtu").find("Name=\"node_id\"") != std::string::npos);
  // Transfer step 0's q onto step 1.
  const fs::path moved = dir / "transferred.vtu";
  const auto t =
      pdmesh_test::run_pdmesh("transfer '" + (out / "step_0000/mesh.vtu").string() + "' '" +
                              (out / "step_0001/mesh.vtu").string() + "' --arrays q --out '" + moved.string() + "'");
  INFO(t.output);
  CHECK(t.status == 0);
  const std::string text = pdmesh_test::slurp(moved);
  CHECK(text.find("Name=\"q\"") != std::string::npos);
  CHECK(text.find("Name=\"node_id\"") != std::string::npos);
  const auto missing = pdmesh_test::run_pdmesh("transfer '" + (out / "step_0000/mesh.vtu").string() + "' '" +
                                               (out / "step_0001/mesh.vtu").string() + "' --arrays pressure --out '" +
                                               (dir / "x.vtu").string() + "'");
  CHECK(missing.status == 2);
  CHECK(missing.output.find("pressure") != std::string::npos);
  CHECK(!fs::exists(dir / "x.vtu"));
}

TEST_CASE("pdmesh mesh with bad [motion] keys: exit 2 naming the key, nothing written") {
  const fs::path dir = pdmesh_test::fresh_dir("motion_bad");
  write_geometry(dir);
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"[motion]\ncurves = [\"wing\"]\nsteps = 4\n", "unknown curve 'wing'"},
      {"[motion]\ncurves = [\"upper\"]\nrotate = \"10*sin(2*_pi*\"\nsteps = 4\n", "motion.rotate"},
      {"[motion]\ncurves = [\"upper\"]\nrotate = \"w*t\"\nsteps = 4\n", "motion.rotate"},
      {"[motion]\ncurves = [\"upper\"]\nrotate = \"1/(t-0.5)\"\nsteps = 4\n", "motion.rotate"},
      {"[motion]\ncurves = [\"upper\"]\nsteps = 0\n", "motion.steps"},
      {"[motion]\ncurves = [\"upper\"]\nsteps = -3\n", "motion.steps"},
      {"[motion]\ncurves = [\"upper\"]\n", "motion.steps is required"},
      {"[motion]\ncurves = [\"upper\"]\nsteps = 2\ntranslate = [\"t\"]\n", "motion.translate"},
      {"[motion]\ncurves = [\"upper\"]\nsteps = 2\nspeed = 3\n", "motion.speed"},
  };
  for (const auto& [motion, message] : bad) {
    INFO(motion);
    std::ofstream(dir / "case.toml") << case_text(motion);
    const fs::path out = dir / "out";
    const auto r = pdmesh_test::run_pdmesh("mesh '" + (dir / "case.toml").string() + "' --out '" + out.string() + "'");
    INFO(r.output);
    CHECK(r.status == 2);
    CHECK(r.output.find(message) != std::string::npos);
    CHECK(!fs::exists(out));
  }
  // The curve check against names read from the files (no geometry.curve_names in the case).
  std::ofstream(dir / "case.toml") << "[geometry]\nfiles = [\"far.crv\", \"body.crv\"]\n[motion]\ncurves = "
                                      "[\"wing\"]\nsteps = 2\n";
  const auto r =
      pdmesh_test::run_pdmesh("mesh '" + (dir / "case.toml").string() + "' --out '" + (dir / "out2").string() + "'");
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK(r.output.find("unknown curve 'wing'") != std::string::npos);
  CHECK(!fs::exists(dir / "out2"));
}

TEST_CASE("motion stepper: the steps of run_motion_steps for the same poses, bit for bit") {
  const fs::path dir = pdmesh_test::fresh_dir("motion_stepper");
  const CaseConfig c =
      motion_case(dir, "[motion]\ncurves = [\"upper\", \"lower\"]\nrotate = \"30*t\"\npivot = [0.2, 0.0]\nsteps = 2\n");
  std::vector<MotionStep> run;
  run_motion_steps(c, [&](const MotionStep& s) { run.push_back(s); });
  REQUIRE(run.size() == 3);
  // The stepper driven by hand, with the case's curve names given as a caller would.
  MotionStepper stepper(c, {{"upper", "lower"}, "moving"}, pose_in_degrees(0.0, {0.2, 0.0}, {0.0, 0.0}));
  std::vector<MotionStep> by_hand{stepper.start(0.0)};
  for (int k = 1; k <= 2; ++k)
    by_hand.push_back(stepper.step(pose_in_degrees(15.0 * k, {0.2, 0.0}, {0.0, 0.0}), 0.5 * k));
  for (int k = 0; k <= 2; ++k) {
    INFO("step " << k);
    CHECK(by_hand[k].mesh.points == run[k].mesh.points);
    CHECK(by_hand[k].mesh.triangles == run[k].mesh.triangles);
    CHECK(by_hand[k].nodes.id == run[k].nodes.id);
    CHECK(by_hand[k].record.ids_kept == run[k].record.ids_kept);
  }
}

TEST_CASE(
    "motion stepper: unknown or no curves and poses not finite or about another pivot are InputErrors, and a "
    "carry that folds is refused with the stepper kept") {
  const fs::path dir = pdmesh_test::fresh_dir("motion_stepper_bad");
  CaseConfig c = motion_case(dir, "");
  const RigidPose rest = pose_in_degrees(0.0, {0.2, 0.0}, {0.0, 0.0});
  CHECK_THROWS_WITH(MotionStepper(c, {{"upper", "wing"}, "moving"}, rest),
                    Catch::Contains("moving: unknown curve 'wing'") && Catch::Contains("far, upper, lower"));
  CHECK_THROWS_AS(MotionStepper(c, {{}, "moving"}, rest), InputError);
  CHECK_THROWS_WITH(MotionStepper(c, {{"upper"}, "moving"}, pose_in_degrees(NAN, {0.2, 0.0}, {0.0, 0.0})),
                    Catch::Contains("start pose") && Catch::Contains("not finite"));
  c.motion.iterations = 5;
  MotionStepper stepper(c, {{"upper", "lower"}, "moving"}, rest);
  stepper.start(0.0);
  CHECK_THROWS_WITH(stepper.step(pose_in_degrees(5.0, {0.2, 0.0}, {INFINITY, 0.0}), 1.0),
                    Catch::Contains("motion step 1") && Catch::Contains("not finite"));
  CHECK_THROWS_WITH(stepper.step(pose_in_degrees(5.0, {0.0, 0.0}, {0.0, 0.0}), 1.0), Catch::Contains("pivot"));
  // A motion too large for one step (the body pushed to the far field): the carry would fold the mesh
  // and is refused; the stepper stays at its last step and goes on from there.
  CHECK_THROWS_WITH(stepper.step(pose_in_degrees(0.0, {0.2, 0.0}, {2.5, 0.0}), 1.0),
                    Catch::Contains("carrying the nodes inverts"));
  const MotionStep& s = stepper.step(pose_in_degrees(5.0, {0.2, 0.0}, {0.0, 0.0}), 1.0);
  CHECK(s.record.step == 1);
  CHECK(s.record.inverted == 0);
  CHECK(check_mesh(s.mesh).ok());
}
