// Tests of the pdmesh command itself (PDMESH_BINARY): help, exit codes, messages, and that a
// failed run leaves no output behind while a good run writes every initial output atomically.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>
#include <vector>

#include "io/mesh_formats.hpp"
#include "io/text_file.hpp"
#include "nodes/node_file.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;

namespace {

using pdmesh_test::Result;
Result run(const std::string& arguments) { return pdmesh_test::run_pdmesh(arguments); }

using pdmesh_test::fresh_dir;

std::size_t read_node_file_size(const fs::path& p) { return pdmesh::read_node_file(p).nodes.size(); }

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// A 2 x 1 rectangle as one closed .crv curve with points every 0.25.
void write_rectangle(const fs::path& file) {
  std::ofstream out(file);
  out << "# rectangle\n25\n";
  for (int k = 0; k <= 8; ++k) out << 0.25 * k << " 0\n";
  for (int k = 1; k <= 4; ++k) out << "2 " << 0.25 * k << "\n";
  for (int k = 7; k >= 0; --k) out << 0.25 * k << " 1\n";
  for (int k = 3; k >= 0; --k) out << "0 " << 0.25 * k << "\n";
}

}  // namespace

TEST_CASE("pdmesh --help and pdmesh mesh --help list the commands and every option", "[cli]") {
  const Result top = run("--help");
  CHECK(top.status == 0);
  CHECK(contains(top.output, "mesh"));
  CHECK(contains(top.output, "--version"));
  const Result mesh = run("mesh --help");
  CHECK(mesh.status == 0);
  for (const char* option :
       {"INPUT", "--out", "--set", "--iterations", "--dt", "--cutoff", "--method", "--seed", "--total", "--device",
        "--precision", "--formats", "--view", "--tree", "--quiet", "--max-nodes"}) {
    INFO(option);
    CHECK(contains(mesh.output, option));
  }
}

TEST_CASE("pdmesh --version prints the version", "[cli]") {
  const Result r = run("--version");
  CHECK(r.status == 0);
  CHECK(contains(r.output, std::string("pdmesh ") + PDMESH_VERSION));
}

TEST_CASE("command-line errors exit with status 2", "[cli]") {
  const Result unknown = run("mesh x.toml --out /tmp/x --no-such-option");
  CHECK(unknown.status == 2);
  CHECK(contains(unknown.output, "--no-such-option"));
  CHECK(run("").status == 2);                   // no command
  CHECK(run("frobnicate").status == 2);         // no such command
  CHECK(run("mesh x.crv").status == 2);         // --out missing
  CHECK(run("mesh --out /tmp/x").status == 2);  // INPUT missing
  // Parse errors carry the prefix of every other input error.
  for (const char* arguments :
       {"", "mesh x.crv", "mesh --out /tmp/x", "quality", "mesh x.toml --out /tmp/x --iterations abc"}) {
    INFO(arguments);
    const Result r = run(arguments);
    CHECK(r.status == 2);
    CHECK(r.output.rfind("pdmesh: error: ", 0) == 0);
  }
  CHECK(run("mesh x.crv").output.rfind("pdmesh: error: --out is required\n", 0) == 0);
}

TEST_CASE("a missing input file exits 2 naming the file and writes nothing", "[cli]") {
  const fs::path dir = fresh_dir("missing");
  const fs::path out = dir / "out";
  const Result r = run("mesh '" + (dir / "no_such_case.toml").string() + "' --out '" + out.string() + "'");
  CHECK(r.status == 2);
  CHECK(contains(r.output, "pdmesh: error: "));
  CHECK(contains(r.output, "no_such_case.toml"));
  CHECK_FALSE(fs::exists(out));
  CHECK(std::distance(fs::directory_iterator(dir), fs::directory_iterator()) == 0);
  fs::remove_all(dir);
}

