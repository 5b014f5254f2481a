// Metric fields from a case file (spacing.field = "metric" / "hessian"): the keys read, every
// refusal naming the key and value, the isotropic size the pipeline uses, and `pdmesh mesh` end to end
// (the triangulation in the metric, the measures in quality.json, a bad metric refused with exit 2
// and nothing written).
#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_inputs.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "app/pipeline/resume.hpp"
#include "core/errors.hpp"
#include "error_message.hpp"
#include "render/metric_picture.hpp"
#include "run_pdmesh.hpp"
#include "spacing/fixed_point_metric.hpp"
#include "spacing/hessian_metric.hpp"
#include "spacing/metric.hpp"
#include "spacing/metric_size_field.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;
using Catch::Matchers::Contains;

namespace {

// The number after "key": in a quality.json's text.
double json_number(const std::string& json, const std::string& key) {
  const auto at = json.find("\"" + key + "\": ");
  REQUIRE(at != std::string::npos);
  return std::stod(json.substr(at + key.size() + 4));
}

// The integer after `said` in a run's output.
int count_after(const std::string& output, const std::string& said) {
  const auto at = output.find(said);
  REQUIRE(at != std::string::npos);
  return std::stoi(output.substr(at + said.size()));
}

const fs::path kCase = "/cases/demo/case.toml";
const std::string kGeometry = "[geometry]\nfiles = [\"a.crv\"]\n";

std::string error_of(const std::string& spacing) {
  try {
    parse_case_text(kGeometry + "[spacing]\n" + spacing, kCase);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

CaseConfig parse(const std::string& spacing) { return parse_case_text(kGeometry + "[spacing]\n" + spacing, kCase); }

}  // namespace

TEST_CASE("metric keys are read: sizes, components, files", "[metric][case]") {
  const CaseConfig sizes = parse("field = \"metric\"\nh1 = \"0.1\"\nh2 = \"0.001 + 0.198*abs(y-0.5)\"\n");
  CHECK(sizes.spacing.field == SpacingKind::Metric);
  CHECK(sizes.spacing.metric());
  CHECK(sizes.spacing.h2 == "0.001 + 0.198*abs(y-0.5)");
  CHECK(sizes.spacing.angle == "0");  // the default direction: the x axis
  const CaseConfig comp = parse("field = \"metric\"\nm11 = \"100\"\nm12 = \"x\"\nm22 = \"400\"\n");
  CHECK(comp.spacing.m12 == "x");
  CHECK(comp.spacing.h1.empty());
  const CaseConfig vtu = parse("field = \"metric\"\nfile = \"m.vtu\"\n");
  CHECK(vtu.spacing.file == fs::path("/cases/demo/m.vtu"));
  CHECK(vtu.spacing.array == "metric");  // the default array of a metric file
  const CaseConfig medit = parse("field = \"metric\"\nfile = \"adapt.mesh\"\n");
  CHECK(medit.spacing.sol == fs::path("/cases/demo/adapt.sol"));  // the same stem
  const CaseConfig hessian = parse(
      "field = \"hessian\"\nfunction = \"tanh(100*(y-0.5))\"\ncomplexity = 4000\n"
      "hmin = 1e-5\nhmax = 0.3\nmax_anisotropy = 1000\n");
  CHECK(hessian.spacing.field == SpacingKind::Hessian);
  CHECK(hessian.spacing.complexity == 4000.0);
  CHECK(hessian.spacing.hmin == 1e-5);
  CHECK(hessian.spacing.hmax == 0.3);
  CHECK(hessian.spacing.max_anisotropy == 1000.0);
  const CaseConfig data = parse("field = \"hessian\"\nfile = \"u.vtu\"\ncomplexity = 100\nmetric_gradation = 1.5\n");
  CHECK(data.spacing.array == "u");
  CHECK(data.spacing.metric_gradation == 1.5);
  // A function's or an expression's metric is graded too (sampled on a grid over the extents).
  CHECK(parse("field = \"hessian\"\nfunction = \"x*x\"\ncomplexity = 10\nmetric_gradation = 1.5\n")
            .spacing.metric_gradation == 1.5);
  CHECK(parse("field = \"metric\"\nh1 = \"0.1\"\nh2 = \"0.01\"\nmetric_gradation = 2\n").spacing.metric_gradation ==
        2.0);
  // An isotropic case has no metric.
  CHECK_FALSE(parse("expression = \"0.1\"\n").spacing.metric());
}

TEST_CASE("bad metric keys are refused naming the key and the value", "[metric][case]") {
  // Sizes and components mixed.
  CHECK_THAT(error_of("field = \"metric\"\nh1 = \"0.1\"\nh2 = \"0.1\"\nm11 = \"1\"\n"),
             Contains("spacing.h1 and spacing.m11 are both set"));
  // A missing size or component.
  CHECK_THAT(error_of("field = \"metric\"\nh1 = \"0.1\"\n"), Contains("spacing.h2 is missing"));
  CHECK_THAT(error_of("field = \"metric\"\nm11 = \"1\"\nm22 = \"1\"\n"), Contains("spacing.m12 is missing"));
  CHECK_THAT(error_of("field = \"metric\"\n"), Contains("no metric is given"));
  // Expressions and a file.
  CHECK_THAT(error_of("field = \"metric\"\nh1 = \"0.1\"\nh2 = \"0.1\"\nfile = \"m.vtu\"\n"),
             Contains("spacing.h1 and spacing.file are both set"));
  // A metric key with another field, and a Hessian key with the metric field.
  CHECK_THAT(error_of("expression = \"0.1\"\nh1 = \"0.1\"\n"),
             Contains("spacing.h1 is set but spacing.field is 'expression'"));
  CHECK_THAT(error_of("field = \"metric\"\nh1 = \"1\"\nh2 = \"1\"\ncomplexity = 10\n"),
             Contains("spacing.complexity is set but spacing.field is 'metric'"));
  // Empty expressions, wrong types, out-of-range numbers: the key's line and the value.
  CHECK_THAT(error_of("field = \"metric\"\nh1 = \"\"\nh2 = \"0.1\"\n"), Contains("/cases/demo/case.toml:5"));
  CHECK_THAT(error_of("field = \"metric\"\nh1 = 0.1\nh2 = \"0.1\"\n"), Contains("spacing.h1 must be a string"));
  CHECK_THAT(error_of("field = \"hessian\"\nfunction = \"x*x\"\ncomplexity = -3\n"),
             Contains("spacing.complexity must be > 0, got -3"));
  CHECK_THAT(error_of("field = \"hessian\"\nfunction = \"x*x\"\n"), Contains("spacing.complexity"));
  CHECK_THAT(error_of("field = \"hessian\"\nfunction = \"x*x\"\ncomplexity = 10\nhmin = 0.5\nhmax = 0.1\n"),
             Contains("got hmin 0.5 and hmax 0.1"));
  CHECK_THAT(error_of("field = \"hessian\"\nfunction = \"x*x\"\ncomplexity = 10\nmax_anisotropy = 0.5\n"),
             Contains("spacing.max_anisotropy must be >= 1, got 0.5"));
  CHECK_THAT(error_of("field = \"hessian\"\ncomplexity = 10\n"), Contains("spacing.function"));
  CHECK_THAT(error_of("field = \"hessian\"\nfunction = \"x*x\"\ncomplexity = 10\nhessian_step = 0\n"),
             Contains("spacing.hessian_step must be in (0, 0.1], got 0"));
  CHECK_THAT(error_of("field = \"metric\"\nh1 = \"1\"\nh2 = \"1\"\nhessian_step = 0.01\n"),
             Contains("spacing.hessian_step is set but spacing.field is 'metric'"));
  // Gradation out of range; a .mesh is metric data only; a .sol needs a .mesh.
  CHECK_THAT(error_of("field = \"metric\"\nfile = \"m.vtu\"\nmetric_gradation = 0.5\n"), Contains("got 0.5"));
  CHECK_THAT(error_of("file = \"m.mesh\"\n"), Contains("is a Medit .mesh"));
  CHECK_THAT(error_of("field = \"metric\"\nfile = \"m.vtu\"\nsol = \"m.sol\"\n"), Contains("not a Medit .mesh"));
  CHECK_THAT(error_of("field = \"metric\"\nfile = \"m.mesh\"\nsol = \"m.txt\"\n"), Contains("'m.txt'"));
  // A misspelt key is refused with a suggestion.
  CHECK_THAT(error_of("field = \"metric\"\nh1 = \"1\"\nh3 = \"1\"\n"), Contains("spacing.h3"));
}

TEST_CASE("the isotropic size of a metric is sqrt(h1 h2)", "[metric][case]") {
  CHECK(isotropic_size(metric_from_sizes(0.1, 0.001, 0.3)) == Approx(std::sqrt(0.1 * 0.001)).epsilon(1e-12));
  CHECK(isotropic_size(metric_from_sizes(0.2, 0.2, 0.0)) == Approx(0.2).epsilon(1e-14));
  // Through the case and the read stage: MeshInputs holds the metric, its base field is the size.
  const CaseConfig c =
      load_case_file(fs::path(PDMESH_SOURCE_DIR) / "cases/aniso/linear/case.toml",
                     {parse_set_option("spacing.h2=0.01 + x*x"), parse_set_option("spacing.angle=30")});
  const MeshInputs inputs(c);
  REQUIRE(inputs.metric != nullptr);
  const Metric m = inputs.metric->at({0.5, 0.2});
  const Metric expected = metric_from_sizes(0.1, 0.26, 30.0 * M_PI / 180.0);
  CHECK(m.m11 == Approx(expected.m11).epsilon(1e-12));
  CHECK(m.m12 == Approx(expected.m12).epsilon(1e-12));
  CHECK(inputs.spacing->at({0.5, 0.2}) == Approx(std::sqrt(0.1 * 0.26)).epsilon(1e-12));
  const SpacingStage stage(c, inputs, SpacingStage::Build::FieldOnly);
  CHECK(stage.metric() == inputs.metric.get());
  // An isotropic case has none.
  const MeshInputs iso(load_case_file(fs::path(PDMESH_SOURCE_DIR) / "cases/circle_circle/case.toml"));
  CHECK(iso.metric == nullptr);
}

namespace {

// The case file of cases/aniso/linear's unit square with the given [spacing] lines, written into a
// fresh directory named by `tag`, loaded.
CaseConfig unit_square_case(const std::string& tag, const std::string& spacing) {
  const fs::path dir = pdmesh_test::fresh_path(tag);
  fs::create_directories(dir);
  {
    std::ofstream f(dir / "case.toml");
    f << "[geometry]\nfiles = ['" << (fs::path(PDMESH_SOURCE_DIR) / "cases/aniso/linear/domain.crv").string()
      << "']\n[spacing]\n"
      << spacing;
  }
  return load_case_file(dir / "case.toml");
}

// ∫ sqrt(det M) dy across the tanh layer y = 0.5 + 0.25 sin 2πx at x, over ±0.03: the metric's node
// density through the layer.
double density_across(const MetricField& m, double x) {
  const double y0 = 0.5 + 0.25 * std::sin(2.0 * M_PI * x);
  double sum = 0.0;
  for (int k = 0; k <= 600; ++k) sum += std::sqrt(m.at({x, y0 - 0.03 + 1e-4 * k}).det()) * 1e-4;
  return sum;
}

}  // namespace

TEST_CASE("spacing.hessian_step at the 1024 grid's scale leaves no hole at a curved layer's inflection",
          "[metric][case][hessian]") {
  // The tanh layer's along-layer curvature vanishes at x = 0.5. The exact Hessian's second eigenvalue
  // vanishes with it, and so does det|H|^(1/3), the L2-optimal metric's node density. Differences at
  // the scale of the 1024 grid (hessian_step = 2/1024) keep the density there comparable to the rest
  // of the layer; the default step (1e-5, the exact Hessian) has the hole.
  const CaseConfig c = unit_square_case("metric_case_tanh",
                                        "field = 'hessian'\nfunction = 'tanh(100*(y - 0.5 - 0.25*sin(2*pi*x)))'\n"
                                        "complexity = 4000\nhmin = 1e-5\nhmax = 0.3\ngradation = 0\n"
                                        "hessian_step = 0.001953125\n");
  CHECK(c.spacing.hessian_step == 0.001953125);
  const MeshInputs inputs(c);
  REQUIRE(inputs.metric != nullptr);
  const double inflection = density_across(*inputs.metric, 0.5);
  const double elsewhere = density_across(*inputs.metric, 0.25);
  CHECK(inflection > 0.5 * elsewhere);
  // The Hessian exact to rounding (step 1e-5) has the hole.
  HessianMetricOptions o;
  o.complexity = 4000;
  o.hmin = 1e-5;
  o.hmax = 0.3;
  const HessianMetricField exact(c.spacing.function, Box{{0, 0}, {1, 1}}, o, 1e-5, 1024);
  CHECK(density_across(exact, 0.5) < 0.2 * density_across(exact, 0.25));
  fs::remove_all(c.source.parent_path());
}

TEST_CASE("pdmesh mesh triangulates in the metric and measures in it", "[metric][case][cli]") {
  const fs::path out = pdmesh_test::fresh_path("metric_case_out");
  const std::string source = PDMESH_SOURCE_DIR;
  const auto r =
      pdmesh_test::run_pdmesh(fmt::format("mesh '{}/cases/aniso/linear/case.toml' --out '{}' "
                                          "--set simulation.iterations=200",
                                          source, out.string()));
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Contains("triangulation in the metric"));
  CHECK_THAT(r.output, Contains("cleanup in the metric: "));
  CHECK_THAT(r.output, Contains("Metric: edges in [0.71,1.41]"));
  const std::string json = pdmesh_test::slurp(out / "quality.json");
  CHECK_THAT(json, Contains("\"metric\": {\"edges\": "));
  CHECK_THAT(json, Contains("\"cleanup\": {"));
  CHECK(fs::exists(out / "mesh_metric_q.png"));
  CHECK(fs::exists(out / "metric.png"));
  // pdmesh quality with the case measures the same mesh in the same metric.
  const auto q = pdmesh_test::run_pdmesh(fmt::format(
      "quality '{}' --geometry '{}/cases/aniso/linear/case.toml' --json -", (out / "mesh.msh").string(), source));
  INFO(q.output);
  CHECK(q.status == 0);
  CHECK_THAT(q.output, Contains("Metric: quality Q"));
  CHECK_THAT(q.output, Contains("\"metric\": {\"edges\": "));
  fs::remove_all(out);
}

TEST_CASE("cleanup.enabled = false leaves a metric run's triangulation in the metric as it is", "[metric][case][cli]") {
  const fs::path out = pdmesh_test::fresh_path("metric_case_no_cleanup");
  const auto r = pdmesh_test::run_pdmesh(
      fmt::format("mesh '{}/cases/aniso/linear/case.toml' --out '{}' --formats msh --set simulation.iterations=200 "
                  "--set cleanup.enabled=false",
                  PDMESH_SOURCE_DIR, out.string()));
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, !Contains("cleanup in the metric"));
  CHECK_THAT(pdmesh_test::slurp(out / "quality.json"), Contains("\"cleanup\": null"));
  // The mesh's nodes are the simulation's.
  CHECK(pdmesh_test::slurp(out / "mesh.nodes") == pdmesh_test::slurp(out / "final.nodes"));
  fs::remove_all(out);
}

