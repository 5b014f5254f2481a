// `pdmesh bench`: the simulation's speed on the host reference and on each OpenCL device, over
// naca0012, rods_fine, 30p30n and a generated ~1M-node case graded 1000x (docs/performance.md).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace pdmesh {

// BenchArguments::verlet_skin when --skin is not given.
inline constexpr double kAutomaticSkin = -1.0;

struct BenchArguments {
  std::vector<std::string> cases = {"naca0012", "rods_fine", "30p30n", "graded_1m"};
  std::string cases_dir = "cases";  // where the named cases live
  int iterations = 50;              // per case and backend
  int large_iterations = 10;        // for graded_1m
  std::size_t large_nodes = 1'000'000;
  // Untimed iterations from the initial distribution (on the first OpenCL device, else the host)
  // before every backend is timed from the same warmed-up state: the first ~100 iterations of a
  // run move nodes far (lists rebuilt every iteration) and are not what most of a 2000-iteration run costs.
  int warmup = 200;
  int large_warmup = 20;
  std::string precision = "double";
  // Device runs: Verlet list radius cutoff q (1 + skin); kAutomaticSkin: as pdmesh mesh picks it
  // (a case file's simulation.verlet_skin, else auto_verlet_skin for the case's node count).
  double verlet_skin = kAutomaticSkin;
  bool skip_host = false;           // devices only
  bool skip_host_large = false;     // the host reference takes seconds per iteration at 1M nodes
  std::string force_loop = "auto";  // device runs: auto | vector | scalar (kernels/forces.cl; docs/opencl.md)
  std::string out;                  // the table as Markdown (atomic write); empty: stdout only
  // > 0: population control during the timed iterations, an event every this many iterations (the
  // first after as many, none skipped for settling), so that the cost of events and re-uploads shows.
  int population_every = 0;
  // Repetitions of the pair-force floor (sim/pair_floor.hpp) measured at each case's node count, whose
  // best gives each row's ratio to the floor; 0: no floor.
  int floor_repeat = 5;
  // --whole-run: the `mesh` command end to end instead (app/bench/whole_run_bench.hpp).
  bool whole_run = false;
  int repeat = 3;                                // runs per case and backend
  std::vector<std::string> backends = {"auto"};  // --device of each run
  std::vector<std::string> sets;                 // --set KEY=VALUE passed to every run
  std::string work_dir = "bench_runs";           // outputs of the runs and the generated cases
  bool keep_pictures = true;                     // false: --formats msh (no pictures)
};

// Runs the benchmark and prints the table; returns the exit status.
int run_bench(const BenchArguments& args);

}  // namespace pdmesh