TEST_CASE("case-file errors exit 2 with FILE:LINE and the suggestion, before any output", "[cli]") {
  const fs::path dir = fresh_dir("badcase");
  write_rectangle(dir / "rect.crv");
  std::ofstream(dir / "case.toml") << "[geometry]\nfiles = [\"rect.crv\"]\n[simulation]\niteratons = 4\n";
  const fs::path out = dir / "out";
  Result r = run("mesh '" + (dir / "case.toml").string() + "' --out '" + out.string() + "'");
  CHECK(r.status == 2);
  CHECK(contains(r.output, "case.toml:4:1: unknown key 'simulation.iteratons'; did you mean 'simulation.iterations'?"));
  CHECK_FALSE(fs::exists(out));
  // The file is checked whole: a wrong value in it is an error even where an option replaces it.
  std::ofstream(dir / "typed.toml") << "[geometry]\nfiles = [\"rect.crv\"]\n[simulation]\niterations = \"many\"\n";
  r = run("mesh '" + (dir / "typed.toml").string() + "' --out '" + out.string() + "' --iterations 2");
  CHECK(r.status == 2);
  CHECK(contains(r.output, "typed.toml:4:14: simulation.iterations must be an integer, got string"));
  CHECK_FALSE(fs::exists(out));
  r = run("mesh '" + (dir / "rect.crv").string() + "' --out '" + out.string() + "' --iterations -3");
  CHECK(r.status == 2);
  CHECK(contains(r.output, "--iterations -3: simulation.iterations must be >= 0, got -3"));
  r = run("mesh '" + (dir / "rect.crv").string() + "' --out '" + out.string() + "' --view 0,0,1");
  CHECK(r.status == 2);
  CHECK(contains(r.output, "window must have 4 numbers, got 3"));
  CHECK_FALSE(fs::exists(out));
  fs::remove_all(dir);
}

TEST_CASE("several geometry files make one geometry, and a case file takes no second input", "[cli]") {
  const fs::path dir = fresh_dir("multi");
  write_rectangle(dir / "rect.crv");
  // A hole: a 0.5 x 0.5 square inside the rectangle, in its own file.
  std::ofstream(dir / "hole.crv") << "5\n0.75 0.25\n1.25 0.25\n1.25 0.75\n0.75 0.75\n0.75 0.25\n";
  std::ofstream(dir / "case.toml") << "[geometry]\nfiles = [\"rect.crv\"]\n";
  const fs::path out = dir / "out";
  Result r = run("mesh '" + (dir / "rect.crv").string() + "' '" + (dir / "hole.crv").string() + "' --out '" +
                 out.string() + "' --iterations 0 --formats msh");
  CHECK(r.status == 0);
  CHECK(contains(r.output, "geometry: 2 curves"));
  CHECK(contains(r.output, "2 loops"));
  r = run("mesh '" + (dir / "case.toml").string() + "' '" + (dir / "hole.crv").string() + "' --out '" +
          (dir / "out2").string() + "'");
  CHECK(r.status == 2);
  CHECK(contains(r.output, "a case file is meshed alone"));
  r = run("mesh '" + (dir / "rect.crv").string() + "' '" + (dir / "case.toml").string() + "' --out '" +
          (dir / "out2").string() + "'");
  CHECK(r.status == 2);
  CHECK(contains(r.output, "expected a .crv, .dat, .poly, .geojson, .json or .shp geometry file"));
  CHECK_FALSE(fs::exists(dir / "out2"));
  fs::remove_all(dir);
}

