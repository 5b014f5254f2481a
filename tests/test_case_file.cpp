// Tests of case-file parsing: a full example, defaults, every error kind (with line numbers and
// suggestions) and --set overrides.
#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <filesystem>
#include <string>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "cleanup/cleanup.hpp"
#include "spacing/background_field.hpp"
#include "core/errors.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;

namespace {

const fs::path kCase = "/cases/demo/case.toml";

// The message of the InputError that parsing `text` throws ("" if none is thrown).
std::string error_of(const std::string& text, const std::vector<CaseOverride>& overrides = {}) {
  try {
    parse_case_text(text, kCase, overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const char* kMinimal = "[geometry]\nfiles = [\"a.crv\"]\n";

}  // namespace

TEST_CASE("a full case file is read into CaseConfig", "[app][case]") {
  const std::string text = R"(name = "naca0012"

[geometry]
files = ["airfoil.crv", "/abs/farfield.crv"]
curve_names = ["upper", "lower"]
join_tolerance = 1e-7
corner_angle = 45

[spacing]
field = "expression"
expression = "0.5 + 19.5*tanh(x/16)^2"

[init]
method = "random"
seed = 7
total = 12000

[simulation]
iterations = 500
dt_initial = { structured = 0.01, random = 0.025 }
cutoff = 1.75
lj_a = 12.5
device = "opencl:0:1"
precision = "float"

[output]
formats = ["msh", "svg", "triangle"]
tree_overlay = true
views = [
  { name = "inner_circle", window = [-1.0, -1.0, 1.0, 1.5] },
  { window = [0, 0, 2, 2] },
]
)";
  const CaseConfig c = parse_case_text(text, kCase);
  CHECK(c.name == "naca0012");
  REQUIRE(c.geometry.files.size() == 2);
  CHECK(c.geometry.files[0] == fs::path("/cases/demo/airfoil.crv"));
  CHECK(c.geometry.files[1] == fs::path("/abs/farfield.crv"));
  CHECK(c.geometry.curve_names == std::vector<std::string>{"upper", "lower"});
  CHECK(c.geometry.join_tolerance == 1e-7);
  CHECK(c.geometry.corner_angle == 45.0);
  CHECK(c.spacing.field == SpacingKind::Expression);
  CHECK(c.spacing.expression == "0.5 + 19.5*tanh(x/16)^2");
  CHECK(c.init.method == InitMethod::Random);
  CHECK(c.init.seed == 7);
  CHECK(c.init.total == 12000);
  CHECK(c.simulation.iterations == 500);
  CHECK(c.simulation.dt_for(InitMethod::Structured) == 0.01);
  CHECK(c.simulation.dt_for(InitMethod::Random) == 0.025);
  CHECK(c.simulation.cutoff == 1.75);
  CHECK(c.simulation.lj_a == 12.5);
  CHECK(c.simulation.device == "opencl:0:1");
  CHECK(c.simulation.precision == Precision::Float);
  CHECK(c.output.formats == std::vector<std::string>{"msh", "svg", "triangle"});
  CHECK(c.output.wants("svg"));
  CHECK_FALSE(c.output.wants("png"));
  CHECK(c.output.tree_overlay);
  REQUIRE(c.output.views.size() == 2);
  CHECK(c.output.views[0].name == "inner_circle");
  CHECK(c.output.views[0].window.lo.x == -1.0);
  CHECK(c.output.views[0].window.hi.y == 1.5);
  CHECK(c.output.views[1].name == "view2");
  CHECK(c.output.views[1].window.hi.x == 2.0);
}

TEST_CASE("omitted keys take the documented defaults", "[app][case]") {
  const CaseConfig c = parse_case_text(kMinimal, kCase);
  CHECK(c.name == "demo");  // the case directory
  CHECK(c.geometry.files == std::vector<fs::path>{"/cases/demo/a.crv"});
  CHECK(c.geometry.curve_names.empty());
  CHECK(c.geometry.join_tolerance == 1e-9);
  CHECK(c.geometry.corner_angle == 30.0);
  CHECK(c.spacing.field == SpacingKind::Boundary);
  CHECK(c.init.method == InitMethod::Hybrid);  // the best preset's fill
  CHECK(c.init.seed == 1);
  CHECK(c.init.total == 0);
  // The best preset's hybrid: the quads where q is flat start at 1.25 x the estimate, the others take the
  // patterns' counts; its lattice quads off q's plateaus on 4 levels per octave.
  CHECK(c.init.density == 1.25);
  CHECK(c.init.density_where == DensityWhere::Flat);
  CHECK(c.init.lattice_levels == 4);
  CHECK(c.simulation.iterations == 2000);
  // The best preset's larger step for structured (and hybrid) starts; a random start keeps the automatic rule.
  CHECK(c.simulation.dt_structured == 0.016);
  CHECK_FALSE(c.simulation.dt_random.has_value());
  CHECK(c.simulation.cutoff == 1.5);
  CHECK(c.simulation.lj_a == 15.0);
  CHECK(c.simulation.device == "auto");
  CHECK(c.simulation.precision == Precision::Auto);
  CHECK(c.output.formats == std::vector<std::string>{"msh", "vtu", "png"});
  CHECK_FALSE(c.output.tree_overlay);
  CHECK(c.output.views.empty());
  CHECK(c.max_nodes == 20'000'000);
}

TEST_CASE("a single dt_initial applies to both methods, and an expression alone selects the expression field",
          "[app][case]") {
  const CaseConfig c = parse_case_text(
      std::string(kMinimal) + "[simulation]\ndt_initial = 0.009\n[spacing]\nexpression = \"2\"\n", kCase);
  CHECK(c.simulation.dt_for(InitMethod::Structured) == 0.009);
  CHECK(c.simulation.dt_for(InitMethod::Random) == 0.009);
  CHECK(c.spacing.field == SpacingKind::Expression);
}

TEST_CASE("TOML syntax errors name file, line and column", "[app][case]") {
  const std::string m = error_of("[geometry]\nfiles = [\"a.crv\"]\n[simulation]\niterations = = 3\n");
  CHECK(m.rfind("/cases/demo/case.toml:4:", 0) == 0);
}

TEST_CASE("geometry.join_tolerance out of (0, 1) is refused at its line", "[app][case]") {
  // build_geometry refuses these too, but without the key or the file (docs/geometry-input.md, "Errors").
  CHECK(error_of(std::string(kMinimal) + "join_tolerance = 2\n") ==
        "/cases/demo/case.toml:3:18: geometry.join_tolerance must be in (0, 1), got 2");
  CHECK_THAT(error_of(std::string(kMinimal) + "join_tolerance = 1\n"),
             Catch::Contains("geometry.join_tolerance must be in (0, 1), got 1"));
  CHECK_THAT(error_of(std::string(kMinimal) + "join_tolerance = 0\n"),
             Catch::Contains("geometry.join_tolerance must be in (0, 1), got 0"));
  CHECK(parse_case_text(std::string(kMinimal) + "join_tolerance = 0.5\n", kCase).geometry.join_tolerance == 0.5);
}

TEST_CASE("unknown keys are reported with the nearest valid key", "[app][case]") {
  std::string m = error_of(std::string(kMinimal) + "\n[simulaton]\niterations = 5\n");
  CHECK(m == "/cases/demo/case.toml:5:1: unknown key 'simulaton.iterations'; did you mean 'simulation.iterations'?");
  m = error_of(std::string(kMinimal) + "join_tolerence = 1e-6\n");
  CHECK(m.find(":3:1: unknown key 'geometry.join_tolerence'; did you mean 'geometry.join_tolerance'?") !=
        std::string::npos);
  m = error_of(std::string(kMinimal) + "completely_unrelated_thing = 1\n");
  CHECK(m.find("unknown key 'geometry.completely_unrelated_thing'") != std::string::npos);
  CHECK(m.find("did you mean") == std::string::npos);
  m = error_of(std::string(kMinimal) + "[output]\nviews = [{ nmae = \"a\", window = [0, 0, 1, 1] }]\n");
  CHECK(m.find(":4:") != std::string::npos);
  CHECK(m.find("unknown key 'output.views[0].nmae'; did you mean 'output.views[0].name'?") != std::string::npos);
}

TEST_CASE("wrong types are reported with the expected and the actual type", "[app][case]") {
  std::string m = error_of(std::string(kMinimal) + "[simulation]\niterations = \"many\"\n");
  CHECK(m == "/cases/demo/case.toml:4:14: simulation.iterations must be an integer, got string");
  m = error_of(std::string(kMinimal) + "[output]\ntree_overlay = 1\n");
  CHECK(m.find(":4:16: output.tree_overlay must be a boolean") != std::string::npos);
  m = error_of("[geometry]\nfiles = [\"a.crv\", 3]\n");
  CHECK(m.find(":2:19: geometry.files[1] must be a string, got integer") != std::string::npos);
  m = error_of("geometry = 3\n");
  CHECK(m.find(":1:12: geometry must be a table, got integer") != std::string::npos);
}

TEST_CASE("out-of-range values are rejected with the value", "[app][case]") {
  const std::string base = kMinimal;
  CHECK(error_of(base + "[simulation]\niterations = -1\n").find(":4:14: simulation.iterations must be >= 0, got -1") !=
        std::string::npos);
  CHECK(error_of(base + "[simulation]\ncutoff = 0\n").find("simulation.cutoff must be > 0, got 0") !=
        std::string::npos);
  CHECK(error_of(base + "[simulation]\ndt_initial = -0.5\n").find("simulation.dt_initial must be > 0, got -0.5") !=
        std::string::npos);
  CHECK(
      error_of(base + "[simulation]\ndt_initial = { random = 0 }\n").find("simulation.dt_initial.random must be > 0") !=
      std::string::npos);
  CHECK(error_of(base + "[init]\nmethod = \"spiral\"\n")
            .find("init.method must be one of structured, random, hexagonal, hybrid, got 'spiral'") !=
        std::string::npos);
  CHECK(error_of(base + "[init]\ndensity = 3\n").find("init.density must be 0 or in [0.5, 2], got 3") !=
        std::string::npos);
  CHECK(error_of(base + "[init]\ndensity_where = \"edges\"\n")
            .find("init.density_where must be one of inside, flat, got 'edges'") != std::string::npos);
  CHECK(error_of(base + "[init]\nlattice_levels = -1\n").find("init.lattice_levels must be 0 or in [1, 64], got -1") !=
        std::string::npos);
  CHECK(error_of(base + "[init]\nlattice_levels = 65\n").find("init.lattice_levels must be 0 or in [1, 64], got 65") !=
        std::string::npos);
  CHECK(error_of(base + "[init]\nlattice_levels = 2.5\n").find("init.lattice_levels") != std::string::npos);
  CHECK(parse_case_text(base + "[init]\nlattice_levels = 8\n", kCase).init.lattice_levels == 8);
  CHECK(parse_case_text(base, kCase, {parse_set_option("init.lattice_levels=0")}).init.lattice_levels == 0);
  CHECK(error_of(base + "[init]\nhybrid_spread = -0.1\n").find("init.hybrid_spread must be in [0, 1], got -0.1") !=
        std::string::npos);
  CHECK(error_of(base + "[init]\nhybrid_spread = 1.5\n").find("init.hybrid_spread must be in [0, 1], got 1.5") !=
        std::string::npos);
  CHECK(error_of(base + "[init]\nhybrid_spread = \"wide\"\n").find("init.hybrid_spread") != std::string::npos);
  CHECK(parse_case_text(base + "[init]\nhybrid_spread = 0.1\n", kCase).init.hybrid_spread == 0.1);
  CHECK(parse_case_text(base, kCase, {parse_set_option("init.hybrid_spread=0.05")}).init.hybrid_spread == 0.05);
  CHECK(error_of(base + "[simulation]\ndevice = \"cuda\"\n").find("got 'cuda'") != std::string::npos);
  CHECK(error_of(base + "[simulation]\ndevice = \"opencl:1\"\n").find("got 'opencl:1'") != std::string::npos);
  CHECK(error_of(base + "[simulation]\nprecision = \"half\"\n").find("got 'half'") != std::string::npos);
  CHECK(error_of(base + "[output]\nformats = [\"png\", \"jpeg\"]\n").find("unknown format 'jpeg'") !=
        std::string::npos);
  CHECK(error_of(base + "[output]\nviews = [{ window = [1, 0, 0, 1] }]\n").find("x0 < x1") != std::string::npos);
  CHECK(error_of(base + "[output]\nviews = [{ window = [0, 0, 1] }]\n").find("must have 4 numbers, got 3") !=
        std::string::npos);
  CHECK(error_of(base + "[spacing]\nfield = \"expression\"\n").find("spacing.expression is missing") !=
        std::string::npos);
  CHECK(error_of(base + "curve_names = [\"has space\"]\n").find("'has space' is not a plain name") !=
        std::string::npos);
  CHECK(error_of("name = \"x\"\n").find("geometry.files is required") != std::string::npos);
  CHECK(error_of("[geometry]\nfiles = []\n").find("at least one file") != std::string::npos);
}

TEST_CASE("overrides (--set) are applied before validation", "[app][case]") {
  const std::vector<CaseOverride> sets = {parse_set_option("simulation.iterations=10"),
                                          parse_set_option("init.method=random"),
                                          parse_set_option("output.formats=[\"png\",\"svg\"]"),
                                          parse_set_option("simulation.dt_initial.structured=0.5"),
                                          parse_set_option("name=renamed"),
                                          parse_set_option("spacing.expression=0.25")};
  const CaseConfig c = parse_case_text(std::string(kMinimal) + "[simulation]\niterations = 99\n", kCase, sets);
  CHECK(c.simulation.iterations == 10);
  CHECK(c.init.method == InitMethod::Random);
  CHECK(c.output.formats == std::vector<std::string>{"png", "svg"});
  CHECK(c.simulation.dt_structured == 0.5);
  CHECK_FALSE(c.simulation.dt_random.has_value());
  CHECK(c.name == "renamed");
  CHECK(c.spacing.field == SpacingKind::Expression);
  CHECK(c.spacing.expression == "0.25");  // a number given to a string key is its text
}

TEST_CASE("a case file is checked whole, also where an override replaces a value", "[app][case]") {
  const std::vector<CaseOverride> iterations = {{"simulation.iterations", "5", "--iterations 5"}};
  CHECK(error_of(std::string(kMinimal) + "[simulation]\niterations = \"many\"\n", iterations) ==
        "/cases/demo/case.toml:4:14: simulation.iterations must be an integer, got string");
  CHECK(error_of(std::string(kMinimal) + "[simulation]\ncutoff = -1\n", {parse_set_option("simulation.cutoff=2")}) ==
        "/cases/demo/case.toml:4:10: simulation.cutoff must be > 0, got -1");
  CHECK(error_of(std::string(kMinimal) + "[simulation]\nprecision = \"half\"\n",
                 {{"simulation.precision", "float", "--precision float"}})
            .find("simulation.precision must be one of double, float, auto, got 'half'") != std::string::npos);
  // What only the whole configuration decides is left to it: overrides may complete a file.
  const CaseConfig c =
      parse_case_text("[spacing]\nfield = \"expression\"\n", kCase,
                      {parse_set_option("geometry.files=[\"b.crv\"]"), parse_set_option("spacing.expression=0.5")});
  CHECK(c.spacing.expression == "0.5");
  CHECK(c.geometry.files.size() == 1);
  CHECK(parse_case_text(std::string(kMinimal) + "[simulation]\niterations = 7\n", kCase, iterations)
            .simulation.iterations == 5);
}

TEST_CASE("errors in overrides name the option, not the case file", "[app][case]") {
  CHECK(error_of(kMinimal, {parse_set_option("simulation.iterations=abc")}) ==
        "--set simulation.iterations=abc: simulation.iterations must be an integer, got string");
  CHECK(error_of(kMinimal, {parse_set_option("simulaton.cutoff=2")}) ==
        "--set simulaton.cutoff=2: unknown key 'simulaton.cutoff'; did you mean 'simulation.cutoff'?");
  CHECK(error_of(kMinimal, {{"simulation.cutoff", "-1", "--cutoff -1"}}) ==
        "--cutoff -1: simulation.cutoff must be > 0, got -1");
  CHECK(error_of(kMinimal, {parse_set_option("geometry.files.x=1")})
            .find("'geometry.files' is not a table (it is an array)") != std::string::npos);
  CHECK(error_of(kMinimal, {parse_set_option("geometry.files.x=1")}).find("not a table") != std::string::npos);
  CHECK_THROWS_AS(parse_set_option("novalue"), InputError);
}

TEST_CASE("appending overrides (--view) append views", "[app][case]") {
  CaseOverride view{"output.views", "{ window = [0, 0, 1, 2] }", "--view 0,0,1,2", true};
  const CaseConfig c = parse_case_text(
      std::string(kMinimal) + "[output]\nviews = [{ name = \"a\", window = [0,0,1,1] }]\n", kCase, {view});
  REQUIRE(c.output.views.size() == 2);
  CHECK(c.output.views[1].name == "view2");
  CHECK(c.output.views[1].window.hi.y == 2.0);
}

TEST_CASE("a geometry file alone makes a default case", "[app][case]") {
  const CaseConfig c = case_for_geometry_file("/data/naca.crv", {parse_set_option("init.seed=3")});
  CHECK(c.name == "naca");
  CHECK(c.geometry.files == std::vector<fs::path>{"/data/naca.crv"});
  CHECK(c.init.seed == 3);
}

TEST_CASE("several geometry files alone make one default case, named after the first", "[app][case]") {
  const CaseConfig c = case_for_geometry_files({"/data/airfoil.crv", "/data/farfield.crv"});
  CHECK(c.name == "airfoil");
  CHECK(c.geometry.files == std::vector<fs::path>{"/data/airfoil.crv", "/data/farfield.crv"});
  CHECK(c.preset == Preset::Best);
}

TEST_CASE("the preset key selects the defaults, and keys the file sets win over it", "[app][case]") {
  CHECK(parse_case_text(kMinimal, kCase).preset == Preset::Best);
  CHECK(parse_case_text(std::string("preset = \"best\"\n") + kMinimal, kCase).preset == Preset::Best);
  const CaseConfig thesis = parse_case_text(std::string("preset = \"thesis\"\n") + kMinimal, kCase);
  CHECK(thesis.preset == Preset::Thesis);
  CaseConfig by_hand;
  apply_preset(by_hand, Preset::Thesis);
  CHECK(by_hand.preset == Preset::Thesis);
  // simulation.precision: auto for best, double for the thesis (its runs repeat the host's where a
  // device can); a file's value wins over either.
  CHECK(parse_case_text(kMinimal, kCase).simulation.precision == Precision::Auto);
  CHECK(thesis.simulation.precision == Precision::Double);
  CHECK(by_hand.simulation.precision == Precision::Double);
  CHECK(parse_case_text(std::string("preset = \"thesis\"\n") + kMinimal + "[simulation]\nprecision = \"auto\"\n", kCase)
            .simulation.precision == Precision::Auto);
  CHECK(parse_case_text(std::string(kMinimal) + "[simulation]\nprecision = \"float\"\n", kCase).simulation.precision ==
        Precision::Float);
  // An override selects it too, and a bad value names the key and the choices.
  CHECK(parse_case_text(kMinimal, kCase, {parse_set_option("preset=thesis")}).preset == Preset::Thesis);
  CHECK_THAT(error_of(std::string("preset = \"quick\"\n") + kMinimal),
             Catch::Contains("preset must be one of best, thesis, long, fast, got 'quick'"));
  CHECK_THAT(error_of(std::string("preset = 3\n") + kMinimal), Catch::Contains("preset must be a string"));
}

TEST_CASE("the best preset is long with momentum, a compressed schedule and rule, a stronger cleanup, and fast is best",
          "[app][case]") {
  const CaseConfig best = parse_case_text(kMinimal, kCase);
  const CaseConfig long_ = parse_case_text(std::string("preset = \"long\"\n") + kMinimal, kCase);
  const CaseConfig fast = parse_case_text(std::string("preset = \"fast\"\n") + kMinimal, kCase);
  const CaseConfig thesis = parse_case_text(std::string("preset = \"thesis\"\n") + kMinimal, kCase);
  CHECK(best.preset == Preset::Best);
  CHECK(long_.preset == Preset::Long);
  CHECK(fast.preset == Preset::Fast);
  CHECK(std::string(to_string(long_.preset)) == "long");
  CHECK(std::string(to_string(fast.preset)) == "fast");
  CHECK(std::string(to_string(best.preset)) == "best");
  // What long shares with best.
  for (const CaseConfig* c : {&long_, &fast}) {
    CHECK(c->simulation.stop == StopRule::Converged);
    CHECK(c->population.enabled);
    CHECK(c->cleanup.enabled);
    CHECK(c->boundary.nodes == best.boundary.nodes);
    CHECK(c->spacing.gradation == best.spacing.gradation);
    CHECK(c->simulation.precision == Precision::Auto);
  }
  // What best (and fast, its session-9 name) set, and long's values: a CaseConfig's initializers.
  const CaseConfig initializers;
  CHECK(initializers.preset == Preset::Long);
  for (const CaseConfig* c : {&best, &fast}) {
    CHECK(c->simulation.momentum == 0.9);
    CHECK(c->population.stop == 0.15);
    CHECK(c->simulation.dt_structured == 0.016);
    CHECK_FALSE(c->simulation.dt_random.has_value());
    CHECK(c->population.insert.first == 0.7);
    CHECK(c->population.insert.last == 0.7);
    CHECK(c->population.settle == 1e-3);
    CHECK(c->population.settle_events == 2);
    CHECK(c->simulation.stop_aspect == 1.5e-3);
    CHECK(c->simulation.momentum_mix == 0.2);
    CHECK(c->simulation.stop_every == 50);
    CHECK(c->simulation.stop_window == 100);
    CHECK(c->simulation.stop_min == 150);
    CHECK(c->simulation.stop_angle == 6.0);
    CHECK(c->init.lattice_levels == 4);
    CHECK(c->init.hybrid_spread == 0.2);
    CHECK(c->cleanup.min_angle == 40.0);
    CHECK(c->cleanup.iterations == 32);
    CHECK(c->spacing.relax_scale == 1.09);
  }
  for (const CaseConfig* c : {&long_, &thesis, &initializers}) {
    CHECK(c->simulation.momentum == 0.0);
    CHECK(c->population.stop == 0.8);
    CHECK_FALSE(c->simulation.dt_structured.has_value());
    CHECK(c->population.insert.first == 0.75);
    CHECK(c->population.insert.last == 0.7);
    CHECK(c->population.settle == 0.0);
    CHECK(c->simulation.stop_aspect == 5e-4);
    CHECK(c->simulation.momentum_mix == 0.0);
    CHECK(c->simulation.stop_every == 100);
    CHECK(c->simulation.stop_window == 400);
    CHECK(c->simulation.stop_min == 400);
    CHECK(c->simulation.stop_angle == 0.25);
    CHECK(c->init.lattice_levels == 0);
    CHECK(c->init.hybrid_spread == 0.05);
    CHECK(c->cleanup.min_angle == 30.0);
    CHECK(c->cleanup.iterations == 16);
    CHECK(c->spacing.relax_scale == 1.0);
  }
  // Applying one preset after another leaves nothing of the first behind.
  CaseConfig by_hand = best;
  apply_preset(by_hand, Preset::Long);
  CHECK(by_hand.simulation.momentum == 0.0);
  CHECK(by_hand.simulation.stop_every == 100);
  CHECK(by_hand.simulation.stop_angle == 0.25);
  CHECK(by_hand.init.lattice_levels == 0);
  CHECK(by_hand.cleanup.min_angle == 30.0);
  CHECK(by_hand.spacing.relax_scale == 1.0);
  apply_preset(by_hand, Preset::Best);
  CHECK(by_hand.simulation.momentum == 0.9);
  // A key the file sets wins over the preset, and --set selects it.
  CHECK(parse_case_text(kMinimal + std::string("[simulation]\nmomentum = 0.5\n"), kCase).simulation.momentum == 0.5);
  CHECK(parse_case_text(kMinimal, kCase, {parse_set_option("preset=long")}).simulation.momentum == 0.0);
  CHECK(parse_case_text(kMinimal, kCase, {parse_set_option("preset=fast")}).simulation.momentum == 0.9);
}

TEST_CASE("geometry.curves and boundary.nodes: preset defaults, file values, overrides, errors", "[app][case]") {
  const CaseConfig best = parse_case_text(kMinimal, kCase);
  CHECK(best.geometry.curves == CurveKind::Polyline);
  CHECK(best.boundary.nodes == BoundaryNodeRule::Spacing);
  const CaseConfig thesis = parse_case_text(std::string("preset = \"thesis\"\n") + kMinimal, kCase);
  CHECK(thesis.geometry.curves == CurveKind::Polyline);
  CHECK(thesis.boundary.nodes == BoundaryNodeRule::Input);
  // A key the file sets wins over the preset; --set wins over the file.
  const std::string text =
      std::string("preset = \"thesis\"\n") + kMinimal + "curves = \"smooth\"\n[boundary]\nnodes = \"spacing\"\n";
  const CaseConfig mixed = parse_case_text(text, kCase);
  CHECK(mixed.geometry.curves == CurveKind::Smooth);  // not the default of either preset
  CHECK(mixed.boundary.nodes == BoundaryNodeRule::Spacing);
  const CaseConfig set = parse_case_text(
      text, kCase, {parse_set_option("boundary.nodes=input"), parse_set_option("geometry.curves=polyline")});
  CHECK(set.geometry.curves == CurveKind::Polyline);
  CHECK(set.boundary.nodes == BoundaryNodeRule::Input);
  CHECK_THAT(error_of(std::string(kMinimal) + "curves = \"spline\"\n"),
             Catch::Contains("demo/case.toml:3:10: geometry.curves must be one of polyline, smooth, got 'spline'"));
  CHECK_THAT(error_of(std::string(kMinimal) + "[boundary]\nnodes = 2\n"),
             Catch::Contains("boundary.nodes must be a string"));
  CHECK_THAT(error_of(kMinimal, {parse_set_option("boundary.nodes=auto")}),
             Catch::Contains("--set boundary.nodes=auto: boundary.nodes must be one of input, spacing, got 'auto'"));
  CHECK_THAT(error_of(std::string(kMinimal) + "[boundary]\nnode = \"input\"\n"),
             Catch::Contains("did you mean 'boundary.nodes'?"));
}

TEST_CASE("population keys: best runs it, thesis does not, every value is checked", "[app][case][population]") {
  const CaseConfig best = parse_case_text(kMinimal, kCase);
  CHECK(best.population.enabled);
  CHECK(best.population.every == 50);
  CHECK(best.population.start == 100);
  CHECK(best.population.stop == 0.15);
  CHECK(best.population.settle == 1e-3);
  CHECK(best.population.settle_events == 2);
  CHECK_FALSE(parse_case_text(std::string("preset = \"thesis\"\n") + kMinimal, kCase).population.enabled);
  // The file wins over the preset.
  CHECK(parse_case_text(std::string("preset = \"thesis\"\n") + kMinimal + "[population]\nenabled = true\n", kCase)
            .population.enabled);
  const CaseConfig set =
      parse_case_text(std::string(kMinimal) +
                          "[population]\nevery = 10\nstart = 50\nstop = 0.5\ninsert = [0.9, 0.8]\nmerge = 0.5\n"
                          "remove_valence = 0\nboundary = false\nboundary_split = 1.4\n"
                          "settle = 2e-3\nsettle_events = 3\n",
                      kCase);
  CHECK(set.population.settle == 2e-3);
  CHECK(set.population.settle_events == 3);
  CHECK(set.population.every == 10);
  CHECK(set.population.start == 50);
  CHECK(set.population.stop == 0.5);
  CHECK(set.population.insert.first == 0.9);
  CHECK(set.population.insert.last == 0.8);
  CHECK(set.population.merge.first == 0.5);
  CHECK(set.population.merge.last == 0.5);
  CHECK(set.population.remove_valence == 0);
  CHECK_FALSE(set.population.boundary);
  CHECK(set.population.boundary_split == 1.4);
  const std::string base = std::string(kMinimal) + "[population]\n";
  CHECK_THAT(error_of(base + "every = 0\n"),
             Catch::Contains("population.every must be in 1..") && Catch::Contains(":4:"));
  CHECK_THAT(error_of(base + "enabled = 1\n"), Catch::Contains("population.enabled must be a boolean"));
  CHECK_THAT(error_of(base + "stop = 1.5\n"), Catch::Contains("population.stop must be in (0, 1]"));
  CHECK_THAT(error_of(base + "insert = 0.5\n"), Catch::Contains("population.insert must be in (0.6, 3), got 0.5"));
  CHECK_THAT(error_of(base + "insert = [0.9]\n"), Catch::Contains("a number or [first, last]"));
  CHECK_THAT(error_of(base + "merge = [0.5, 1.2]\n"), Catch::Contains("population.merge must be in (0, 1), got 1.2"));
  CHECK_THAT(error_of(base + "merge = 0.9\n"), Catch::Contains("population.merge must stay below population.insert"));
  CHECK_THAT(error_of(base + "remove_valence = 6\n"), Catch::Contains("population.remove_valence must be in 0..5"));
  CHECK_THAT(error_of(base + "boundary_split = 1.1\n"), Catch::Contains("population.boundary_split must be in"));
  CHECK_THAT(error_of(base + "settle = 0.5\n"), Catch::Contains("population.settle must be in [0, 0.1]"));
  CHECK_THAT(error_of(base + "settle = -1e-3\n"), Catch::Contains("population.settle must be in [0, 0.1]"));
  CHECK_THAT(error_of(base + "settle_events = 4\n"), Catch::Contains("population.settle_events must be in 1..3"));
  CHECK_THAT(error_of(base + "settle_events = 0\n"), Catch::Contains("population.settle_events must be in 1..3"));
  CHECK_THAT(error_of(base + "evry = 3\n"), Catch::Contains("did you mean 'population.every'"));
  CHECK_THAT(error_of(kMinimal, {parse_set_option("population.start=-1")}),
             Catch::Contains("--set population.start=-1") && Catch::Contains("population.start must be in 0.."));
}

TEST_CASE("cleanup keys: best cleans, thesis does not, a key wins over the preset, bad values are refused",
          "[app][case]") {
  const CaseConfig best = parse_case_text(kMinimal, kCase);
  CHECK(best.cleanup.enabled);
  CHECK(best.cleanup.min_angle == 40.0);
  CHECK(best.cleanup.iterations == 32);
  CHECK(best.cleanup.topology);
  CHECK(best.cleanup.split_boundary);
  CHECK_FALSE(parse_case_text(std::string("preset = \"thesis\"\n") + kMinimal, kCase).cleanup.enabled);
  const CaseConfig on = parse_case_text(std::string("preset = \"thesis\"\n") + kMinimal, kCase,
                                        {parse_set_option("cleanup.enabled=true")});
  CHECK(on.cleanup.enabled);
  CHECK(on.preset == Preset::Thesis);
  const CaseConfig set = parse_case_text(
      std::string(kMinimal) + "[cleanup]\nmin_angle = 33.5\niterations = 4\ntopology = false\nsplit_boundary = false\n",
      kCase);
  CHECK(set.cleanup.min_angle == 33.5);
  CHECK(set.cleanup.iterations == 4);
  CHECK_FALSE(set.cleanup.topology);
  CHECK_FALSE(set.cleanup.split_boundary);
  CHECK_FALSE(best.cleanup.sharp_corners);
  CHECK(best.cleanup.polish == 0);
  const CaseConfig polished =
      parse_case_text(std::string(kMinimal) + "[cleanup]\nsharp_corners = true\npolish = 7\n", kCase);
  CHECK(polished.cleanup.sharp_corners);
  CHECK(polished.cleanup.polish == 7);
  CHECK_THAT(error_of(std::string(kMinimal) + "[cleanup]\npolish = -1\n"),
             Catch::Contains("cleanup.polish must be in 0..1000, got -1"));
  CHECK(best.cleanup.threads == 0);
  CHECK(parse_case_text(std::string(kMinimal) + "[cleanup]\nthreads = 3\n", kCase).cleanup.threads == 3);
  CHECK_THAT(error_of(std::string(kMinimal) + "[cleanup]\nthreads = -1\n"),
             Catch::Contains("cleanup.threads must be in 0..256, got -1"));
  CHECK(best.cleanup.small_strip_vertices == 0);
  CHECK(parse_case_text(std::string(kMinimal) + "[cleanup]\nsmall_strip_vertices = 1000\n", kCase)
            .cleanup.small_strip_vertices == 1000);
  CHECK_THAT(error_of(std::string(kMinimal) + "[cleanup]\nsmall_strip_vertices = -1\n"),
             Catch::Contains("cleanup.small_strip_vertices must be in 0..1000000, got -1"));
  CHECK_THAT(error_of(std::string(kMinimal) + "[cleanup]\nmin_angle = 60\n"),
             Catch::Contains("case.toml:4:13: cleanup.min_angle must be in (0, 60) degrees, got 60"));
  CHECK_THAT(error_of(kMinimal, {parse_set_option("cleanup.min_angle=0")}),
             Catch::Contains("--set cleanup.min_angle=0: cleanup.min_angle must be in (0, 60) degrees, got 0"));
  CHECK_THAT(error_of(std::string(kMinimal) + "[cleanup]\niterations = 0\n"),
             Catch::Contains("case.toml:4:14: cleanup.iterations must be in 1..1000, got 0"));
  CHECK_THAT(error_of(std::string(kMinimal) + "[cleanup]\nenabled = \"yes\"\n"),
             Catch::Contains("cleanup.enabled must be a boolean (true or false), got string"));
  CHECK_THAT(error_of(std::string(kMinimal) + "[cleanup]\nmin_angel = 20\n"),
             Catch::Contains("unknown key 'cleanup.min_angel'; did you mean 'cleanup.min_angle'?"));
}

TEST_CASE("cleanup trial budget keys: the presets' values, a file's values win, ranges", "[app][case]") {
  // long (and so the thesis' cleanup when a file turns it on) keeps CleanupOptions' bound.
  const CleanupOptions options;
  const CaseConfig long_preset = parse_case_text(std::string("preset = \"long\"\n") + kMinimal, kCase);
  CHECK(long_preset.cleanup.trials_per_triangle == options.trials_per_triangle);
  CHECK(static_cast<double>(long_preset.cleanup.min_trials) == options.min_trials);
  const CaseConfig thesis = parse_case_text(std::string("preset = \"thesis\"\n") + kMinimal, kCase);
  CHECK(thesis.cleanup.trials_per_triangle == options.trials_per_triangle);
  CHECK(static_cast<double>(thesis.cleanup.min_trials) == options.min_trials);
  // best: a smaller first budget (app/config/presets.cpp).
  const CaseConfig best = parse_case_text(kMinimal, kCase);
  CHECK(best.cleanup.trials_per_triangle == 0.05);
  CHECK(best.cleanup.min_trials == 2000);
  const CaseConfig set =
      parse_case_text(std::string(kMinimal) + "[cleanup]\ntrials_per_triangle = 1.5\nmin_trials = 300\n", kCase);
  CHECK(set.cleanup.trials_per_triangle == 1.5);
  CHECK(set.cleanup.min_trials == 300);
  CHECK_THAT(error_of(std::string(kMinimal) + "[cleanup]\ntrials_per_triangle = -1\n"),
             Catch::Contains("cleanup.trials_per_triangle must be in [0, 100], got -1"));
  CHECK_THAT(error_of(std::string(kMinimal) + "[cleanup]\nmin_trials = -5\n"),
             Catch::Contains("cleanup.min_trials must be in 0..1000000000, got -5"));
  CHECK_THAT(error_of(std::string(kMinimal) + "[cleanup]\nmin_trials = 2.5\n"),
             Catch::Contains("cleanup.min_trials must be"));
}

TEST_CASE("case file: cleanup.settle per preset, set and checked", "[app][case]") {
  // long and thesis run every iteration; best ends once an iteration only lowers the mean aspect ratio
  // by less than 1e-6 (app/config/presets.cpp; docs/cleanup.md, "Settling").
  CHECK(parse_case_text(std::string("preset = \"long\"\n") + kMinimal, kCase).cleanup.settle == 0.0);
  CHECK(parse_case_text(std::string("preset = \"thesis\"\n") + kMinimal, kCase).cleanup.settle == 0.0);
  CHECK(parse_case_text(kMinimal, kCase).cleanup.settle == 1e-6);
  CHECK(parse_case_text(std::string(kMinimal) + "[cleanup]\nsettle = 0\n", kCase).cleanup.settle == 0.0);
  CHECK(parse_case_text(std::string(kMinimal) + "[cleanup]\nsettle = 2e-4\n", kCase).cleanup.settle == 2e-4);
  CHECK_THAT(error_of(std::string(kMinimal) + "[cleanup]\nsettle = 0.5\n"),
             Catch::Contains("cleanup.settle must be in [0, 0.01], got 0.5"));
}

TEST_CASE("edit distance", "[app][case]") {
  CHECK(edit_distance("", "abc") == 3);
  CHECK(edit_distance("kitten", "sitting") == 3);
  CHECK(edit_distance("simulaton", "simulation") == 1);
  CHECK(edit_distance("same", "same") == 0);
}

TEST_CASE("spacing.file selects a background-mesh field and its keys are checked", "[app][case]") {
  const std::string base = kMinimal;
  // A file alone selects the mesh field; the path is relative to the case file; the array defaults to q.
  CaseConfig c = parse_case_text(base + "[spacing]\nfile = \"data/flow.vtu\"\n", kCase);
  CHECK(c.spacing.field == SpacingKind::Mesh);
  CHECK(c.spacing.file == fs::path("/cases/demo/data/flow.vtu"));
  CHECK(c.spacing.array == "q");
  c = parse_case_text(base + "[spacing]\nfield = \"mesh\"\nfile = \"/abs/f.MSH\"\narray = \"h\"\n", kCase);
  CHECK(c.spacing.field == SpacingKind::Mesh);
  CHECK(c.spacing.file == fs::path("/abs/f.MSH"));
  CHECK(c.spacing.array == "h");
  // Given by --set, a relative path is relative to the current directory, where it was typed.
  c = parse_case_text(base, kCase,
                      {parse_set_option("spacing.file=run1/mesh.vtu"), parse_set_option("spacing.array=2")});
  CHECK(c.spacing.field == SpacingKind::Mesh);
  CHECK(c.spacing.file == fs::path("run1/mesh.vtu"));
  CHECK(c.spacing.array == "2");  // a number given to a string key is its text
  // Contradictions and bad values.
  CHECK(error_of(base + "[spacing]\nfield = \"mesh\"\n")
            .find("spacing.file (a .vtu or .msh background mesh) is missing") != std::string::npos);
  CHECK(error_of(base + "[spacing]\nfile = \"f.vtu\"\nexpression = \"1\"\n")
            .find("both set; choose one with spacing.field") != std::string::npos);
  CHECK(error_of(base + "[spacing]\nfield = \"boundary\"\nfile = \"f.vtu\"\n")
            .find("spacing.file is set but spacing.field is 'boundary'") != std::string::npos);
  CHECK(error_of(base + "[spacing]\nfield = \"mesh\"\nfile = \"f.vtu\"\nexpression = \"1\"\n")
            .find("spacing.expression is set but spacing.field is 'mesh'") != std::string::npos);
  CHECK(error_of(base + "[spacing]\narray = \"q\"\n").find("spacing.array is set but spacing.field is 'boundary'") !=
        std::string::npos);
  CHECK(error_of(base + "[spacing]\nfile = \"f.vtu\"\narray = \"\"\n").find("spacing.array must not be empty") !=
        std::string::npos);
  CHECK(error_of(base + "[spacing]\nfile = \"f.stl\"\n").find(":4:8: spacing.file 'f.stl' must be a .vtu or .msh") !=
        std::string::npos);
  CHECK(error_of(base + "[spacing]\nfield = \"data\"\n")
            .find("spacing.field must be one of boundary, expression, mesh") != std::string::npos);
}

TEST_CASE("spacing pipeline keys: best and thesis defaults, values and ranges", "[app][case]") {
  const CaseConfig best = parse_case_text(kMinimal, kCase);
  CHECK(best.spacing.scale == 1.0);
  CHECK(best.spacing.gradation == 0.2);
  CHECK(best.spacing.rows_in_gap == 2.0);
  CHECK(best.spacing.curvature_angle == 10.0);
  CHECK_FALSE(best.output.spacing_picture);
  // The thesis' field is eq. 3.6 alone.
  const CaseConfig thesis = parse_case_text(std::string("preset = \"thesis\"\n") + kMinimal, kCase);
  CHECK(thesis.spacing.scale == 1.0);
  CHECK(thesis.spacing.gradation == 0.0);
  CHECK(thesis.spacing.rows_in_gap == 0.0);
  CHECK(thesis.spacing.curvature_angle == 0.0);
  // Keys the file sets win over the preset.
  const CaseConfig set = parse_case_text(std::string("preset = \"thesis\"\n") + kMinimal +
                                             "[spacing]\nscale = 0.5\ngradation = 0.3\nrows_in_gap = 3\n"
                                             "curvature_angle = 12.5\nrelax_scale = 1.25\n[output]\n"
                                             "spacing_picture = true\n",
                                         kCase);
  CHECK(set.spacing.scale == 0.5);
  CHECK(set.spacing.relax_scale == 1.25);
  CHECK(parse_case_text(kMinimal, kCase, {parse_set_option("spacing.relax_scale=1")}).spacing.relax_scale == 1.0);
  CHECK(set.spacing.gradation == 0.3);
  CHECK(set.spacing.rows_in_gap == 3.0);
  CHECK(set.spacing.curvature_angle == 12.5);
  CHECK(set.output.spacing_picture);
  const std::string base = std::string(kMinimal) + "[spacing]\n";
  CHECK_THAT(error_of(base + "scale = 0\n"), Catch::Contains(":4:9: spacing.scale must be > 0, got 0"));
  CHECK_THAT(error_of(base + "relax_scale = 2.5\n"),
             Catch::Contains(":4:15: spacing.relax_scale must be in [0.5, 2], got 2.5"));
  CHECK_THAT(error_of(base + "gradation = -0.1\n"),
             Catch::Contains("spacing.gradation must be in [0, 10] (0 = off), got -0.1"));
  CHECK_THAT(error_of(base + "rows_in_gap = 0.5\n"),
             Catch::Contains("spacing.rows_in_gap must be 0 (off) or in [1, 100], got 0.5"));
  CHECK_THAT(error_of(base + "curvature_angle = 91\n"),
             Catch::Contains("spacing.curvature_angle must be in [0, 90] degrees (0 = off), got 91"));
  CHECK_THAT(error_of(base + "gradation = \"steep\"\n"),
             Catch::Contains("spacing.gradation must be a number, got string"));
  CHECK_THAT(error_of(std::string(kMinimal) + "[output]\nspacing_picture = 1\n"),
             Catch::Contains("output.spacing_picture must be a boolean"));
  CHECK_THAT(error_of(base + "gradiation = 0.2\n"), Catch::Contains("did you mean 'spacing.gradation'?"));
}

TEST_CASE("spacing background keys: the builder's defaults but best's interior cap, a file's values win, ranges",
          "[app][case]") {
  const BackgroundOptions builder;
  for (const char* preset : {"thesis", "best", "fast", "long"}) {
    const CaseConfig c = parse_case_text(fmt::format("preset = \"{}\"\n", preset) + kMinimal, kCase);
    INFO("preset " << preset);
    const bool best = std::string(preset) == "best" || std::string(preset) == "fast";
    CHECK(c.spacing.background_tolerance == builder.tolerance);
    CHECK(c.spacing.background_min_side == (best ? 0.5 : builder.min_side_fraction));
    CHECK(c.spacing.background_boundary_min_side == builder.boundary_min_side_fraction);
  }
  // Applying one preset after another leaves nothing of the first behind.
  CaseConfig by_hand = parse_case_text(kMinimal, kCase);
  apply_preset(by_hand, Preset::Long);
  CHECK(by_hand.spacing.background_min_side == builder.min_side_fraction);
  apply_preset(by_hand, Preset::Best);
  CHECK(by_hand.spacing.background_min_side == 0.5);
  const CaseConfig set = parse_case_text(std::string(kMinimal) +
                                             "[spacing]\nbackground_tolerance = 0.03\nbackground_min_side = 0.5\n"
                                             "background_boundary_min_side = 0.125\n",
                                         kCase);
  CHECK(set.spacing.background_tolerance == 0.03);
  CHECK(set.spacing.background_min_side == 0.5);
  CHECK(set.spacing.background_boundary_min_side == 0.125);
  // They reach the background builder.
  const SpacingOptions o = spacing_options(set);
  CHECK(o.background.tolerance == 0.03);
  CHECK(o.background.min_side_fraction == 0.5);
  CHECK(o.background.boundary_min_side_fraction == 0.125);
  const std::string base = std::string(kMinimal) + "[spacing]\n";
  CHECK_THAT(error_of(base + "background_tolerance = 0\n"),
             Catch::Contains("spacing.background_tolerance must be in (0, 1], got 0"));
  CHECK_THAT(error_of(base + "background_min_side = 2\n"),
             Catch::Contains("spacing.background_min_side must be in (0, 1], got 2"));
  CHECK_THAT(error_of(base + "background_boundary_min_side = -0.5\n"),
             Catch::Contains("spacing.background_boundary_min_side must be in (0, 1], got -0.5"));
}

TEST_CASE("simulation.stop: best converges, thesis counts, a key wins over the preset, bad values are refused",
          "[app][case][convergence]") {
  CHECK(parse_case_text(kMinimal, kCase).simulation.stop == StopRule::Converged);
  const std::string thesis = std::string("preset = \"thesis\"\n") + kMinimal;
  CHECK(parse_case_text(thesis, kCase).simulation.stop == StopRule::Iterations);
  CHECK(parse_case_text(thesis + "[simulation]\nstop = \"converged\"\n", kCase).simulation.stop == StopRule::Converged);
  CHECK(parse_case_text(kMinimal, kCase, {parse_set_option("simulation.stop=iterations")}).simulation.stop ==
        StopRule::Iterations);
  CHECK_THAT(error_of(std::string(kMinimal) + "[simulation]\nstop = \"settled\"\n"),
             Catch::Contains("case.toml:4:8:") && Catch::Contains("simulation.stop") && Catch::Contains("converged") &&
                 Catch::Contains("iterations"));
  CHECK_THAT(error_of(std::string(kMinimal) + "[simulation]\nstop = 3\n"), Catch::Contains("simulation.stop"));
  CHECK_THAT(error_of(kMinimal, {parse_set_option("simulation.stop=never")}),
             Catch::Contains("--set simulation.stop=never") && Catch::Contains("simulation.stop"));
}

TEST_CASE("simulation.stop_aspect / stop_angle: the convergence rule's tolerances, checked",
          "[app][case][convergence]") {
  const CaseConfig best = parse_case_text(kMinimal, kCase);
  CHECK(best.simulation.stop_aspect == 1.5e-3);
  CHECK(best.simulation.stop_angle == 6.0);
  const CaseConfig set =
      parse_case_text(std::string(kMinimal) + "[simulation]\nstop_aspect = 2e-3\nstop_angle = 0.5\n", kCase);
  CHECK(set.simulation.stop_aspect == 2e-3);
  CHECK(set.simulation.stop_angle == 0.5);
  CHECK(parse_case_text(kMinimal, kCase, {parse_set_option("simulation.stop_aspect=0")}).simulation.stop_aspect == 0.0);
  CHECK_THAT(error_of(std::string(kMinimal) + "[simulation]\nstop_aspect = 0.2\n"),
             Catch::Contains("simulation.stop_aspect must be in [0, 0.1], got 0.2") && Catch::Contains(":4:"));
  CHECK_THAT(error_of(std::string(kMinimal) + "[simulation]\nstop_angle = -1\n"),
             Catch::Contains("simulation.stop_angle must be in [0, 10], got -1"));
  CHECK_THAT(error_of(kMinimal, {parse_set_option("simulation.stop_angle=nan")}),
             Catch::Contains("simulation.stop_angle"));
}

TEST_CASE("simulation.stop_every / stop_window / stop_min: the rule's interval, window and earliest stop",
          "[app][case][convergence]") {
  const CaseConfig set = parse_case_text(
      std::string(kMinimal) + "[simulation]\nstop_every = 25\nstop_window = 150\nstop_min = 0\n", kCase);
  CHECK(set.simulation.stop_every == 25);
  CHECK(set.simulation.stop_window == 150);
  CHECK(set.simulation.stop_min == 0);
  CHECK_THAT(error_of(std::string(kMinimal) + "[simulation]\nstop_every = 0\n"),
             Catch::Contains("simulation.stop_every must be in [1, 1000000], got 0"));
  CHECK_THAT(error_of(std::string(kMinimal) + "[simulation]\nstop_min = -5\n"),
             Catch::Contains("simulation.stop_min must be in [0, 1000000], got -5"));
  CHECK_THAT(error_of(std::string(kMinimal) + "[simulation]\nstop_window = 2.5\n"),
             Catch::Contains("simulation.stop_window must be an integer"));
  // The window starts at a measurement, so it is a multiple of the interval (best's 100 is not of 40).
  CHECK_THAT(error_of(std::string(kMinimal) + "[simulation]\nstop_every = 40\n"),
             Catch::Contains("simulation.stop_window must be a multiple of simulation.stop_every (40), got 100") &&
                 Catch::Contains(":4:"));
}