TEST_CASE(
    "linear and polar-2 stop soon after population control's last event, and the cleanup in the metric "
    "settles early at issue 37's targets",
    "[metric][case][cli][convergence]") {
  // With the particles' nodes as they are, 98.9 % / Q min 0.561 (linear) and 82.1 % / 0.086
  // (polar-2); the targets: >= 99.5 % of the edges in [1/sqrt2, sqrt2], Q min >= 0.75 and the
  // element count within 10 % of 4C/sqrt3. Population control ends at iteration 300 and the step
  // anneals from there (metric_anneal_from), so the nodes settle within a few measurements of it; the
  // bounds leave two measurements or more of margin over where the two cases stop.
  for (const auto& [name, most] : {std::pair{"linear", 450}, std::pair{"polar2", 700}}) {
    INFO(name);
    const fs::path out = pdmesh_test::fresh_path(std::string("metric_cleanup_") + name);
    const auto r = pdmesh_test::run_pdmesh(fmt::format(
        "mesh '{}/cases/aniso/{}/case.toml' --out '{}' --formats msh --check", PDMESH_SOURCE_DIR, name, out.string()));
    INFO(r.output);
    REQUIRE(r.status == 0);
    // --check: all but the isotropic Delaunay test, on the triangulation and on the cleaned mesh.
    CHECK_THAT(r.output, Contains("mesh check (triangulation in the metric): passed"));
    CHECK_THAT(r.output, Contains("mesh check (mesh cleaned in the metric): passed"));
    const int iterations = count_after(r.output, "simulation: converged after ");
    CHECK(iterations > 300);  // not before population control's last event
    CHECK(iterations <= most);
    // The cleanup ends once settled (no split or collapse, Q min not raised, the mean Q still), well
    // before the best preset's cap of 32 iterations: "cleanup in the metric: T s, N iterations".
    const std::string said = "cleanup in the metric: ";
    const auto at = r.output.find(said);
    REQUIRE(at != std::string::npos);
    CHECK(count_after(r.output.substr(at), " s, ") <= 16);
    const std::string json = pdmesh_test::slurp(out / "quality.json");
    CHECK(json_number(json, "window_percent") >= 99.5);
    CHECK(json_number(json, "q_min") >= 0.75);
    CHECK(std::abs(json_number(json, "n_over_ideal") - 1.0) <= 0.1);
    fs::remove_all(out);
  }
}