TEST_CASE("the node limit (--max-nodes) refuses a case by its estimate", "[cli]") {
  const fs::path dir = fresh_dir("limit");
  write_rectangle(dir / "rect.crv");
  // relax_scale 1: at best's 1.09 this small rectangle's coarser root cells all touch the boundary,
  // which the level count leaves out, and the refusal comes from the finished base tree instead.
  const Result r = run("mesh '" + (dir / "rect.crv").string() + "' --out '" + (dir / "out").string() +
                       "' --max-nodes 3 --set spacing.relax_scale=1");
  CHECK(r.status == 2);
  CHECK(contains(r.output, "estimate"));
  // The best preset refuses by the base field's quadtree, on the level where its count passes the
  // limit, before the tree is finished or the limits refine it.
  CHECK(contains(r.output, "already on level"));
  CHECK(contains(r.output, "--max-nodes 3"));
  CHECK_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

TEST_CASE("pdmesh mesh writes every stage's files: initial, history, final, mesh, quality", "[cli]") {
  const fs::path dir = fresh_dir("good");
  write_rectangle(dir / "rect.crv");
  const fs::path out = dir / "out" / "nested";
  const Result r = run("mesh '" + (dir / "rect.crv").string() + "' --out '" + out.string() +
                       "' --tree --view corner=0,0,0.5,0.5 --view 1,0,2,1 --iterations 20 --check");
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(contains(r.output, "initial distribution: "));
  CHECK(contains(r.output, "by hexagonal packing"));
  CHECK(contains(r.output, "mesh check (triangulation): passed"));
  CHECK(contains(r.output, "cleanup: "));                          // the best preset cleans the mesh ...
  CHECK(contains(r.output, "mesh check (cleaned mesh): passed"));  // ... and --check checks the result too
  CHECK(contains(r.output, "Minimum Corner Jacobian"));            // the quality table
  CHECK(contains(r.output, "Cleanup: min angle"));
  // The default formats (msh, vtu, png): no SVG pictures (svg is opt-in).
  const std::vector<std::string> expected = {
      "initial.nodes", "initial.png", "initial_corner.png", "initial_view2.png", "history.csv",   "history.png",
      "final.nodes",   "final.png",   "final_corner.png",   "final_view2.png",   "mesh.msh",      "mesh.vtu",
      "quality.json",  "mesh.nodes",  "mesh.png",           "mesh_corner.png",   "mesh_view2.png"};
  for (const std::string& f : expected) {
    INFO(f);
    CHECK(fs::is_regular_file(out / f));
  }
  // Exactly those files: no temporaries left behind.
  CHECK(std::distance(fs::directory_iterator(out), fs::directory_iterator()) ==
        static_cast<std::ptrdiff_t>(expected.size()));
  const pdmesh::Mesh mesh = pdmesh::read_mesh(out / "mesh.msh");
  CHECK(mesh.triangles.size() > 0);
  CHECK(mesh.curve_names == std::vector<std::string>{"curve0"});
  const pdmesh::NodeFile nodes = pdmesh::read_node_file(out / "initial.nodes");
  CHECK(nodes.nodes.count(pdmesh::NodeKind::Interior) > 0);
  // Placed by 1.09 x the field (spacing.relax_scale): 22 stations on the rectangle's 24 segments of q.
  CHECK(nodes.nodes.count(pdmesh::NodeKind::Fixed) + nodes.nodes.count(pdmesh::NodeKind::Boundary) == 22);
  CHECK(nodes.curve_names == std::vector<std::string>{"curve0"});
  // A case directory stands for its case.toml; --quiet silences progress.
  std::ofstream(dir / "case.toml") << "name = \"rect\"\n[geometry]\nfiles = [\"rect.crv\"]\n";
  const Result quiet = run("mesh '" + dir.string() + "' --out '" + out.string() + "' -q");
  CHECK(quiet.status == 0);
  CHECK(quiet.output.empty());
  CHECK(read_node_file_size(out / "initial.nodes") == nodes.nodes.size());
  fs::remove_all(dir);
}

TEST_CASE("pdmesh mesh: a picture that cannot be written is refused before the run starts", "[cli]") {
  // Every output path is checked before any work (app/pipeline/output_guard): a directory where a picture goes
  // ends the run with exit 2 naming it, and nothing is written.
  for (const char* device : {"host", "auto"}) {
    INFO(device);
    const fs::path dir = fresh_dir(std::string("bad_picture_") + device);
    write_rectangle(dir / "rect.crv");
    const fs::path out = dir / "out";
    fs::create_directories(out / "initial_corner.png");  // a directory where the picture goes
    const Result r = run("mesh '" + (dir / "rect.crv").string() + "' --out '" + out.string() +
                         "' --view corner=0,0,0.5,0.5 --iterations 20 --device " + device);
    INFO(r.output);
    CHECK(r.status == 2);
    CHECK(contains(r.output, "initial_corner.png"));
    CHECK(std::distance(fs::directory_iterator(out), fs::directory_iterator()) == 1);
    CHECK(fs::is_directory(out / "initial_corner.png"));
    fs::remove_all(dir);
  }
}

TEST_CASE("pdmesh mesh --plot-spacing writes spacing.png and one picture per view, and the field is reported",
          "[cli]") {
  const fs::path dir = fresh_dir("spacing");
  write_rectangle(dir / "rect.crv");
  const fs::path out = dir / "out";
  const Result r = run("mesh '" + (dir / "rect.crv").string() + "' --out '" + out.string() +
                       "' --iterations 0 --plot-spacing --view corner=0,0,0.5,0.5 --formats msh");
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(contains(r.output, "spacing field: "));
  CHECK(contains(r.output, "gradation 0.2, rows in gap 2"));
  for (const char* f : {"spacing.png", "spacing_corner.png"}) {
    INFO(f);
    REQUIRE(fs::is_regular_file(out / f));
    std::ifstream png(out / f, std::ios::binary);
    char magic[8] = {};
    png.read(magic, 8);
    CHECK(std::string(magic + 1, 3) == "PNG");
  }
  // The thesis preset reports eq. 3.6 used exactly; a bad key value is refused before any output.
  const Result thesis = run("mesh '" + (dir / "rect.crv").string() + "' --out '" + (dir / "thesis").string() +
                            "' --iterations 0 --set preset=thesis --formats msh");
  CHECK(contains(thesis.output, "spacing field: eq. 3.6 (thesis), evaluated exactly"));
  const Result bad = run("mesh '" + (dir / "rect.crv").string() + "' --out '" + (dir / "bad").string() +
                         "' --set spacing.gradation=-1");
  CHECK(bad.status == 2);
  CHECK(contains(bad.output, "spacing.gradation must be in [0, 10]"));
  CHECK_FALSE(fs::exists(dir / "bad"));
  fs::remove_all(dir);
}

TEST_CASE("pdmesh quality --geometry judges a mesh against the field pdmesh mesh built for it", "[cli]") {
  // A 4 x 1 rectangle whose left side is segmented 0.01 and the rest 0.25: the gradation limit and
  // the floors make the best field differ from eq. 3.6.
  const fs::path dir = fresh_dir("quality_field");
  {
    std::ofstream crv(dir / "strip.crv");
    std::vector<std::pair<double, double>> pts;
    for (int k = 0; k < 16; ++k) pts.push_back({0.25 * k, 0.0});
    for (int k = 0; k < 4; ++k) pts.push_back({4.0, 0.25 * k});
    for (int k = 16; k > 0; --k) pts.push_back({0.25 * k, 1.0});
    for (int k = 0; k < 100; ++k) pts.push_back({0.0, 1.0 - 0.01 * k});
    pts.push_back({0.0, 0.0});
    crv << pts.size() << "\n";
    for (const auto& [x, y] : pts) crv << x << " " << y << "\n";
  }
  const fs::path out = dir / "out";
  const Result r =
      run("mesh '" + (dir / "strip.crv").string() + "' --out '" + out.string() + "' --iterations 0 --formats msh -q");
  REQUIRE(r.status == 0);
  auto conformance = [](const std::string& json) {
    const auto at = json.find("\"spacing_conformance\"");
    return at == std::string::npos ? std::string() : json.substr(at, json.find('}', at) - at);
  };
  std::ifstream mesh_json(out / "quality.json");
  const std::string from_mesh = conformance(std::string(std::istreambuf_iterator<char>(mesh_json), {}));
  REQUIRE_FALSE(from_mesh.empty());
  const Result best =
      run("quality '" + (out / "mesh.msh").string() + "' --geometry '" + (dir / "strip.crv").string() + "' --json -");
  REQUIRE(best.status == 0);
  CHECK(conformance(best.output) == from_mesh);
  std::ofstream(dir / "case.toml") << "preset = \"thesis\"\n[geometry]\nfiles = [\"strip.crv\"]\n";
  const Result thesis =
      run("quality '" + (out / "mesh.msh").string() + "' --geometry '" + (dir / "case.toml").string() + "' --json -");
  REQUIRE(thesis.status == 0);
  CHECK(conformance(thesis.output) != from_mesh);
  fs::remove_all(dir);
}

TEST_CASE("pdmesh mesh --formats decides the pictures: msh alone draws none, svg adds the SVG pictures", "[cli]") {
  const fs::path dir = fresh_dir("formats");
  write_rectangle(dir / "rect.crv");
  const auto files_in = [](const fs::path& d) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(d)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  };
  const Result batch = run("mesh '" + (dir / "rect.crv").string() + "' --out '" + (dir / "batch").string() +
                           "' --view corner=0,0,0.5,0.5 --iterations 10 --formats msh --timings '" +
                           (dir / "timings.json").string() + "'");
  INFO(batch.output);
  REQUIRE(batch.status == 0);
  CHECK(files_in(dir / "batch") == std::vector<std::string>{"final.nodes", "history.csv", "initial.nodes", "mesh.msh",
                                                            "mesh.nodes", "quality.json"});
  // --timings: every phase of the run, and no picture among them.
  const std::string timings = pdmesh::read_text_file(dir / "timings.json");
  for (const char* phase : {"\"read\"", "\"spacing\"", "\"estimate\"", "\"fill\"", "\"simulation\"",
                            "\"triangulation\"", "\"cleanup\"", "\"quality\"", "\"mesh msh\""})
    CHECK(contains(timings, phase));
  CHECK_FALSE(contains(timings, "\"background\": true"));
  // The backend that ran the simulation, in words (a fallback of --device auto shows here under -q too).
  CHECK((contains(timings, "\"backend\": \"opencl:") || contains(timings, "\"backend\": \"the host reference")));
  const Result svg = run("mesh '" + (dir / "rect.crv").string() + "' --out '" + (dir / "svg").string() +
                         "' --iterations 10 --formats svg");
  INFO(svg.output);
  REQUIRE(svg.status == 0);
  CHECK(files_in(dir / "svg") == std::vector<std::string>{"final.nodes", "final.svg", "history.csv", "initial.nodes",
                                                          "initial.svg", "mesh.nodes", "mesh.svg", "quality.json"});
  fs::remove_all(dir);
}

