// `pdmesh bench`: times run_simulation on the host reference and the device-resident run on every
// OpenCL device, per case, and prints one table row per (case, backend). See bench_command.hpp.
#include "app/bench/bench_command.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <optional>

#include <fmt/format.h>

#include "app/config/case_file.hpp"
#include "app/config/case_spacing.hpp"
#include "app/bench/bench_floor.hpp"
#include "app/bench/graded_case.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "app/pipeline/run_phases.hpp"
#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "geometry/geometry.hpp"
#include "init/initial_distribution.hpp"
#include "opencl/command_counts.hpp"
#include "opencl/context.hpp"
#include "opencl/device_simulation.hpp"
#include "opencl/devices.hpp"
#include "opencl/step_program.hpp"

namespace pdmesh {
namespace {

struct BenchCase {
  std::string name;
  // A generated case owns its geometry, tree and field; a case file's come from MeshInputs, built
  // as pdmesh mesh builds them (the node geometry and boundary nodes of its settings).
  Geometry geometry;
  std::unique_ptr<GeometryTree> own_tree;
  std::unique_ptr<SpacingField> own_spacing;
  std::unique_ptr<MeshInputs> inputs;
  std::unique_ptr<SpacingStage> final_spacing;  // over *inputs: the initial distribution's field
  const GeometryTree* tree = nullptr;
  const SpacingField* spacing = nullptr;
  NodeSet initial;
  SimOptions options;
  std::optional<double> verlet_skin;  // a case file's simulation.verlet_skin; empty: automatic
};

std::unique_ptr<BenchCase> generated_case(std::size_t target) {
  auto c = std::make_unique<BenchCase>();
  c->name = fmt::format("graded_{}k", target / 1000);
  c->geometry = graded_case_geometry(graded_case_spacing(target));
  c->own_tree = std::make_unique<GeometryTree>(c->geometry);
  c->own_spacing = std::make_unique<BoundarySpacing>(*c->own_tree);
  c->tree = c->own_tree.get();
  c->spacing = c->own_spacing.get();
  c->initial = make_initial_distribution(*c->tree, *c->spacing, {}).nodes;
  c->options.stability_factor = 1.0;  // as pdmesh mesh
  return c;
}

std::unique_ptr<BenchCase> file_case(const std::string& dir, const std::string& name) {
  auto c = std::make_unique<BenchCase>();
  c->name = name;
  CaseConfig config = load_case_file(std::filesystem::path(dir) / name / "case.toml");
  config.quiet = true;
  c->inputs = std::make_unique<MeshInputs>(config);
  c->tree = &c->inputs->node_tree();
  c->spacing = c->inputs->spacing.get();
  c->final_spacing = std::make_unique<SpacingStage>(config, *c->inputs, SpacingStage::Build::FieldOnly);
  c->initial = make_initial(config, *c->inputs, *c->final_spacing).nodes;
  c->options.dt_initial = config.simulation.dt_for(config.init.method);
  c->options.cutoff = config.simulation.cutoff;
  c->options.lj_a = config.simulation.lj_a;
  c->options.r0_any_direction = config.simulation.r0_any_direction;
  c->options.stability_factor = config.simulation.stability_factor;
  c->options.momentum = config.simulation.momentum;
  c->options.momentum_mix = config.simulation.momentum_mix;
  c->verlet_skin = config.simulation.verlet_skin;
  return c;
}

// OpenCL commands of a device run (ocl::command_counts, counted by the wrapper) over one kind of
// window: a window of iterations is enqueued and read back at once (docs/opencl.md, "One iteration"),
// so its commands are all counted at its first row. Per window: the smallest, largest and summed
// launches, reads, writes, copies and waits; and the iterations it ran.
struct CommandSpread {
  int windows = 0, iterations = 0;
  std::array<std::uint64_t, 5> min{}, max{}, sum{};
  void add(const ocl::CommandCounts& c, int rows) {
    const std::array<std::uint64_t, 5> v = {c.launches, c.reads, c.writes, c.copies, c.waits};
    for (std::size_t k = 0; k < v.size(); ++k) {
      min[k] = windows == 0 ? v[k] : std::min(min[k], v[k]);
      max[k] = windows == 0 ? v[k] : std::max(max[k], v[k]);
      sum[k] += v[k];
    }
    ++windows;
    iterations += rows;
  }
  // "launches / reads / writes / copies / waits" per iteration (means; `per`: what `iterations` counts),
  // then per window: a count, or "min–max" where windows differ.
  std::string format(const char* per = "it.") const {
    if (windows == 0) return "-";
    std::string mean, spread;
    for (std::size_t k = 0; k < sum.size(); ++k) {
      if (k > 0) mean += " / ", spread += " / ";
      mean += fmt::format("{:.2f}", static_cast<double>(sum[k]) / iterations);
      spread += min[k] == max[k] ? fmt::format("{}", min[k]) : fmt::format("{}–{}", min[k], max[k]);
    }
    return fmt::format("{} ({} {} in {} windows; per window {})", mean, iterations, per, windows, spread);
  }
};

// Command counts of a device run's windows: the iterations' own (the rebuilds' taken out) per
// iteration, and the rebuilds' (DeviceRunStats::rebuild_commands) per rebuild. The first window (setup
// uploads and the first build) is left out.
struct IterationCommands {
  CommandSpread steady, rebuild;
};

struct Row {
  std::string case_name, backend;
  std::size_t nodes = 0;
  int iterations = 0;
  double seconds = 0.0;
  std::uint64_t pairs_within = 0, pairs_examined = 0;
  std::optional<ocl::DeviceRunStats> device;
  IterationCommands commands;
  std::size_t peak_rss = 0;
  double host_ms = 0.0;                // the host reference's ms/iteration in the same run (for the ratio)
  SimStats stats;                      // population events
  const FloorResult* floor = nullptr;  // the host CPU's pair-force floor at the case's node count (none: nullptr)
  // A device row: its device and precision, and that device's floor at the row's node count (none: nullptr).
  std::optional<ocl::DeviceInfo> device_info = std::nullopt;
  ocl::Precision precision = ocl::Precision::Double;
  const ocl::DeviceFloorResult* device_floor = nullptr;
};

std::string format_row(const Row& r) {
  const double per_it = r.seconds / r.iterations;
  const double node_its = static_cast<double>(r.nodes) * r.iterations / r.seconds;
  const double pairs = static_cast<double>(r.pairs_within) / r.seconds;
  std::string split = "-", traffic = "-", device_mem = "-", steady = "-", rebuild = "-", examined = "-";
  if (r.device) {
    const ocl::DeviceRunStats& d = *r.device;
    const double it = d.iterations;
    split = fmt::format(
        "bin {:.2f} / gather {:.2f} / step {:.2f} / host {:.2f} / down {:.2f} / up {:.2f} ({} rebuilds, {} from a "
        "sample, {} build passes, {} rows outgrew; largest spacing ratio {:.2f})",
        1e3 * d.bin_seconds / it, 1e3 * d.gather_seconds / it, 1e3 * d.step_seconds / it, 1e3 * d.host_seconds / it,
        1e3 * d.download_seconds / it, 1e3 * d.upload_seconds / it, d.rebuilds, d.sampled_builds, d.gathers,
        d.outgrown_rows, d.largest_spacing_ratio);
    traffic = fmt::format("{:.0f}", static_cast<double>(d.bytes_down + d.bytes_up) / it);
    device_mem = fmt::format("{:.0f}", static_cast<double>(d.device_bytes) / static_cast<double>(r.nodes));
    steady = r.commands.steady.format();
    rebuild = r.commands.rebuild.format("rebuilds");
    if (d.pairs_listed > 0)
      examined = fmt::format(
          "{:.2f} (rebuilds {:.2f} per listed entry, x{:.2f} skin, longest row {})",
          static_cast<double>(r.pairs_examined) / static_cast<double>(r.pairs_within),
          static_cast<double>(d.rebuild_candidates) / d.pairs_listed,
          static_cast<double>(d.pairs_listed) * it / d.rebuilds / static_cast<double>(r.pairs_within), d.stride);
  } else if (r.pairs_within > 0) {
    examined = fmt::format("{:.2f}", static_cast<double>(r.pairs_examined) / static_cast<double>(r.pairs_within));
  }
  if (r.stats.population_events > 0) {
    // Per iteration; on a device also the read-back and re-upload within it.
    const std::string transfer =
        r.device ? fmt::format(", transfers {:.2f}", 1e3 * r.device->population_transfer_seconds / r.iterations) : "";
    const double seconds = r.device ? r.device->population_seconds : r.stats.population_seconds;
    split = fmt::format("{}{}population {:.2f}{} ({} events, +{} -{})", split == "-" ? "" : split,
                        split == "-" ? "" : " / ", 1e3 * seconds / r.iterations, transfer, r.stats.population_events,
                        r.stats.inserted, r.stats.removed);
  }
  const std::string ratio = r.device && r.host_ms > 0.0 ? fmt::format("{:.2f}", r.host_ms / (1e3 * per_it)) : "-";
  // A device row against its device's floor, the host reference's against the CPU's.
  const std::string floor_ms = r.device_info ? device_floor_ms_cell(r.device_floor) : floor_ms_cell(r.floor);
  const std::string over_floor =
      r.device_info ? device_floor_ratio_cell(r.device_floor, per_it) : floor_ratio_cell(r.floor, per_it);
  return fmt::format(
      "| {} | {} | {} | {} | {:.3f} | {:.3g} | {:.3g} | {:.0f} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
      r.case_name, r.backend, r.nodes, r.iterations, 1e3 * per_it, node_its, pairs,
      1e9 * per_it / static_cast<double>(r.nodes), examined, split, traffic, steady, rebuild,
      fmt::format("{:.0f} / {}", static_cast<double>(r.peak_rss) / static_cast<double>(r.nodes), device_mem), ratio,
      floor_ms, over_floor);
}

// InputError naming the first argument out of range.
void check_arguments(const BenchArguments& args) {
  if (args.warmup < 0 || args.large_warmup < 0)
    throw InputError(fmt::format("bench: --warmup must be >= 0, got {}", args.warmup));
  if (args.iterations < 1 || args.large_iterations < 1)
    throw InputError(fmt::format("bench: --iterations and --large-iterations must be >= 1, got {} and {}",
                                 args.iterations, args.large_iterations));
  if (args.verlet_skin != kAutomaticSkin && !(args.verlet_skin >= 0.0 && args.verlet_skin <= 4.0))
    throw InputError(fmt::format("bench: --skin must be in [0, 4], got {}", args.verlet_skin));
  if (args.population_every < 0)
    throw InputError(fmt::format("bench: --population must be >= 0, got {}", args.population_every));
  if (args.floor_repeat < 0)
    throw InputError(fmt::format("bench: --floor-repeat must be >= 0, got {}", args.floor_repeat));
  if (args.precision != "double" && args.precision != "float")
    throw InputError(fmt::format("bench: --precision must be double or float, got '{}'", args.precision));
}

// `warm` iterations of the case on the first device (the host without one), moving c.initial on: the
// measured runs start where the warm-up ended, and with the dt_GM it returns (options.dt_initial
// without a warm-up).
std::optional<double> warm_up(BenchCase& c, const SimOptions& options, int warm,
                              const std::vector<ocl::DeviceInfo>& devices, ocl::Precision precision,
                              ocl::ForceLoop loop) {
  SimOptions w = options;
  w.iterations = warm;
  std::optional<ocl::Context> ctx;
  std::unique_ptr<Simulator> simulator = make_host_simulator();
  if (!devices.empty() && warm > 0) {
    ctx.emplace(devices.front());
    simulator = std::make_unique<ocl::DeviceSimulator>(*ctx, precision, loop);
  }
  if (warm > 0) {
    const SimResult r = simulator->run(c.initial, *c.tree, *c.spacing, w);
    // Continue with the dt_GM the warm-up ended with.
    if (!r.history.empty()) return r.history.back().dt_gm;
  }
  return options.dt_initial;
}

// The row of one device: the run, with its commands per iteration from the wrapper's counts.
Row device_row(const BenchCase& c, const ocl::DeviceInfo& info, const SimOptions& o, ocl::Precision precision,
               ocl::ForceLoop loop, const std::string& suffix, double host_ms) {
  ocl::Context ctx(info);
  NodeSet nodes = c.initial;
  ocl::DeviceSimulator simulator(ctx, precision, loop);
  // Commands per iteration from the wrapper's counts; the simulator's stats are live during the run.
  // A window's commands come before its first row (and the host's work at its last); the simulator's
  // live stats say where a window starts.
  IterationCommands commands;
  ocl::CommandCounts last = ocl::command_counts(), window, last_rebuild, rebuild;
  int last_rebuilds = 0, rows = 0, windows = 0, last_windows = 0, rebuilt = 0;
  const auto close_window = [&] {
    if (windows <= 1) return;
    commands.steady.add(window - rebuild, rows);
    if (rebuilt > 0) commands.rebuild.add(rebuild, rebuilt);
  };
  SimCallbacks callbacks;
  callbacks.on_iteration = [&](const HistoryRow&) {
    const ocl::CommandCounts now = ocl::command_counts(), d = now - last;
    const int rebuilds = simulator.stats().rebuilds;
    if (windows == 0 || simulator.stats().windows != last_windows) {
      close_window();
      ++windows;
      window = rebuild = ocl::CommandCounts{};
      rows = rebuilt = 0;
    }
    window = window + d;
    rebuild = rebuild + (simulator.stats().rebuild_commands - last_rebuild);
    last_rebuild = simulator.stats().rebuild_commands;
    rebuilt += rebuilds - last_rebuilds;
    last_windows = simulator.stats().windows;
    ++rows;
    last = now;
    last_rebuilds = rebuilds;
  };
  const SimResult r = simulator.run(nodes, *c.tree, *c.spacing, o, callbacks);
  close_window();
  Row row{c.name,
          fmt::format("opencl:{}:{} {} ({}, {} loop){}", info.platform, info.device, info.type,
                      precision == ocl::Precision::Float ? "float" : "double",
                      ocl::force_loop_name(simulator.force_loop()), suffix),
          nodes.size(),
          o.iterations,
          r.stats.seconds,
          r.stats.pairs_within,
          r.stats.pairs_examined,
          simulator.stats(),
          commands,
          peak_rss_bytes(),
          host_ms,
          r.stats};
  row.device_info = info;
  row.precision = precision;
  return row;
}

}  // namespace

int run_bench(const BenchArguments& args) {
  check_arguments(args);
  const ocl::ForceLoop loop = ocl::parse_force_loop(args.force_loop, "bench: --force-loop");
  const std::vector<ocl::DeviceInfo> devices = ocl::list_devices();
  const auto precision_on = [&args](const ocl::DeviceInfo& d) {
    return args.precision == "float" || !d.fp64 ? ocl::Precision::Float : ocl::Precision::Double;
  };
  std::string table =
      "| case | backend | nodes | iterations | ms/iteration | node-iterations/s | pair interactions/s | ns per "
      "node-iteration | pairs examined per pair | device split, ms/iteration | bytes/iteration | commands per "
      "iteration, rebuilds left out: launches / reads / writes / copies / waits | the same per rebuild "
      "| peak host RSS / device bytes per node | host/device time | pair-force floor, ms/iteration: the host CPU's "
      "scalar / vector (host rows), the device's (OpenCL rows) | x floor (of the row's own floor) |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::string floors;
  fmt::print("{}", table);
  for (const std::string& name : args.cases) {
    const bool large = name == "graded_1m";
    std::unique_ptr<BenchCase> c = large ? generated_case(args.large_nodes) : file_case(args.cases_dir, name);
    SimOptions options = c->options;
    options.iterations = large ? args.large_iterations : args.iterations;
    options.quiet = true;
    options.verlet_skin = args.verlet_skin != kAutomaticSkin
                              ? args.verlet_skin
                              : c->verlet_skin.value_or(auto_verlet_skin(options.momentum, c->initial.size()));
    const std::string suffix =
        args.population_every > 0 ? fmt::format(", population every {}", args.population_every) : std::string();
    options.dt_initial = warm_up(*c, options, large ? args.large_warmup : args.warmup, devices,
                                 devices.empty() ? ocl::Precision::Double : precision_on(devices.front()), loop);
    if (args.population_every > 0) {
      options.population.enabled = true;
      options.population.every = args.population_every;
      options.population.start = args.population_every;
      options.population.stop = 1.0;
    }
    double host_ms = 0.0;
    // A case's rows are printed after its floor is measured, which comes after its runs, so that the
    // floor's arrays do not count in the runs' peak memory.
    std::vector<Row> rows;
    auto emit = [&](const Row& row) { rows.push_back(row); };
    if (!args.skip_host && !(large && args.skip_host_large)) {
      NodeSet nodes = c->initial;
      const SimResult r = run_simulation(nodes, *c->tree, *c->spacing, options);
      Row row{c->name,
              "host reference" + suffix,
              nodes.size(),
              options.iterations,
              r.stats.seconds,
              r.stats.pairs_within,
              r.stats.pairs_examined,
              std::nullopt,
              {},
              peak_rss_bytes(),
              0.0,
              r.stats};
      host_ms = 1e3 * r.stats.seconds / options.iterations;
      emit(row);
    }
    for (const ocl::DeviceInfo& info : devices)
      emit(device_row(*c, info, options, precision_on(info), loop, suffix, host_ms));
    const FloorResult* floor = nullptr;
    if (args.floor_repeat > 0 && !rows.empty()) {
      floor = &bench_floor(rows.front().nodes, args.floor_repeat, options.cutoff, options.lj_a);
      floors += fmt::format("- {}: {}\n", c->name, format_floor(*floor));
    }
    for (Row& row : rows) {
      row.floor = floor;
      if (args.floor_repeat > 0 && row.device_info) {
        row.device_floor = bench_device_floor(*row.device_info, row.precision, row.nodes, args.floor_repeat,
                                              options.cutoff, options.lj_a);
        if (row.device_floor != nullptr)
          floors += fmt::format("- {}: {}\n", c->name, ocl::format_device_floor(*row.device_floor));
      }
      const std::string line = format_row(row);
      fmt::print("{}", line);
      std::fflush(stdout);
      table += line;
    }
  }
  if (!floors.empty()) {
    floors =
        "\nThe pair-force floor at each case's node count: on the host CPU (sim/pair_floor.hpp), the host "
        "reference rows' x floor; on each OpenCL device (opencl/device_floor.hpp, the same iteration in "
        "kernels/pair_floor.cl, its best kernel time), that device's rows' x floor:\n\n" +
        floors;
    fmt::print("{}", floors);
    table += floors;
  }
  if (!args.out.empty()) write_file_atomically(args.out, table);
  return 0;
}

}  // namespace pdmesh
