// Interrupted runs and restart (thesis ch. 7, "Restart Capability"): checkpoints round-trip exactly,
// a stopped and resumed run ends bit-identical to an uninterrupted one on the host reference, a
// checkpoint of another case is refused, and a real SIGINT leaves a checkpoint and exit status 130.
#include <catch2/catch.hpp>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "app/pipeline/resume.hpp"
#include "core/errors.hpp"
#include "io/text_file.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "run_pdmesh.hpp"
#include "sim/simulation.hpp"
#include "sim_fixtures.hpp"
#include "spacing/spacing_field.hpp"
#include "sim/checkpoint.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using pdmesh_test::fresh_path;
using pdmesh_test::run_pdmesh;

namespace {

const std::string kCase = std::string(PDMESH_SOURCE_DIR) + "/cases/circle_circle";

std::string mesh_command(const fs::path& out, const std::string& extra, const std::string& device = "host") {
  return "mesh '" + kCase + "' --out '" + out.string() + "' --device " + device + " --formats msh --iterations 60 " +
         extra;
}

bool has_temporaries(const fs::path& dir) {
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().find(".tmp") != std::string::npos) return true;
  return false;
}

// history.csv as numbers, one vector per row (header skipped).
std::vector<std::vector<double>> history_numbers(const fs::path& file) {
  std::vector<std::vector<double>> rows;
  std::istringstream in(pdmesh::read_text_file(file));
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::istringstream fields(line);
    for (std::string f; std::getline(fields, f, ',');) row.push_back(std::stod(f));
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

TEST_CASE("a checkpoint survives format and parse exactly", "[resume]") {
  pdmesh::Checkpoint c;
  c.case_keys = {{"geometry.file.0", "a b.crv (12 bytes)"}, {"spacing.expression", ""}, {"init.seed", "7"}};
  c.nodes.add({0.1, -0.0}, 0.3, pdmesh::NodeKind::Fixed, 0);
  c.nodes.add({1.0 / 3.0, 2.5e-310}, 0.7, pdmesh::NodeKind::Boundary, 0);
  c.nodes.add({1.0, 0.0}, 0.3, pdmesh::NodeKind::Fixed, 0);
  c.nodes.add({0.5, 0.25}, 1e-17, pdmesh::NodeKind::Interior, -1);
  c.nodes.curve_nodes = {{0, 1, 2}};
  c.state.iterations_done = 2;
  c.state.dt_initial = 0.01;
  c.state.time_step = {0.0101, 3.25, 2, 1};
  c.state.arcs = {{0.0, 1.0 / 7.0, 1.0}};
  c.state.tangents = {{0, 0}, {0.6, 0.8}, {0, 0}, {0, 0}};
  pdmesh::HistoryRow row;
  row.iteration = 1;
  row.average_force = 1.0 / 3.0;
  row.max_force = 1e300;
  c.state.history = {row, row};
  c.state.history[1].iteration = 2;
  const std::string text = pdmesh::format_checkpoint(c);
  const pdmesh::Checkpoint back = pdmesh::parse_checkpoint(text, "mem");
  CHECK(pdmesh::format_checkpoint(back) == text);
  CHECK(back.case_keys == c.case_keys);
  CHECK(back.nodes.x[1].x == 1.0 / 3.0);
  CHECK(back.nodes.x[1].y == 2.5e-310);
  CHECK(std::signbit(back.nodes.x[0].y));
  CHECK(back.state.arcs[0][1] == 1.0 / 7.0);
  CHECK(back.state.time_step.previous == 3.25);
  CHECK(back.state.history[0].average_force == 1.0 / 3.0);
  // A truncated file (no end line) is refused with its line.
  const std::string truncated = text.substr(0, text.rfind("end"));
  CHECK_THROWS_AS(pdmesh::parse_checkpoint(truncated, "mem"), pdmesh::InputError);
  CHECK_THROWS_WITH(pdmesh::parse_checkpoint("pdmesh-checkpoint 3\n", "mem"), Catch::Contains("mem:1"));
}

TEST_CASE("a checkpoint keeps the stopping rule's measurements exactly, and a file without them has none",
          "[resume][convergence]") {
  pdmesh::Checkpoint c;
  c.nodes.add({0.0, 0.0}, 0.3, pdmesh::NodeKind::Fixed, 0);
  c.nodes.add({1.0, 0.0}, 0.3, pdmesh::NodeKind::Fixed, 0);
  c.nodes.curve_nodes = {{0, 1}};
  c.state.iterations_done = 300;
  c.state.dt_initial = 0.01;
  c.state.arcs = {{0.0, 1.0}};
  c.state.tangents = {{0, 0}, {0, 0}};
  c.state.history.resize(300);
  for (int k = 0; k < 300; ++k) c.state.history[static_cast<std::size_t>(k)].iteration = k + 1;
  // Without measurements (simulation.stop = "iterations"): no section at all, as in older files.
  const std::string without = pdmesh::format_checkpoint(c);
  CHECK(without.find("convergence") == std::string::npos);
  CHECK(pdmesh::parse_checkpoint(without, "mem").state.convergence.empty());
  // With them, a NaN one (nodes that did not triangulate) included: bit for bit.
  c.state.convergence = {{100, 1.0 / 3.0, 1.0 + 0x1p-52}, {200, std::nan(""), std::nan("")}, {300, 35.25, 1.0123}};
  const std::string text = pdmesh::format_checkpoint(c);
  const pdmesh::Checkpoint back = pdmesh::parse_checkpoint(text, "mem");
  CHECK(pdmesh::format_checkpoint(back) == text);
  REQUIRE(back.state.convergence.size() == 3);
  CHECK(back.state.convergence[0].iteration == 100);
  CHECK(back.state.convergence[0].min_angle == 1.0 / 3.0);
  CHECK(back.state.convergence[0].aspect_ratio == 1.0 + 0x1p-52);
  CHECK(std::isnan(back.state.convergence[1].min_angle));
  CHECK(std::isnan(back.state.convergence[1].aspect_ratio));
  CHECK(back.state.convergence[2].iteration == 300);
  // Measurements after the last iteration done, out of order, or of the wrong shape are refused.
  const auto section = text.find("convergence 3\n");
  REQUIRE(section != std::string::npos);
  const std::string tail = text.substr(section);
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string t = tail;
    const auto at = t.find(from);
    REQUIRE(at != std::string::npos);
    return text.substr(0, section) + t.replace(at, from.size(), to);
  };
  CHECK_THROWS_AS(pdmesh::parse_checkpoint(replaced("\n300 ", "\n301 "), "mem"), pdmesh::InputError);
  CHECK_THROWS_AS(pdmesh::parse_checkpoint(replaced("\n200 ", "\n50 "), "mem"), pdmesh::InputError);
  CHECK_THROWS_AS(pdmesh::parse_checkpoint(replaced("convergence 3", "convergence 4"), "mem"), pdmesh::InputError);
  CHECK_THROWS_AS(pdmesh::parse_checkpoint(replaced(" nan nan", " nan"), "mem"), pdmesh::InputError);
}