TEST_CASE("pdmesh quality draws a picture, and bad picture options exit 2 before writing anything", "[cli]") {
  const fs::path dir = fresh_dir("quality_picture");
  pdmesh::Mesh m;
  m.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.curve_names = {"square"};
  m.boundary_edges = {{0, 1, 0}, {1, 2, 0}, {2, 3, 0}, {3, 0, 0}};
  pdmesh::write_mesh(m, dir, "square", {"msh"});
  const std::string mesh = "quality '" + (dir / "square.msh").string() + "' --json '" + (dir / "q.json").string() + "'";
  const Result good = run(mesh + " --picture '" + (dir / "q.png").string() +
                          "' --view 0,0,0.5,0.5 --color-by min_angle --color-range 20,60");
  INFO(good.output);
  CHECK(good.status == 0);
  CHECK(fs::file_size(dir / "q.png") > 0);
  fs::remove(dir / "q.png");
  fs::remove(dir / "q.json");
  for (const char* bad :
       {" --picture x.jpg", " --view 0,0,1,1", " --picture p.png --view 0,0,1", " --picture p.png --view 1,0,0,1",
        " --picture p.png --color-by angle", " --picture p.png --color-by min_angle --color-range 60,20",
        " --picture p.png --color-range 0,60", " --picture p.png --view 0,0,1,nan"}) {
    INFO(bad);
    const Result r = run(mesh + bad);
    CHECK(r.status == 2);
    CHECK(contains(r.output, "pdmesh: error:"));
    CHECK(!fs::exists(dir / "q.json"));
  }
  fs::remove_all(dir);
}