TEST_CASE("polar-1 reaches issue 37's targets under the step's decay factors around the default",
          "[metric][case][cli][convergence]") {
  // polar-1's worst triangles lie in the first rows off its curved wall, where no tangential edge can be
  // in the window (docs/metric-fields.md, "Cases"); where the nodes stand when the step freezes
  // depends on the decay factor. The climb lifts a ball whose worst Q is below 0.35 even when edges
  // leave the window, so that Q min clears 0.30 at these decays; >= 95 % of the edges stay in it.
  for (const char* decay : {"0.985", "0.99", "0.995"}) {
    INFO(decay);
    const fs::path out = pdmesh_test::fresh_path(std::string("metric_polar1_") + decay);
    const auto r =
        pdmesh_test::run_pdmesh(fmt::format("mesh '{}/cases/aniso/polar1/case.toml' --out '{}' --formats msh --check "
                                            "--set simulation.metric_anneal={}",
                                            PDMESH_SOURCE_DIR, out.string(), decay));
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK_THAT(r.output, Contains("mesh check (mesh cleaned in the metric): passed"));
    const std::string said = "cleanup in the metric: ";
    const auto at = r.output.find(said);
    REQUIRE(at != std::string::npos);
    CHECK(count_after(r.output.substr(at), " s, ") < 32);  // ended before the cap
    const std::string json = pdmesh_test::slurp(out / "quality.json");
    CHECK(json_number(json, "q_min") >= 0.30);
    CHECK(json_number(json, "window_percent") >= 95.0);
    fs::remove_all(out);
  }
}