TEST_CASE("a stopped and resumed run ends bit-identical to an uninterrupted one", "[resume][cli]") {
  // The thesis' settings, and boundary nodes placed by the field on smooth curves.
  const std::string settings =
      GENERATE(std::string(""), std::string("--set boundary.nodes=spacing --set geometry.curves=smooth"));
  INFO("settings: " << settings);
  const fs::path whole = fresh_path("whole"), parts = fresh_path("parts");
  const auto full = run_pdmesh(mesh_command(whole, "-q " + settings));
  REQUIRE(full.status == 0);
  CHECK_FALSE(fs::exists(whole / "checkpoint.pdmesh"));

  const auto stopped = run_pdmesh(mesh_command(parts, "-q --stop-after 23 " + settings));
  INFO(stopped.output);
  REQUIRE(stopped.status == 130);
  REQUIRE(fs::exists(parts / "checkpoint.pdmesh"));
  // A stop writes the checkpoint and nothing else (no mesh of the unsettled nodes).
  CHECK_FALSE(fs::exists(parts / "final.nodes"));
  CHECK_FALSE(fs::exists(parts / "mesh.msh"));
  CHECK_FALSE(has_temporaries(parts));
  const pdmesh::Checkpoint c = pdmesh::read_checkpoint(parts / "checkpoint.pdmesh");
  CHECK(c.state.iterations_done == 23);
  CHECK(c.state.history.size() == 23);

  const auto resumed = run_pdmesh(mesh_command(parts, "-q --resume '" + parts.string() + "' " + settings));
  INFO(resumed.output);
  REQUIRE(resumed.status == 0);
  CHECK(pdmesh::read_text_file(parts / "final.nodes") == pdmesh::read_text_file(whole / "final.nodes"));
  CHECK(pdmesh::read_text_file(parts / "history.csv") == pdmesh::read_text_file(whole / "history.csv"));
  CHECK(pdmesh::read_text_file(parts / "mesh.msh") == pdmesh::read_text_file(whole / "mesh.msh"));
  CHECK_FALSE(fs::exists(parts / "checkpoint.pdmesh"));  // the run there is finished
  fs::remove_all(whole);
  fs::remove_all(parts);
}