TEST_CASE("pdmesh devices lists the OpenCL devices and checks each with a kernel", "[cli][opencl]") {
  const Result r = run("devices --check");
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK(contains(r.output, "opencl:0:0"));
  CHECK(contains(r.output, "--device auto picks: opencl:"));
  CHECK(contains(r.output, "check opencl:0:0: ok"));
  // The check builds the simulation program, runs a short case against the host reference and
  // measures the fp64 rate (PoCL's double is bit-identical to the host).
  CHECK(contains(r.output, "program: built in double; work-groups of 64 fit every kernel"));
  CHECK(contains(r.output, "equal the host reference bit for bit"));
  CHECK(contains(r.output, "--precision auto picks double"));
}

TEST_CASE("pdmesh mesh --device auto simulates a small case on the host reference, without setting OpenCL up",
          "[cli]") {
  const fs::path dir = fresh_dir("auto_small");
  write_rectangle(dir / "rect.crv");
  const Result r = run("mesh '" + (dir / "rect.crv").string() + "' --out '" + (dir / "out").string() +
                       "' --iterations 5 --stop iterations --formats msh --device auto --timings '" +
                       (dir / "t.json").string() + "'");
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(contains(r.output, "device auto: the host reference for"));
  CHECK(contains(r.output, "simulation: 5 iterations on the host reference"));
  CHECK_FALSE(contains(r.output, "opencl:"));
  CHECK(contains(pdmesh::read_text_file(dir / "t.json"), "\"backend\": \"the host reference"));
  fs::remove_all(dir);
}