TEST_CASE("the nodes relax in the metric: the linear case's edges have unit metric length", "[metric][case][cli]") {
  // Nodes started isotropically at sqrt(h1 h2) and relaxed in the metric gave 98.9 % in the window and
  // Q min 0.56; started at unit metric length (init/metric_fill) and relaxed with population control in
  // the metric, 99.78 % and 0.756.
  const fs::path out = pdmesh_test::fresh_path("metric_relax_out");
  const auto r = pdmesh_test::run_pdmesh(
      fmt::format("mesh '{}/cases/aniso/linear/case.toml' --out '{}' --formats msh", PDMESH_SOURCE_DIR, out.string()));
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Contains("population control: 5 events"));
  const std::string json = pdmesh_test::slurp(out / "quality.json");
  CHECK(json_number(json, "window_percent") > 99.5);
  CHECK(json_number(json, "q_min") > 0.7);
  CHECK(std::abs(json_number(json, "n_over_ideal") - 1.0) < 0.1);
  fs::remove_all(out);
}

TEST_CASE("a Medit .mesh + .sol metric runs, the .sol found by the .mesh's stem", "[metric][case][cli]") {
  const fs::path dir = pdmesh_test::fresh_dir("metric_case_medit");
  const std::string source = PDMESH_SOURCE_DIR;
  // A constant metric, h = 0.05 along x and 0.1 along y, on two triangles around the unit square.
  std::ofstream(dir / "bg.mesh") << "MeshVersionFormatted 2\nDimension 2\nVertices\n4\n-0.1 -0.1 0\n1.1 -0.1 0\n"
                                    "1.1 1.1 0\n-0.1 1.1 0\nTriangles\n2\n1 2 3 0\n1 3 4 0\nEnd\n";
  std::ofstream(dir / "bg.sol") << "MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n4\n1 3\n400 0 100\n"
                                   "400 0 100\n400 0 100\n400 0 100\nEnd\n";
  std::ofstream(dir / "case.toml") << fmt::format(
      "[geometry]\nfiles = [\"{}/cases/aniso/linear/domain.crv\"]\n[spacing]\nfield = \"metric\"\nfile = \"bg.mesh\"\n",
      source);
  const fs::path out = dir / "out";
  const auto r =
      pdmesh_test::run_pdmesh(fmt::format("mesh '{}' --out '{}' -q", (dir / "case.toml").string(), out.string()));
  INFO(r.output);
  REQUIRE(r.status == 0);
  const std::string json = pdmesh_test::slurp(out / "quality.json");
  CHECK_THAT(json, Contains("\"metric\": {\"edges\": "));
  // A .sol whose metric is not SPD: exit 2 naming the .sol, nothing written.
  std::ofstream(dir / "bg.sol") << "MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n4\n1 3\n400 0 100\n"
                                   "400 300 100\n400 0 100\n400 0 100\nEnd\n";
  const fs::path out2 = dir / "out2";
  const auto bad =
      pdmesh_test::run_pdmesh(fmt::format("mesh '{}' --out '{}' -q", (dir / "case.toml").string(), out2.string()));
  CHECK(bad.status == 2);
  CHECK_THAT(bad.output, Contains("bg.sol"));
  CHECK_FALSE(fs::exists(out2));
  fs::remove_all(dir);
}