// circle_circle's geometry alone (the best preset: population control on), a random start with early,
// frequent population events, 90 iterations on the host, writing to `out`.
namespace {
std::string population_command(const fs::path& out, const std::string& extra) {
  return "mesh '" + std::string(PDMESH_SOURCE_DIR) + "/cases/circle_circle/circles.crv' --out '" + out.string() +
         "' --device host --formats msh --iterations 90 --method random --seed 3 -q --set population.start=20 "
         "--set population.every=10 --set population.stop=0.8 " +
         extra;
}

// Stops `parts`' run (made by `command`) after iteration 45 again, then resumes its checkpoint with
// `settings` in a fresh directory: refused with exit 2, naming `key`.
template <class Command>
void check_resume_refused(const Command& command, const fs::path& parts, const std::string& dir,
                          const std::string& settings, const std::string& key) {
  REQUIRE(run_pdmesh(command(parts, "--stop-after 45")).status == 130);
  const auto refused = run_pdmesh(command(fresh_path(dir), settings + " --resume '" + parts.string() + "'"));
  CHECK(refused.status == 2);
  CHECK_THAT(refused.output, Catch::Contains(key));
}
}  // namespace

TEST_CASE("a run stopped after population events resumes bit-identical on the host", "[resume][cli][population]") {
  // Events from iteration 20 on, so that the node set has changed before the stop.
  const auto command = population_command;
  const fs::path whole = fresh_path("pop_whole"), parts = fresh_path("pop_parts");
  REQUIRE(run_pdmesh(command(whole, "")).status == 0);
  const auto stopped = run_pdmesh(command(parts, "--stop-after 45"));
  INFO(stopped.output);
  REQUIRE(stopped.status == 130);
  const pdmesh::Checkpoint c = pdmesh::read_checkpoint(parts / "checkpoint.pdmesh");
  std::size_t inserted = 0, removed = 0;
  for (const pdmesh::HistoryRow& row : c.state.history) {
    inserted += row.inserted;
    removed += row.removed;
  }
  // Events ran after iterations 20, 30 and 40 and changed the node set.
  CHECK(c.state.population.last_event == 40);
  REQUIRE(inserted + removed > 0);
  CHECK(c.nodes.size() ==
        c.state.history.back().fixed + c.state.history.back().boundary + c.state.history.back().interior);
  const auto resumed = run_pdmesh(command(parts, "--resume '" + parts.string() + "'"));
  INFO(resumed.output);
  REQUIRE(resumed.status == 0);
  CHECK(pdmesh::read_text_file(parts / "final.nodes") == pdmesh::read_text_file(whole / "final.nodes"));
  CHECK(pdmesh::read_text_file(parts / "history.csv") == pdmesh::read_text_file(whole / "history.csv"));
  // A checkpoint with population control is refused by a run without it.
  check_resume_refused(command, parts, "pop_off", "--set population.enabled=false", "population.enabled");
  fs::remove_all(whole);
  fs::remove_all(parts);
}