TEST_CASE("pdmesh mesh sets the backend up beside the fill: its notes and errors come at the simulation",
          "[cli][opencl]") {
  const fs::path dir = fresh_dir("backend_thread");
  write_rectangle(dir / "rect.crv");
  const auto base = [&dir](const std::string& out) {
    return "mesh '" + (dir / "rect.crv").string() + "' --out '" + (dir / out).string() +
           "' --iterations 5 --stop iterations --formats msh";
  };
  // auto: the device's program build fails (injected), the note says so and the run goes on on the host.
  const Result fallback = pdmesh_test::run_pdmesh(base("auto") + " --device auto",
                                                  "PDMESH_TEST_FAIL_BUILD=1 PDMESH_TEST_AUTO_HOST_BELOW=0");
  INFO(fallback.output);
  REQUIRE(fallback.status == 0);
  const std::size_t note = fallback.output.find("cannot run the simulation: building OpenCL program");
  const std::size_t initial = fallback.output.find("initial distribution:");
  const std::size_t simulation = fallback.output.find("simulation: 5 iterations on the host reference");
  REQUIRE(note != std::string::npos);
  REQUIRE(initial != std::string::npos);
  REQUIRE(simulation != std::string::npos);
  // Printed when the simulation starts, after the fill's line, as when the backend was chosen there.
  CHECK(initial < note);
  CHECK(note < simulation);
  // An explicit device does not fall back: the set-up thread's error ends the run (exit 1), after the
  // initial outputs, before any simulation output.
  const Result failed = pdmesh_test::run_pdmesh(base("explicit") + " --device opencl:0:0", "PDMESH_TEST_FAIL_BUILD=1");
  INFO(failed.output);
  CHECK(failed.status == 1);
  CHECK(contains(failed.output, "building OpenCL program"));
  CHECK(fs::exists(dir / "explicit" / "initial.nodes"));
  CHECK_FALSE(fs::exists(dir / "explicit" / "history.csv"));
  fs::remove_all(dir);
}

TEST_CASE("pdmesh mesh --stop: the rule is named in the progress output, a bad rule exits 2", "[cli][convergence]") {
  const fs::path dir = fresh_dir("stop_rule");
  write_rectangle(dir / "rect.crv");
  const std::string base = "mesh '" + (dir / "rect.crv").string() + "' --out '" + (dir / "out").string() +
                           "' --iterations 10 --formats msh --device host";
  const Result converged = run(base);  // a geometry alone: the best preset, which stops once converged
  INFO(converged.output);
  REQUIRE(converged.status == 0);
  CHECK(contains(converged.output, "simulation: until converged, at most 10 iterations"));
  // A run that reached its maximum says which part of the rule held it.
  CHECK(contains(converged.output,
                 "simulation: not converged in 10 iterations: iteration 10 is before the earliest stop (150)"));
  const Result counted = run(base + " --stop iterations");
  INFO(counted.output);
  REQUIRE(counted.status == 0);
  CHECK(contains(counted.output, "simulation: 10 iterations on"));
  CHECK_FALSE(contains(counted.output, "converged"));
  const Result bad = run(base + " --stop never");
  CHECK(bad.status == 2);
  CHECK(contains(bad.output, "--stop never"));
  CHECK(contains(bad.output, "simulation.stop"));
  fs::remove_all(dir);
}

// (No brackets or commas in test names: ctest passes the name to Catch as a test spec.)
TEST_CASE("simulation.momentum out of range exits 2 naming the key and the value before any output",
          "[cli][momentum]") {
  const fs::path dir = fresh_dir("momentum");
  write_rectangle(dir / "rect.crv");
  const fs::path out = dir / "out";
  Result r = run("mesh '" + (dir / "rect.crv").string() + "' --out '" + out.string() + "' --momentum 1");
  CHECK(r.status == 2);
  CHECK(contains(r.output, "--momentum 1: simulation.momentum must be in [0, 1) (0 = plain gradient descent), got 1"));
  CHECK_FALSE(fs::exists(out));
  std::ofstream(dir / "case.toml") << "[geometry]\nfiles = [\"rect.crv\"]\n[simulation]\nmomentum = -0.5\n";
  r = run("mesh '" + (dir / "case.toml").string() + "' --out '" + out.string() + "'");
  CHECK(r.status == 2);
  CHECK(contains(r.output,
                 "case.toml:4:12: simulation.momentum must be in [0, 1) (0 = plain gradient descent), got -0.5"));
  CHECK_FALSE(fs::exists(out));
  // In range: the run takes it (and says so).
  r = run("mesh '" + (dir / "rect.crv").string() + "' --out '" + out.string() +
          "' --momentum 0.9 --iterations 3 --formats msh --device host");
  CHECK(r.status == 0);
  CHECK(contains(r.output, "momentum 0.9"));
  fs::remove_all(dir);
}