TEST_CASE("a metric that is not a size is exit 2, naming the expression, nothing written", "[metric][case][cli]") {
  const fs::path dir = pdmesh_test::fresh_dir("metric_case_bad");
  const std::string source = PDMESH_SOURCE_DIR;
  std::ofstream(dir / "case.toml") << fmt::format(
      "[geometry]\nfiles = [\"{}/cases/aniso/linear/domain.crv\"]\n"
      "[spacing]\nfield = \"metric\"\nh1 = \"0.1\"\nh2 = \"y - 0.5\"\n",
      source);
  const fs::path out = dir / "out";
  const auto r =
      pdmesh_test::run_pdmesh(fmt::format("mesh '{}' --out '{}'", (dir / "case.toml").string(), out.string()));
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("h2 = 'y - 0.5'"));
  CHECK_THAT(r.output, Contains("a size must be a finite positive number"));
  CHECK_FALSE(fs::exists(out));
  fs::remove_all(dir);
}

TEST_CASE("the metric keys are part of the checkpoint's case identity", "[metric][case][resume]") {
  const fs::path file = fs::path(PDMESH_SOURCE_DIR) / "cases/aniso/linear/case.toml";
  const auto identity = case_identity(load_case_file(file));
  const auto other = case_identity(load_case_file(file, {parse_set_option("spacing.h1=0.2")}));
  CHECK(identity != other);
  const auto has = [&identity](const std::string& key, const std::string& value) {
    return std::find(identity.begin(), identity.end(), std::pair{key, value}) != identity.end();
  };
  CHECK(has("spacing.field", "metric"));
  CHECK(has("spacing.h2", "0.001 + 0.198*abs(y - 0.5)"));
  // An isotropic case's identity has no metric keys (its checkpoints keep their identity).
  const auto iso = case_identity(load_case_file(fs::path(PDMESH_SOURCE_DIR) / "cases/circle_circle/case.toml"));
  for (const auto& [key, value] : iso) CHECK(key != "spacing.h1");
}

