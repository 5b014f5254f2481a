// Convergence study: runs one case on the host reference for simulation.iterations iterations (every
// one of them: simulation.stop is set to "iterations") and, every --every iterations, measures the
// mesh of the nodes as the stopping rule does (sim/convergence measure_mesh: the smallest angle and
// the mean aspect ratio of their constrained Delaunay triangulation, before any cleanup) together with
// whether population control has settled then. One CSV line per measurement on stdout; the history
// to --history. tools/studies/convergence_check.py replays the stopping rule over these lines with any
// options (docs/simulation.md, "When a run stops").
// Usage: convergence_study CASE.toml|GEOMETRY... [--set KEY=VALUE ...] [--every N] [--history FILE]
#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "core/errors.hpp"
#include "sim/convergence.hpp"
#include "sim/history.hpp"
#include "sim/population.hpp"

int main(int argc, char** argv) {
  using namespace pdmesh;
  try {
    std::vector<std::string> inputs;
    std::vector<CaseOverride> overrides;
    int every = 10;
    std::string history_file;
    for (int a = 1; a < argc; ++a) {
      const std::string arg = argv[a];
      if (arg == "--set" && a + 1 < argc)
        overrides.push_back(parse_set_option(argv[++a]));
      else if (arg == "--every" && a + 1 < argc)
        every = std::stoi(argv[++a]);
      else if (arg == "--history" && a + 1 < argc)
        history_file = argv[++a];
      else if (!arg.empty() && arg[0] != '-')
        inputs.push_back(arg);
      else
        throw InputError(fmt::format("convergence_study: unknown argument '{}'", arg));
    }
    if (inputs.empty() || every < 1) {
      fmt::print(stderr,
                 "usage: convergence_study CASE.toml|GEOMETRY... [--set KEY=VALUE ...] [--every N] "
                 "[--history FILE]\n");
      return 2;
    }
    std::vector<std::filesystem::path> files(inputs.begin(), inputs.end());
    CaseConfig config = files.size() == 1 && files[0].extension() == ".toml" ? load_case_file(files[0], overrides)
                        : files.size() == 1 && std::filesystem::is_directory(files[0])
                            ? load_case_file(files[0] / "case.toml", overrides)
                            : case_for_geometry_files(files, overrides);
    config.quiet = true;
    config.simulation.stop = StopRule::Iterations;  // the study runs every iteration
    const MeshInputs in(config);
    const SpacingStage spacing(config, in);
    check_node_limit(config, in, spacing);
    NodeSet nodes = make_initial(config, in, spacing).nodes;
    SimOptions options = simulation_options(config);
    options.background = in.dense ? nullptr : &spacing.background();
    fmt::print("iteration,min_angle,aspect_ratio,settled,nodes,average_force,seconds\n");
    const auto start = std::chrono::steady_clock::now();
    // Population control's schedule, followed as the driver keeps it (an event is due by the same
    // rule; the row counts its insertions and removals), so that `settled` is
    // what the driver hands the rule.
    PopulationSchedule schedule;
    // The host driver updates `nodes` in place: in the callback they hold the iteration's positions,
    // after its population event, as when the rule measures them.
    SimCallbacks callbacks;
    callbacks.on_iteration = [&](const HistoryRow& row) {
      const int it = row.iteration;
      if (options.population.enabled && population_event_due(options.population, schedule, it, options.iterations))
        schedule.record(options.population, it, row.inserted + row.removed, nodes.size());
      if (it % every != 0) return;
      const bool settled = population_status(options.population, schedule, it, options.iterations).settled;
      const MeshSample s = measure_mesh(nodes, it);
      fmt::print("{},{:.6f},{:.8f},{},{},{:.6g},{:.2f}\n", it, s.min_angle, s.aspect_ratio, settled ? 1 : 0,
                 nodes.size(), row.average_force,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      std::fflush(stdout);
    };
    const SimResult r = run_simulation(nodes, in.node_tree(), spacing.field(), options, callbacks);
    if (!history_file.empty()) write_history_csv(history_file, r.history);
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "convergence_study: {}\n", e.what());
    return 1;
  }
}
