// Ctrl-C at any moment (docs/robustness.md, "Stopping a run"): the stop flag of core/interrupt ends
// the library's loops with Interrupted; `pdmesh mesh` stopped in any phase (a real SIGINT, sent by the
// PDMESH_TEST_SIGNAL_IN_PHASE hook when the phase begins) exits 130 with a message naming the phase
// and the commands that continue, and writes the checkpoint of the current nodes once the simulation
// has run, and nothing else; the printed commands work.
#include <catch2/catch.hpp>

#include <atomic>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "core/interrupt.hpp"
#include "core/parallel.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "io/text_file.hpp"
#include "run_pdmesh.hpp"
#include "sim/checkpoint.hpp"
#include "sim/simulation.hpp"
#include "sim_fixtures.hpp"
#include "spacing/spacing_field.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using pdmesh_test::run_pdmesh;

namespace {

const std::string kCase = std::string(PDMESH_SOURCE_DIR) + "/cases/circle_circle";

// Sets the process's stop flag for a scope (and clears it after).
struct FlagSet {
  FlagSet() { pdmesh::interrupt_flag().store(true); }
  ~FlagSet() { pdmesh::interrupt_flag().store(false); }
};

bool has_temporaries(const fs::path& dir) {
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().find(".tmp") != std::string::npos) return true;
  return false;
}

// The line of `output` after `label` (the commands the stop message prints), without the label.
std::string line_after(const std::string& output, const std::string& label) {
  const auto at = output.find(label);
  if (at == std::string::npos) return "";
  const auto start = output.find_first_not_of(' ', at + label.size());
  return output.substr(start, output.find('\n', start) - start);
}

// Runs a printed command line (its first word the binary) through the shell.
pdmesh_test::Result run_printed(const std::string& command) {
  const std::string binary = PDMESH_BINARY;
  REQUIRE(command.rfind(binary + " ", 0) == 0);
  return run_pdmesh(command.substr(binary.size() + 1));
}

std::string mesh_command(const fs::path& out, const std::string& extra, const std::string& input = kCase) {
  return "mesh '" + input + "' --out '" + out.string() + "' --device host --formats msh,png --iterations 60 " + extra;
}

// The geometry alone: the best preset, whose runs have every phase (cleanup too).
const std::string kGeometry = kCase + "/circles.crv";

}  // namespace

TEST_CASE("check_interrupt throws Interrupted once the flag is set, except under a shield", "[interrupt]") {
  CHECK_NOTHROW(pdmesh::check_interrupt());
  const FlagSet set;
  CHECK_THROWS_AS(pdmesh::check_interrupt(), pdmesh::Interrupted);
  {
    const pdmesh::InterruptShield shield;
    CHECK_NOTHROW(pdmesh::check_interrupt());
    CHECK_FALSE(pdmesh::interrupt_requested());
  }
  CHECK(pdmesh::interrupt_requested());
}

TEST_CASE("parallel_for ends with Interrupted at a stop request, and runs whole under a shield", "[interrupt]") {
  const std::size_t n = 1 << 20;
  std::vector<int> done(n, 0);
  const FlagSet set;
  CHECK_THROWS_AS(pdmesh::parallel_for(
                      n, [&](std::size_t i) { done[i] = 1; }, 1024),
                  pdmesh::Interrupted);
  std::size_t count = 0;
  for (int d : done) count += static_cast<std::size_t>(d);
  CHECK(count < n);
  {
    const pdmesh::InterruptShield shield;
    std::fill(done.begin(), done.end(), 0);
    pdmesh::parallel_for(
        n, [&](std::size_t i) { done[i] = 1; }, 1024);
    count = 0;
    for (int d : done) count += static_cast<std::size_t>(d);
    CHECK(count == n);
  }
}

TEST_CASE("a stop during an iteration's forces or the stopping rule's measurement resumes bit-identical",
          "[interrupt][sim]") {
  using namespace pdmesh;
  const Geometry geometry = pdmesh_test::circle_circle();
  const GeometryTree tree(geometry);
  const BoundarySpacing spacing(tree);
  const NodeSet start = make_initial_distribution(tree, spacing, {InitMethod::Structured, 1, {}}).nodes;
  SimOptions options;
  options.iterations = 120;
  options.dt_initial = 0.01;
  options.quiet = true;
  options.convergence.enabled = true;
  options.convergence.check_every = 20;
  options.convergence.window = 40;
  options.convergence.min_iterations = 40;
  NodeSet whole = start;
  const SimResult a = run_simulation(whole, tree, spacing, options, {});
  // The flag set in iteration 60's callback (a measurement is due after it) ends the measurement; set
  // in iteration 90's, the forces of iteration 91 (the state after 90 is kept).
  const int at = GENERATE(60, 90);
  INFO("stop requested in iteration " << at);
  NodeSet parts = start;
  SimCallbacks callbacks;
  callbacks.on_iteration = [at](const HistoryRow& row) {
    if (row.iteration == at) interrupt_flag().store(true);
  };
  const SimResult b = run_simulation(parts, tree, spacing, options, callbacks);
  interrupt_flag().store(false);
  REQUIRE(b.stopped);
  CHECK(b.state.iterations_done == at);
  REQUIRE_FALSE(b.state.convergence.empty());
  // After 60 the measurement is missing (taken by the resumed run); after 90 none was due.
  CHECK(b.state.convergence.back().iteration == (at == 60 ? 40 : 80));
  SimOptions again = options;
  again.resume = &b.state;
  const SimResult c = run_simulation(parts, tree, spacing, again, {});
  CHECK(c.state.iterations_done == a.state.iterations_done);
  CHECK(c.converged == a.converged);
  REQUIRE(c.state.convergence.size() == a.state.convergence.size());
  for (std::size_t k = 0; k < a.state.convergence.size(); ++k) {
    CHECK(c.state.convergence[k].iteration == a.state.convergence[k].iteration);
    CHECK(c.state.convergence[k].min_angle == a.state.convergence[k].min_angle);
  }
  REQUIRE(parts.size() == whole.size());
  for (std::size_t i = 0; i < whole.size(); ++i) {
    CHECK(parts.x[i].x == whole.x[i].x);
    CHECK(parts.x[i].y == whole.x[i].y);
  }
}