TEST_CASE("a run with momentum stopped after population events resumes bit-identical on the host",
          "[resume][cli][population][momentum]") {
  // The beta as a --set, so that a check's own --momentum (a direct option, applied after it) replaces it.
  const auto command = [](const fs::path& out, const std::string& extra) {
    return population_command(out, "--set simulation.momentum=0.9 " + extra);
  };
  const fs::path whole = fresh_path("mom_whole"), parts = fresh_path("mom_parts");
  REQUIRE(run_pdmesh(command(whole, "")).status == 0);
  REQUIRE(run_pdmesh(command(parts, "--stop-after 45")).status == 130);
  const pdmesh::Checkpoint c = pdmesh::read_checkpoint(parts / "checkpoint.pdmesh");
  REQUIRE(c.state.momentum.size() == c.nodes.size());
  std::size_t carried = 0;
  for (const pdmesh::Vec2& p : c.state.momentum) carried += p.x != 0.0 || p.y != 0.0 ? 1 : 0;
  CHECK(carried > 0);
  const auto resumed = run_pdmesh(command(parts, "--resume '" + parts.string() + "'"));
  INFO(resumed.output);
  REQUIRE(resumed.status == 0);
  CHECK(pdmesh::read_text_file(parts / "final.nodes") == pdmesh::read_text_file(whole / "final.nodes"));
  CHECK(pdmesh::read_text_file(parts / "history.csv") == pdmesh::read_text_file(whole / "history.csv"));
  // The momentum is part of the case: another beta, or none, is refused.
  check_resume_refused(command, parts, "mom_other", "--momentum 0.5", "simulation.momentum");
  check_resume_refused(command, parts, "mom_none", "--momentum 0", "simulation.momentum");
  fs::remove_all(whole);
  fs::remove_all(parts);
}

TEST_CASE("a run whose population control settled early resumes bit-identical, without further events",
          "[resume][cli][population]") {
  // settle = 0.1: every event is quiet; with settle_events = 1 the first one (after iteration 20) ends
  // population control. The checkpoint after iteration 45 holds the finished schedule.
  const auto command = [](const fs::path& out, const std::string& extra) {
    return population_command(out, "--set population.settle=0.1 --set population.settle_events=1 " + extra);
  };
  const fs::path whole = fresh_path("settle_whole"), parts = fresh_path("settle_parts");
  REQUIRE(run_pdmesh(command(whole, "")).status == 0);
  REQUIRE(run_pdmesh(command(parts, "--stop-after 45")).status == 130);
  const pdmesh::Checkpoint c = pdmesh::read_checkpoint(parts / "checkpoint.pdmesh");
  CHECK(c.state.population.last_event == 20);
  CHECK(c.state.population.last_change == 0);
  const auto resumed = run_pdmesh(command(parts, "--resume '" + parts.string() + "'"));
  INFO(resumed.output);
  REQUIRE(resumed.status == 0);
  CHECK(pdmesh::read_text_file(parts / "final.nodes") == pdmesh::read_text_file(whole / "final.nodes"));
  const std::string history = pdmesh::read_text_file(parts / "history.csv");
  CHECK(history == pdmesh::read_text_file(whole / "history.csv"));
  // One event only: after iteration 20 no row inserts or removes (the last two columns).
  std::istringstream lines(history);
  std::string line;
  std::getline(lines, line);  // header
  int after = 0;
  while (std::getline(lines, line)) {
    if (std::stoi(line.substr(0, line.find(','))) <= 20) continue;
    ++after;
    CHECK(line.substr(line.size() - 4) == ",0,0");
  }
  CHECK(after == 70);
  // Another settle tolerance is another schedule: refused.
  check_resume_refused(command, parts, "settle_other", "--set population.settle=0", "population.schedule");
  fs::remove_all(whole);
  fs::remove_all(parts);
}