TEST_CASE("the metric picture needs one metric per point", "[metric][render]") {
  Mesh mesh;
  mesh.points = {{0, 0}, {1, 0}, {0, 1}};
  mesh.triangles = {{0, 1, 2}};
  const fs::path out = pdmesh_test::fresh_dir("metric_picture");
  CHECK_THAT(pdmesh_test::error_message<Error>([&] { write_metric_picture(out / "m.png", mesh, {Metric{}}, {}); }),
             Contains("1 metrics for 3 points"));
  write_metric_picture(out / "m.png", mesh, std::vector<Metric>(3, metric_from_sizes(0.5, 0.1, 0.3)), {});
  CHECK(fs::file_size(out / "m.png") > 0);
  fs::remove_all(out);
}

TEST_CASE("an output that would replace the metric file is refused", "[metric][cli][outputs]") {
  const fs::path dir = pdmesh_test::fresh_dir("metric_case_guard");
  fs::create_directories(dir / "out");
  std::ofstream(dir / "out" / "mesh.vtu") << "the metric\n";
  std::ofstream(dir / "case.toml") << fmt::format(
      "[geometry]\nfiles = [\"{}/cases/aniso/linear/domain.crv\"]\n[spacing]\nfield = \"metric\"\nfile = "
      "\"out/mesh.vtu\"\n",
      PDMESH_SOURCE_DIR);
  const auto r = pdmesh_test::run_pdmesh(
      fmt::format("mesh '{}' --out '{}' -q", (dir / "case.toml").string(), (dir / "out").string()));
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("would replace the input"));
  CHECK(pdmesh_test::slurp(dir / "out" / "mesh.vtu") == "the metric\n");
  fs::remove_all(dir);
}