TEST_CASE("a run stopped during the simulation writes the checkpoint and nothing else, and its commands work",
          "[interrupt][cli]") {
  const fs::path dir = pdmesh_test::fresh_dir("interrupt_sim");
  fs::remove_all(dir);
  const auto stopped = run_pdmesh(mesh_command(dir, "--stop-after 23"));
  INFO(stopped.output);
  REQUIRE(stopped.status == 130);
  CHECK_THAT(stopped.output, Catch::Contains("during simulation") && Catch::Contains("after iteration 23 of 60"));
  REQUIRE(fs::exists(dir / "checkpoint.pdmesh"));
  CHECK(pdmesh::read_checkpoint(dir / "checkpoint.pdmesh").state.iterations_done == 23);
  // Nothing of the unsettled mesh: no history, final nodes, mesh or quality.
  for (const char* name :
       {"history.csv", "final.nodes", "final.png", "mesh.msh", "mesh.nodes", "quality.json", "mesh.png"})
    CHECK_FALSE(fs::exists(dir / name));
  CHECK_FALSE(has_temporaries(dir));
  // The printed commands, run as printed: the current nodes meshed (the checkpoint kept), then the run
  // continued to its end (the checkpoint removed).
  const std::string as_is = line_after(stopped.output, "to mesh the nodes as they are:");
  const std::string go_on = line_after(stopped.output, "to continue the run:");
  INFO(as_is << "\n" << go_on);
  CHECK_THAT(as_is, Catch::Contains("--resume") && Catch::Contains("--iterations 0"));
  CHECK_THAT(go_on, Catch::Contains("--resume") && !Catch::Contains("--stop-after"));
  const auto meshed = run_printed(as_is);
  INFO(meshed.output);
  CHECK(meshed.status == 0);
  CHECK(fs::exists(dir / "mesh.msh"));
  CHECK(fs::exists(dir / "checkpoint.pdmesh"));
  const auto continued = run_printed(go_on);
  INFO(continued.output);
  CHECK(continued.status == 0);
  CHECK(fs::exists(dir / "final.nodes"));
  CHECK_FALSE(fs::exists(dir / "checkpoint.pdmesh"));
  // The continued run ends where an uninterrupted one does.
  const fs::path whole = pdmesh_test::fresh_dir("interrupt_whole");
  REQUIRE(run_pdmesh(mesh_command(whole, "-q")).status == 0);
  CHECK(pdmesh::read_text_file(dir / "final.nodes") == pdmesh::read_text_file(whole / "final.nodes"));
  fs::remove_all(dir);
  fs::remove_all(whole);
}

TEST_CASE("SIGINT in any phase stops the run with exit 130, a message, and only the checkpoint once simulated",
          "[interrupt][cli][signal]") {
  struct Phase {
    const char* name;
    bool simulated;  // the simulation has run: a checkpoint is written
  };
  const Phase phase = GENERATE(Phase{"read", false}, Phase{"spacing", false}, Phase{"fill", false},
                               // At the simulation's start: its first iteration's forces are cut short.
                               Phase{"initial.nodes", false}, Phase{"simulation", false}, Phase{"history.csv", true},
                               Phase{"final.nodes", true}, Phase{"triangulation", true}, Phase{"cleanup", true},
                               Phase{"quality", true}, Phase{"mesh msh", true}, Phase{"waiting for pictures", true});
  INFO("phase: " << phase.name);
  const fs::path dir = pdmesh_test::fresh_dir("interrupt_phase");
  fs::remove_all(dir);
  const auto r =
      run_pdmesh(mesh_command(dir, "-q", kGeometry), std::string("'PDMESH_TEST_SIGNAL_IN_PHASE=") + phase.name + "'");
  CHECK_THAT(r.output, Catch::Contains("SIGINT sent at"));  // the phase ran
  INFO(r.output);
  CHECK(r.status == 130);
  CHECK_THAT(r.output, Catch::Contains("stopped by SIGINT (Ctrl-C) during"));
  CHECK(fs::exists(dir / "checkpoint.pdmesh") == phase.simulated);
  if (phase.simulated) {
    CHECK_THAT(r.output, Catch::Contains("--iterations 0") && Catch::Contains("checkpoint.pdmesh"));
    CHECK(pdmesh::read_checkpoint(dir / "checkpoint.pdmesh").state.iterations_done >= 1);
  } else {
    CHECK_THAT(r.output, Catch::Contains("nothing to continue from"));
  }
  // The mesh files are written after every phase tried here but the last two.
  if (std::string(phase.name) != "waiting for pictures") CHECK_FALSE(fs::exists(dir / "mesh.nodes"));
  if (fs::exists(dir)) CHECK_FALSE(has_temporaries(dir));
  fs::remove_all(dir);
}
