// Boundary layers in a [motion] run (docs/motion.md, "Boundary layers"): the layer nodes move rigidly
// with the body and keep their ids, no cell inverts, the core stays above 30 degrees, the layers'
// measures do not change; a front driven into a fixed curve is a run error; the command's files.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>

#include "app/config/case_file.hpp"
#include "app/pipeline/motion_pipeline.hpp"
#include "core/errors.hpp"
#include "core/predicates.hpp"
#include "motion/rigid_motion.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
namespace fs = std::filesystem;

namespace {

// A square far field [-3, 3]^2 and an ellipse (semi-axes 0.8, 0.3) in two halves, upper and lower.
void write_body(const fs::path& dir) {
  std::ofstream(dir / "far.crv") << "5\n-3 -3\n3 -3\n3 3\n-3 3\n-3 -3\n";
  std::ofstream body(dir / "body.crv");
  const int n = 24;
  for (int half = 0; half < 2; ++half) {
    body << n + 1 << "\n";
    for (int k = 0; k <= n; ++k) {
      const double a = M_PI * (half + static_cast<double>(k) / n);
      body << 0.8 * std::cos(a) << " " << 0.3 * std::sin(a) << "\n";
    }
  }
}

// The case: six quad layers from 0.004 on the ellipse, and `motion`.
std::string layered_case(const std::string& motion) {
  return "name = \"moving_layers\"\n[geometry]\nfiles = [\"far.crv\", \"body.crv\"]\ncurve_names = [\"far\", "
         "\"upper\", \"lower\"]\n[spacing]\nexpression = \"0.1 + 0.1 * sqrt(x*x + y*y)\"\n[simulation]\niterations = "
         "300\ndevice = \"host\"\n[output]\nformats = [\"vtu\", \"msh\"]\n[[boundary_layer]]\ncurves = [\"upper\", "
         "\"lower\"]\nfirst_height = 0.004\ngrowth = 1.2\nlayers = 6\nelements = \"quads\"\n" +
         motion;
}

CaseConfig layered_motion_case(const fs::path& dir, const std::string& motion) {
  write_body(dir);
  CaseConfig c = parse_case_text(layered_case(motion), dir / "case.toml", {});
  c.quiet = true;
  c.write_outputs = false;
  c.out_dir = dir / "out";
  return c;
}

// Cells whose corners are not all strictly counter-clockwise (exact).
std::size_t inverted_cells(const MixedMesh& m) {
  std::size_t bad = 0;
  for (const auto& c : m.cells) {
    const int n = c[3] < 0 ? 3 : 4;
    bool ok = true;
    for (int i = 0; i < n; ++i) {
      const auto at = [&](int k) {
        return m.points[static_cast<std::size_t>(c[static_cast<std::size_t>((k + n) % n)])];
      };
      ok = ok && orient2d(at(i - 1), at(i), at(i + 1)) > 0.0;
    }
    bad += !ok;
  }
  return bad;
}

// id -> position of the nodes of the layer cells.
std::map<std::int64_t, Vec2> layer_nodes(const MotionStep& s) {
  std::map<std::int64_t, Vec2> out;
  for (std::size_t k = 0; k < s.mixed.cells.size(); ++k) {
    if (!s.mixed.layer[k]) continue;
    for (const int v : s.mixed.cells[k])
      if (v >= 0) out[s.nodes.id[static_cast<std::size_t>(v)]] = s.mixed.points[static_cast<std::size_t>(v)];
  }
  return out;
}

}  // namespace

TEST_CASE("motion with boundary layers: the layer nodes move rigidly with their ids, nothing inverts") {
  const fs::path dir = pdmesh_test::fresh_dir("motion_layers_rotate");
  CaseConfig c = layered_motion_case(
      dir, "[motion]\ncurves = [\"upper\", \"lower\"]\nrotate = \"30*t\"\npivot = [0.2, 0.0]\nsteps = 3\n");
  c.check = true;  // every step's core mesh through the invariant checker
  std::vector<MotionStep> steps;
  run_motion_steps(c, [&](const MotionStep& s) { steps.push_back(s); });
  REQUIRE(steps.size() == 4);
  const MotionStep& first = steps.front();
  const std::map<std::int64_t, Vec2> rest = layer_nodes(first);
  REQUIRE(first.record.layer_cells > 0);
  REQUIRE(rest.size() > 100);
  for (const MotionStep& s : steps) {
    INFO("step " << s.record.step);
    const MotionStepRecord& r = s.record;
    REQUIRE(s.nodes.id.size() == s.mixed.points.size());
    REQUIRE(s.mixed.point_data.size() == 1);
    CHECK(s.mixed.point_data[0].name == "node_id");
    CHECK(std::set<std::int64_t>(s.nodes.id.begin(), s.nodes.id.end()).size() == s.nodes.size());
    CHECK(r.inverted == 0);
    CHECK(r.layer_inverted == 0);
    CHECK(inverted_cells(s.mixed) == 0);
    CHECK(r.min_angle >= 30.0);  // the core's
    // Every layer node kept, at the pose applied to its place at step 0.
    RigidPose pose;
    pose.pivot = {0.2, 0.0};
    pose.angle = 30.0 * r.t * M_PI / 180.0;
    const std::map<std::int64_t, Vec2> now = layer_nodes(s);
    CHECK(now.size() == rest.size());
    double worst = 0.0;
    std::size_t missing = 0;
    for (const auto& [id, p0] : rest) {
      const auto it = now.find(id);
      if (it == now.end()) {
        ++missing;
        continue;
      }
      worst = std::max(worst, dist(it->second, pose.apply(p0)));
    }
    CHECK(missing == 0);
    CHECK(worst < 1e-9);
    // The layer cells' measures are those of step 0: a rigid move changes no angle or height.
    CHECK(r.layer_cells == first.record.layer_cells);
    CHECK(r.layer_max_angle == Approx(first.record.layer_max_angle).margin(1e-9));
    CHECK(r.layer_first_height_within_2pct == first.record.layer_first_height_within_2pct);
    CHECK(r.layer_growth_max == Approx(first.record.layer_growth_max).margin(1e-9));
    if (r.step > 0) CHECK(r.ids_kept > 0.8);
  }
}