TEST_CASE("simulation.metric_anneal: 0.99 by default, a case's value in [0.5, 1] reaches the run, others refused",
          "[metric][case]") {
  CHECK(parse("field = \"metric\"\nh1 = \"0.1\"\nh2 = \"0.01\"\n").simulation.metric_anneal ==
        SimOptions{}.metric_anneal);
  CHECK(SimOptions{}.metric_anneal == 0.99);
  const CaseConfig off = parse_case_text(
      kGeometry + "[spacing]\nfield = \"metric\"\nh1 = \"0.1\"\nh2 = \"0.01\"\n[simulation]\nmetric_anneal = 1\n",
      kCase);
  CHECK(off.simulation.metric_anneal == 1.0);
  CHECK(simulation_options(off).metric_anneal == 1.0);
  for (const char* bad : {"0.4", "1.01", "0", "\"fast\""})
    CHECK_THROWS_AS(parse_case_text(kGeometry + "[simulation]\nmetric_anneal = " + bad + "\n", kCase), InputError);
}

namespace {

// The size of metric m along the unit vector at `angle` (radians): 1 / |(cos, sin)|_m.
double size_along(const Metric& m, double angle) { return 1.0 / m.length({std::cos(angle), std::sin(angle)}); }

}  // namespace

TEST_CASE("a fixed node on a Hessian metric's inflection line gets the field's metric around it",
          "[metric][case][hessian]") {
  // u = tanh(20 (y - x/2)): u'' = 0 on the line y = x/2 through the unit square's corner (0, 0), a
  // fixed node. There the exact Hessian vanishes and the metric is isotropic at hmax; 0.005 beside
  // the line its size across the line is a few thousandths. The corner's metric is graded from the
  // field around it, so the pairs, gaps and triangles at the corner are not measured by hmax.
  const CaseConfig c = unit_square_case(
      "metric_case_corner",
      "field = 'hessian'\nfunction = 'tanh(20*(y - 0.5*x))'\ncomplexity = 2000\nhmax = 1\ngradation = 0\n");
  const MeshInputs inputs(c);
  REQUIRE(inputs.metric != nullptr);
  HessianMetricOptions o;
  o.complexity = 2000;
  o.hmax = 1;
  const HessianMetricField exact(c.spacing.function, Box{{0, 0}, {1, 1}}, o, 1e-5, 1024);
  const double across = std::atan2(1.0, -0.5);  // the line's normal
  // The field at distance d from the line, beside its point (0.2, 0.1).
  const auto off_line = [&](double d) { return exact.at({0.2 + d * std::cos(across), 0.1 + d * std::sin(across)}); };
  // The field itself: hmax at the corner, small beside the line.
  CHECK(size_along(exact.at({0, 0}), across) == Approx(1.0).epsilon(1e-9));
  const double near = size_along(off_line(1e-4), across), far = size_along(off_line(5e-3), across);
  CHECK(near < 0.01);
  CHECK(far < near);
  // The case's metric at the corner: between the field's sizes 1e-4 and 5e-3 beside the line.
  const double corner = size_along(inputs.metric->at({0, 0}), across);
  CHECK(corner < near);
  CHECK(corner > far);
  // Elsewhere the field as it is: the other corners (no steeper grading around them), and a point on
  // the line that is no fixed node.
  for (const Vec2 p : {Vec2{1, 0}, Vec2{1, 1}, Vec2{0, 1}, Vec2{0.5, 0.25}, Vec2{0.3, 0.7}}) {
    const Metric a = inputs.metric->at(p), b = exact.at(p);
    CHECK(a.m11 == b.m11);
    CHECK(a.m12 == b.m12);
    CHECK(a.m22 == b.m22);
  }
  fs::remove_all(c.source.parent_path());
}

TEST_CASE("largest_metric_ratio is the largest |v|_b^2 / |v|_a^2 over the directions", "[metric]") {
  const Metric a = metric_from_sizes(0.3, 0.01, 0.4), b = metric_from_sizes(0.05, 0.02, -1.1);
  double brute = 0.0;
  for (int k = 0; k < 36000; ++k) {
    const Vec2 v{std::cos(k * M_PI / 36000), std::sin(k * M_PI / 36000)};
    brute = std::max(brute, b.quad(v) / a.quad(v));
  }
  // The sampled directions miss the largest by a step of pi/36000: brute is below it, by a few 1e-6.
  CHECK(largest_metric_ratio(a, b) == Approx(brute).epsilon(1e-5));
  CHECK(brute <= largest_metric_ratio(a, b) * (1.0 + 1e-12));
  CHECK(largest_metric_ratio(a, a) == Approx(1.0).epsilon(1e-12));
  CHECK(largest_metric_ratio(a, 4.0 * a) == Approx(4.0).epsilon(1e-12));
}
