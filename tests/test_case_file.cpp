// Tests of case-file parsing: a full example, defaults, every error kind (with line numbers and
// suggestions) and --set overrides.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include "app/case_file.hpp"
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
  CHECK(c.init.method == InitMethod::Structured);
  CHECK(c.init.seed == 1);
  CHECK(c.init.total == 0);
  CHECK(c.simulation.iterations == 2000);
  CHECK_FALSE(c.simulation.dt_structured.has_value());
  CHECK_FALSE(c.simulation.dt_random.has_value());
  CHECK(c.simulation.cutoff == 1.5);
  CHECK(c.simulation.lj_a == 15.0);
  CHECK(c.simulation.device == "auto");
  CHECK(c.simulation.precision == Precision::Double);
  CHECK(c.output.formats == std::vector<std::string>{"msh", "vtu", "png"});
  CHECK_FALSE(c.output.tree_overlay);
  CHECK(c.output.views.empty());
  CHECK(c.max_nodes == 20'000'000);
}

TEST_CASE("a single dt_initial applies to both methods, and an expression alone selects the expression field",
          "[app][case]") {
  const CaseConfig c = parse_case_text(std::string(kMinimal) +
                                           "[simulation]\ndt_initial = 0.009\n[spacing]\nexpression = \"2\"\n",
                                       kCase);
  CHECK(c.simulation.dt_for(InitMethod::Structured) == 0.009);
  CHECK(c.simulation.dt_for(InitMethod::Random) == 0.009);
  CHECK(c.spacing.field == SpacingKind::Expression);
}

TEST_CASE("TOML syntax errors name file, line and column", "[app][case]") {
  const std::string m = error_of("[geometry]\nfiles = [\"a.crv\"]\n[simulation]\niterations = = 3\n");
  CHECK(m.rfind("/cases/demo/case.toml:4:", 0) == 0);
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
  CHECK(error_of(base + "[simulation]\ncutoff = 0\n").find("simulation.cutoff must be > 0, got 0") != std::string::npos);
  CHECK(error_of(base + "[simulation]\ndt_initial = -0.5\n").find("simulation.dt_initial must be > 0, got -0.5") !=
        std::string::npos);
  CHECK(error_of(base + "[simulation]\ndt_initial = { random = 0 }\n")
            .find("simulation.dt_initial.random must be > 0") != std::string::npos);
  CHECK(error_of(base + "[init]\nmethod = \"hexagonal\"\n")
            .find("init.method must be one of structured, random, got 'hexagonal'") != std::string::npos);
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

TEST_CASE("errors in overrides name the option, not the case file", "[app][case]") {
  CHECK(error_of(kMinimal, {parse_set_option("simulation.iterations=abc")}) ==
        "--set simulation.iterations=abc: simulation.iterations must be an integer, got string");
  CHECK(error_of(kMinimal, {parse_set_option("simulaton.cutoff=2")}) ==
        "--set simulaton.cutoff=2: unknown key 'simulaton.cutoff'; did you mean 'simulation.cutoff'?");
  CHECK(error_of(kMinimal, {{"simulation.cutoff", "-1", "--cutoff -1"}}) ==
        "--cutoff -1: simulation.cutoff must be > 0, got -1");
  CHECK(error_of(kMinimal, {parse_set_option("geometry.files.x=1")}).find("'geometry.files' is not a table (it is an array)") !=
        std::string::npos);
  CHECK(error_of(kMinimal, {parse_set_option("geometry.files.x=1")}).find("not a table") != std::string::npos);
  CHECK_THROWS_AS(parse_set_option("novalue"), InputError);
}

TEST_CASE("appending overrides (--view) append views", "[app][case]") {
  CaseOverride view{"output.views", "{ window = [0, 0, 1, 2] }", "--view 0,0,1,2", true};
  const CaseConfig c = parse_case_text(std::string(kMinimal) + "[output]\nviews = [{ name = \"a\", window = [0,0,1,1] }]\n",
                                       kCase, {view});
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
  // An override selects it too, and a bad value names the key and the choices.
  CHECK(parse_case_text(kMinimal, kCase, {parse_set_option("preset=thesis")}).preset == Preset::Thesis);
  CHECK_THAT(error_of(std::string("preset = \"fast\"\n") + kMinimal),
             Catch::Contains("preset must be one of best, thesis, got 'fast'"));
  CHECK_THAT(error_of(std::string("preset = 3\n") + kMinimal), Catch::Contains("preset must be a string"));
}

TEST_CASE("cleanup keys: best cleans, thesis does not, a key wins over the preset, bad values are refused",
          "[app][case]") {
  const CaseConfig best = parse_case_text(kMinimal, kCase);
  CHECK(best.cleanup.enabled);
  CHECK(best.cleanup.min_angle == 30.0);
  CHECK(best.cleanup.iterations == 16);
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

TEST_CASE("edit distance", "[app][case]") {
  CHECK(edit_distance("", "abc") == 3);
  CHECK(edit_distance("kitten", "sitting") == 3);
  CHECK(edit_distance("simulaton", "simulation") == 1);
  CHECK(edit_distance("same", "same") == 0);
}