TEST_CASE("motion with boundary layers: a front driven into a fixed curve is a run error naming the step") {
  const fs::path dir = pdmesh_test::fresh_dir("motion_layers_collide");
  CaseConfig c = layered_motion_case(
      dir, "[motion]\ncurves = [\"upper\", \"lower\"]\ntranslate = [\"2.3*t\", \"0\"]\nsteps = 2\n");
  int done = 0;
  try {
    run_motion_steps(c, [&](const MotionStep&) { ++done; });
    FAIL("no error");
  } catch (const SimulationError& e) {
    const std::string what = e.what();
    INFO(what);
    CHECK(what.find("motion step 2 ") != std::string::npos);
    CHECK(what.find("_front' (moving with the body)") != std::string::npos);
    CHECK(what.find("'far'") != std::string::npos);
  }
  CHECK(done == 2);  // steps 0 and 1 finished
}

TEST_CASE("motion with boundary layers: a moving table whose wall chain is open is refused by name") {
  // Layers on the ellipse's upper half alone, which moves: the chain ends where the lower half, which
  // stays, continues it; the layers cannot move rigidly with a curve that does not.
  const fs::path dir = pdmesh_test::fresh_dir("motion_layers_open");
  write_body(dir);
  std::string text = layered_case("[motion]\ncurves = [\"upper\"]\nrotate = \"5*t\"\nsteps = 1\n");
  const std::string both = "curves = [\"upper\", \"lower\"]\nfirst_height";
  text.replace(text.find(both), both.size(), "curves = [\"upper\"]\nfirst_height");
  CaseConfig c = parse_case_text(text, dir / "case.toml", {});
  c.quiet = true;
  c.write_outputs = false;
  c.out_dir = dir / "out";
  CHECK_THROWS_AS(run_motion_steps(c, [](const MotionStep&) {}), InputError);
  CHECK_THROWS_WITH(run_motion_steps(c, [](const MotionStep&) {}),
                    Catch::Contains("the moving wall chain of curve \"upper\" is open (it ends at (") &&
                        Catch::Contains("add the curves that close its loop to the table and to [motion] curves"));
}

TEST_CASE("pdmesh mesh with [motion] and [[boundary_layer]]: step files with node_id and the layer cells") {
  const fs::path dir = pdmesh_test::fresh_dir("motion_layers_cli");
  write_body(dir);
  std::ofstream(dir / "case.toml") << layered_case(
      "[motion]\ncurves = [\"upper\", \"lower\"]\nrotate = \"10*sin(2*_pi*t)\"\npivot = [0.2, 0.0]\nsteps = 2\n");
  const fs::path out = dir / "out";
  const auto r = pdmesh_test::run_pdmesh("mesh '" + (dir / "case.toml").string() + "' --out '" + out.string() + "' -q");
  INFO(r.output);
  REQUIRE(r.status == 0);
  for (const char* step : {"step_0000", "step_0001", "step_0002"}) {
    const std::string vtu = pdmesh_test::slurp(out / step / "mesh.vtu");
    CHECK(vtu.find("Name=\"node_id\"") != std::string::npos);
    CHECK(vtu.find("Name=\"boundary_layer\"") != std::string::npos);
    CHECK(fs::exists(out / step / "mesh.msh"));
  }
  CHECK(pdmesh_test::slurp(out / "motion.json").find("\"layer_cells\"") != std::string::npos);
  CHECK(fs::exists(out / "motion.pvd"));

  // A table whose walls move only in part: exit 2 naming the table, nothing written.
  std::ofstream(dir / "case.toml") << layered_case("[motion]\ncurves = [\"upper\"]\nsteps = 2\n");
  const fs::path out2 = dir / "out2";
  const auto bad = pdmesh_test::run_pdmesh("mesh '" + (dir / "case.toml").string() + "' --out '" + out2.string() + "'");
  INFO(bad.output);
  CHECK(bad.status == 2);
  CHECK(bad.output.find("[[boundary_layer]] table 1: its curves upper move") != std::string::npos);
  CHECK(!fs::exists(out2));
}
