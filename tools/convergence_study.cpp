// Convergence study: runs one case for simulation.iterations iterations in chunks (each chunk resumes
// the state of the last, which the drivers continue bit-identically), and after every chunk
// triangulates the nodes and measures the mesh, so that the quality can be read against the
// iteration. Writes one CSV line per chunk on stdout and the run's history to --history; the
// stopping rule (sim/convergence) is judged against these with tools/convergence_check.py.
// Usage: convergence_study CASE.toml [--set KEY=VALUE ...] [--chunk N] [--history FILE]
#include <fmt/format.h>

#include <chrono>
#include <string>
#include <vector>

#include "app/case_file.hpp"
#include "app/mesh_command.hpp"
#include "core/errors.hpp"
#include "mesh/quality.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "sim/history.hpp"

int main(int argc, char** argv) {
  using namespace pdmesh;
  try {
    if (argc < 2) {
      fmt::print(stderr, "usage: convergence_study CASE.toml [--set KEY=VALUE ...] [--chunk N] [--history FILE]\n");
      return 2;
    }
    std::vector<CaseOverride> overrides;
    int chunk = 50;
    std::string history_file;
    for (int a = 2; a < argc; ++a) {
      const std::string arg = argv[a];
      if (arg == "--set" && a + 1 < argc) overrides.push_back(parse_set_option(argv[++a]));
      else if (arg == "--chunk" && a + 1 < argc) chunk = std::stoi(argv[++a]);
      else if (arg == "--history" && a + 1 < argc) history_file = argv[++a];
      else throw InputError(fmt::format("convergence_study: unknown argument '{}'", arg));
    }
    CaseConfig config = load_case_file(argv[1], overrides);
    config.quiet = true;
    config.simulation.stop = StopRule::Iterations;  // the study runs every iteration
    const MeshInputs inputs(config);
    NodeSet nodes = make_initial(config, inputs).nodes;
    const int total = static_cast<int>(config.simulation.iterations);
    SimState state;
    bool have_state = false;
    fmt::print("iteration,min_angle,max_angle,aspect_ratio_avg,triangles,points,seconds\n");
    const auto start = std::chrono::steady_clock::now();
    for (int done = 0; done < total;) {
      const int next = std::min(total, done + chunk);
      CaseConfig c = config;
      c.simulation.iterations = next;
      c.simulation.device = "host";
      const SimResult r = [&] {
        // simulate() writes files; the study only needs the state, so it calls the driver directly.
        SimOptions o = simulation_options(c);
        o.resume = have_state ? &state : nullptr;
        return run_simulation(nodes, *inputs.tree, *inputs.spacing, o);
      }();
      state = r.state;
      have_state = true;
      done = next;
      const Mesh mesh = triangulate(nodes, inputs.curve_names());
      const QualitySummary s = summarize_quality(mesh);
      fmt::print("{},{:.4f},{:.4f},{:.6f},{},{},{:.2f}\n", done, s.min_angle, s.max_angle, s.aspect_ratio_avg,
                 s.triangles, s.points,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      std::fflush(stdout);
    }
    if (!history_file.empty()) write_history_csv(history_file, state.history);
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "convergence_study: {}\n", e.what());
    return 1;
  }
}