TEST_CASE("a checkpoint of another case or other settings is refused with exit 2", "[resume][cli]") {
  const fs::path dir = fresh_path("other");
  REQUIRE(run_pdmesh(mesh_command(dir, "-q --stop-after 3")).status == 130);
  const auto other_settings =
      run_pdmesh(mesh_command(fresh_path("o2"), "--cutoff 1.6 --resume '" + dir.string() + "'"));
  CHECK(other_settings.status == 2);
  CHECK_THAT(other_settings.output, Catch::Contains("another case") && Catch::Contains("simulation.cutoff"));
  // The spacing pipeline's keys change the field the run follows.
  const auto other_field =
      run_pdmesh(mesh_command(fresh_path("o5"), "--set spacing.gradation=0.3 --resume '" + dir.string() + "'"));
  CHECK(other_field.status == 2);
  CHECK_THAT(other_field.output, Catch::Contains("another case") && Catch::Contains("spacing.gradation"));
  const auto other_curves =
      run_pdmesh(mesh_command(fresh_path("o5"), "--set geometry.curves=smooth --resume '" + dir.string() + "'"));
  CHECK(other_curves.status == 2);
  CHECK_THAT(other_curves.output, Catch::Contains("another case") && Catch::Contains("geometry.curves"));
  const std::string square = std::string(PDMESH_SOURCE_DIR) + "/cases/square200";
  const auto other_case = run_pdmesh("mesh '" + square + "' --out '" + fresh_path("o3").string() +
                                     "' --device host --resume '" + (dir / "checkpoint.pdmesh").string() + "'");
  CHECK(other_case.status == 2);
  CHECK_THAT(other_case.output, Catch::Contains("another case") && Catch::Contains("geometry.file.0"));
  const auto missing = run_pdmesh(mesh_command(fresh_path("o4"), "--resume '" + fresh_path("none").string() + "'"));
  CHECK(missing.status == 2);
  CHECK_THAT(missing.output, Catch::Contains("no checkpoint"));
  fs::remove_all(dir);
}

TEST_CASE("SIGINT stops a running mesh command with exit 130 and a readable checkpoint", "[resume][cli][signal]") {
  const fs::path dir = fresh_path("sigint");
  int err[2];
  REQUIRE(::pipe(err) == 0);
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    ::dup2(err[1], STDERR_FILENO);
    ::close(err[0]);
    ::close(err[1]);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, STDOUT_FILENO);
    const std::string out = dir.string();
    ::execl(PDMESH_BINARY, PDMESH_BINARY, "mesh", kCase.c_str(), "--out", out.c_str(), "--device", "host", "--formats",
            "msh", "--iterations", "100000", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(err[1]);
  // Wait until iterations have ended (the first "simulation N/100000" progress line, printed after the
  // simulation's first second), however loaded the machine: a stop before the first iteration has
  // ended leaves nothing to continue from, and no checkpoint.
  std::string seen;
  char buffer[256];
  while (seen.find("/100000") == std::string::npos) {
    const ssize_t n = ::read(err[0], buffer, sizeof buffer);
    if (n <= 0) break;
    seen.append(buffer, static_cast<std::size_t>(n));
  }
  REQUIRE(seen.find("/100000") != std::string::npos);
  REQUIRE(::kill(pid, SIGINT) == 0);
  // Keep draining stderr so that the child never blocks on a full pipe.
  while (::read(err[0], buffer, sizeof buffer) > 0) {
  }
  ::close(err[0]);
  int status = 0;
  REQUIRE(::waitpid(pid, &status, 0) == pid);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 130);
  REQUIRE(fs::exists(dir / "checkpoint.pdmesh"));
  const pdmesh::Checkpoint c = pdmesh::read_checkpoint(dir / "checkpoint.pdmesh");
  CHECK(c.state.iterations_done >= 1);
  CHECK(c.state.iterations_done < 100000);
  CHECK(c.state.history.size() == static_cast<std::size_t>(c.state.iterations_done));
  CHECK_FALSE(fs::exists(dir / "final.nodes"));
  CHECK_FALSE(fs::exists(dir / "mesh.msh"));
  CHECK_FALSE(has_temporaries(dir));
  fs::remove_all(dir);
}

TEST_CASE("a stopped and resumed device run continues the same run", "[resume][cli][opencl]") {
  // The device-resident run restarts its Verlet lists on resume: the same run within round-off,
  // not promised bit-identical.
  const fs::path whole = fresh_path("dev_whole"), parts = fresh_path("dev_parts");
  REQUIRE(run_pdmesh(mesh_command(whole, "-q", "opencl")).status == 0);
  REQUIRE(run_pdmesh(mesh_command(parts, "-q --stop-after 23", "opencl")).status == 130);
  REQUIRE(run_pdmesh(mesh_command(parts, "-q --resume '" + parts.string() + "'", "opencl")).status == 0);
  const auto a = history_numbers(whole / "history.csv"), b = history_numbers(parts / "history.csv");
  REQUIRE(a.size() == 60);
  REQUIRE(b.size() == a.size());
  for (std::size_t r = 0; r < a.size(); ++r) {
    REQUIRE(b[r].size() == a[r].size());
    for (std::size_t f = 0; f < a[r].size(); ++f) CHECK(b[r][f] == Approx(a[r][f]).epsilon(1e-9));
  }
  fs::remove_all(whole);
  fs::remove_all(parts);
}

TEST_CASE("a failing simulation hands the last good state to on_failure before throwing", "[resume][sim]") {
  using namespace pdmesh;
  const Geometry geometry = pdmesh_test::circle_circle();
  const GeometryTree tree(geometry);
  const BoundarySpacing spacing(tree);
  NodeSet nodes = make_initial_distribution(tree, spacing, {InitMethod::Structured, 1, {}}).nodes;
  std::size_t interior = 0;
  while (nodes.kind[interior] != NodeKind::Interior) ++interior;
  SimOptions options;
  options.iterations = 30;
  options.dt_initial = 0.01;
  options.quiet = true;
  SimCallbacks callbacks;
  // After iteration 10 one spacing turns NaN: iteration 11's forces are non-finite.
  callbacks.on_iteration = [&](const HistoryRow& row) {
    if (row.iteration == 10) nodes.q[interior] = std::nan("");
  };
  std::optional<SimState> saved;
  callbacks.on_failure = [&](const SimState& state) { saved = state; };
  CHECK_THROWS_AS(run_simulation(nodes, tree, spacing, options, callbacks), SimulationError);
  REQUIRE(saved);
  CHECK(saved->iterations_done == 10);
  CHECK(saved->history.size() == 10);
  CHECK(saved->history.back().iteration == 10);
  CHECK(saved->arcs.size() == nodes.curve_nodes.size());
  CHECK(saved->tangents.size() == nodes.size());
}

TEST_CASE("a checkpoint of a mesh field knows its file's content and array", "[resume]") {
  const fs::path dir = fresh_path("identity");
  fs::create_directories(dir);
  pdmesh::write_text_file(dir / "f.vtu", "one");
  const std::string text = "[geometry]\nfiles = [\"" + kCase + "/circles.crv\"]\n[spacing]\nfile = \"f.vtu\"\n";
  const auto keys = [&](const std::string& extra) {
    return pdmesh::case_identity(pdmesh::parse_case_text(text + extra, dir / "case.toml"));
  };
  const auto value = [](const std::vector<std::pair<std::string, std::string>>& k, const std::string& key) {
    for (const auto& [name, v] : k)
      if (name == key) return v;
    return std::string("(none)");
  };
  const auto first = keys("");
  CHECK(value(first, "spacing.field") == "mesh");
  CHECK_THAT(value(first, "spacing.file"), Catch::StartsWith("f.vtu (3 bytes, FNV-1a "));
  CHECK(value(first, "spacing.array") == "q");
  CHECK(value(keys("array = \"h\"\n"), "spacing.array") == "h");
  pdmesh::write_text_file(dir / "f.vtu", "two");
  CHECK(value(keys(""), "spacing.file") != value(first, "spacing.file"));
  // Other fields keep the keys (and so the checkpoints) they had.
  const auto boundary =
      pdmesh::case_identity(pdmesh::parse_case_text(text.substr(0, text.find("[spacing]")), dir / "case.toml"));
  CHECK(value(boundary, "spacing.file") == "(none)");
  fs::remove_all(dir);
}

TEST_CASE("population control's identity names the settle keys only when settling is on", "[resume]") {
  // The long preset: settling off by default (best settles).
  const std::string text = "preset = \"long\"\n[geometry]\nfiles = [\"" + kCase + "/circles.crv\"]\n";
  const auto schedule = [&](const std::string& extra) {
    for (const auto& [name, v] : pdmesh::case_identity(pdmesh::parse_case_text(text + extra, "case.toml")))
      if (name == "population.schedule") return v;
    return std::string("(none)");
  };
  // Off (long's default): the string of the checkpoints written before the keys existed, so they resume.
  CHECK(schedule("") == "every 50 start 100 stop 0.8");
  CHECK(schedule("[population]\nsettle = 0.001\n") == "every 50 start 100 stop 0.8 settle 0.001 2");
  CHECK(schedule("[population]\nsettle = 0.001\nsettle_events = 3\n") != schedule("[population]\nsettle = 0.001\n"));
}

TEST_CASE("the background's resolution is part of a checkpoint's identity only when it is not the default",
          "[resume]") {
  const std::string text = "[geometry]\nfiles = [\"" + kCase + "/circles.crv\"]\n";
  const auto keys = [&](const std::string& extra, const std::string& preset = "") {
    std::vector<std::string> names;
    for (const auto& [name, v] : pdmesh::case_identity(pdmesh::parse_case_text(preset + text + extra, "case.toml")))
      if (name.rfind("spacing.background", 0) == 0) names.push_back(name + "=" + v);
    return names;
  };
  // The builder's defaults (thesis, long): no key, so checkpoints written before the keys existed keep
  // their identity. Best's interior cap is not the builder's: its runs name all three.
  CHECK(keys("", "preset = \"thesis\"\n").empty());
  CHECK(keys("", "preset = \"long\"\n").empty());
  const auto best = keys("");
  REQUIRE(best.size() == 3);
  CHECK(best[1] == "spacing.background_min_side=0.5");
  // Any one of the three set: all three, with their values.
  const auto coarse = keys("[spacing]\nbackground_boundary_min_side = 0.25\n");
  REQUIRE(coarse.size() == 3);
  CHECK(coarse[2] == "spacing.background_boundary_min_side=0.25");
  CHECK(keys("[spacing]\nbackground_tolerance = 0.02\n") != coarse);
  CHECK(keys("[spacing]\nbackground_min_side = 0.25\n") != coarse);
  CHECK(keys("[spacing]\nbackground_min_side = 0.25\n") != best);
}
