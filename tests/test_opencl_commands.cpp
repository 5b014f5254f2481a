// What the OpenCL wrapper counts (opencl/command_counts.hpp: launches, reads, writes, device copies,
// host waits), the commands a device run enqueues per iteration as `pdmesh bench` reports them, and
// the choice of the force loop's shape (opencl/step_program.hpp: by device type, PDMESH_FORCE_LOOP,
// or explicitly; the kernel refuses a program built without exactly one shape).
#include <catch2/catch.hpp>

#include "opencl/device_window.hpp"

#include <algorithm>
#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/bench/bench_command.hpp"
#include "core/errors.hpp"
#include "device_run_fixtures.hpp"
#include "scoped_env.hpp"
#include "opencl/buffer.hpp"
#include "opencl/command_counts.hpp"
#include "opencl/context.hpp"
#include "opencl/step_program.hpp"
#include "selftest_axpy.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
using namespace pdmesh::ocl;

using pdmesh_test::ScopedEnv;

TEST_CASE("the wrapper counts launches, transfers, device copies and waits", "[opencl]") {
  auto info = select_device("auto");
  REQUIRE(info.has_value());
  Context ctx(*info);  // no canary tail: its checks are not counted anyway
  const std::size_t wg = 8;
  const int n = 13;
  const std::vector<float> x(n, 1.5f);
  Buffer<float> bx(ctx, "x", n), by(ctx, "y", n), bz(ctx, "z", n);
  cl::Kernel k = pdmesh::test::selftest_axpy(ctx, wg, n, bx, by);

  const CommandCounts start = command_counts();
  bx.upload(ctx.queue(), x);         // blocking: a write and a wait
  by.upload(ctx.queue(), x, false);  // non-blocking: a write
  launch(ctx.queue(), k, "selftest_axpy", n, wg);
  copy_buffer(ctx.queue(), by.get(), bz.get(), n * sizeof(float), "copy y to z");
  fill_zero(ctx.queue(), by.get(), n * sizeof(float), "clear y");
  std::vector<float> y, z, none;
  by.download(ctx.queue(), y, n, false);           // non-blocking: a read
  finish(ctx.queue(), "reads");                    // a wait
  bz.download(ctx.queue(), z);                     // blocking: a read and a wait
  bz.download(ctx.queue(), none, 0);               // nothing to read: no command
  launch(ctx.queue(), k, "selftest_axpy", 0, wg);  // no work-items: no command
  const CommandCounts d = command_counts() - start;

  CHECK(d.launches == 1);
  CHECK(d.writes == 2);
  CHECK(d.reads == 2);
  CHECK(d.copies == 2);
  CHECK(d.waits == 3);
  CHECK(d.bytes_written == 2 * n * sizeof(float));
  CHECK(d.bytes_read == 2 * n * sizeof(float));
  // The copy and the fill did what they say (y = 2 x + i before the copy, zeros after the fill).
  for (int i = 0; i < n; ++i) {
    CHECK(z[i] == 2.0f * 1.5f + static_cast<float>(i));
    CHECK(y[i] == 0.0f);
  }
}

TEST_CASE("a device run's iterations: 2 launches each, one wait per window without a rebuild, more with one",
          "[opencl][device_sim]") {
  const test::Case c = test::load_case("circle_circle");
  SimOptions o = test::options_for(c, 60);
  DeviceSimulator simulator(test::test_context(), ocl::Precision::Double);
  // The commands of a window come before its first row (the host enqueues and reads the whole window
  // before it hands out the rows) and, for the host's work, its last: a chunk is one window's rows.
  struct Chunk {
    int rows = 0;
    CommandCounts d, rebuild;  // all commands, and the rebuilds' among them
    int rebuilds = 0;
  };
  std::vector<Chunk> chunks;
  CommandCounts last = command_counts();
  int last_rebuilds = 0, last_windows = 0;
  CommandCounts last_rebuild;
  SimCallbacks callbacks;
  callbacks.on_iteration = [&](const HistoryRow&) {
    const CommandCounts d = command_counts() - last;
    last = command_counts();
    const int rebuilds = simulator.stats().rebuilds;
    if (chunks.empty() || simulator.stats().windows != last_windows) chunks.push_back(Chunk{});
    Chunk& k = chunks.back();
    k.d = k.d + d;
    k.rebuild = k.rebuild + (simulator.stats().rebuild_commands - last_rebuild);
    last_rebuild = simulator.stats().rebuild_commands;
    k.rebuilds += rebuilds - last_rebuilds;
    ++k.rows;
    last_windows = simulator.stats().windows;
    last_rebuilds = rebuilds;
  };
  NodeSet nodes = c.initial;
  simulator.run(nodes, c.inputs->node_tree(), *c.inputs->spacing, o, callbacks);
  int rows = 0, long_windows = 0, rebuilds = 0;
  std::uint64_t waits = 0;
  REQUIRE(chunks.size() > 2);
  chunks.erase(chunks.begin());  // the first window holds the setup
  for (const Chunk& k : chunks) {
    const CommandCounts d = k.d - k.rebuild;  // the iterations' own
    INFO(k.rows << " iterations, " << k.rebuilds << " rebuilds: " << d.launches << " launches, " << d.reads
                << " reads, " << d.writes << " writes, " << d.copies << " copies, " << d.waits
                << " waits; the rebuilds " << k.rebuild.launches << " launches, " << k.rebuild.waits << " waits");
    CHECK(d.waits >= 1);  // the window's rows are read once
    CHECK(d.reads >= 1);
    // device_step and boundary_snap_rule (the time-step rule in its last work-group) per iteration
    // enqueued (at least the rows it ran, at most a ring's worth; + apply_host_moves after its last row
    // when the host moved nodes), one wait for the rows (+ one for the host's nodes), no copies.
    CHECK(d.launches >= 2 * static_cast<std::uint64_t>(k.rows));
    CHECK(d.launches <= 2 * static_cast<std::uint64_t>(ocl::kWindowLength) + 1);
    CHECK(d.waits <= 2);
    CHECK(d.copies == 0);
    if (k.rebuilds > 0)
      CHECK(k.rebuild.launches >= 2 * static_cast<std::uint64_t>(k.rebuilds));  // the neighbour kernels
    rows += k.rows;
    waits += d.waits;
    rebuilds += k.rebuilds;
    long_windows += k.rows >= 8 && d.waits == 1;
  }
  CHECK(long_windows > 0);
  CHECK(waits < static_cast<std::uint64_t>(rows));  // fewer waits than iterations (one each before the windows)
  CHECK(rebuilds > 1);
}

TEST_CASE("the force loop is chosen by device type, PDMESH_FORCE_LOOP, or explicitly", "[opencl]") {
  {
    const ScopedEnv unset("PDMESH_FORCE_LOOP", std::nullopt);
    CHECK(resolve_force_loop(ForceLoop::Auto, "CPU") == ForceLoop::Vector);
    CHECK(resolve_force_loop(ForceLoop::Auto, "GPU") == ForceLoop::Scalar);
    CHECK(resolve_force_loop(ForceLoop::Auto, "accelerator") == ForceLoop::Scalar);
    CHECK(resolve_force_loop(ForceLoop::Scalar, "CPU") == ForceLoop::Scalar);
    CHECK(resolve_force_loop(ForceLoop::Vector, "GPU") == ForceLoop::Vector);
  }
  {
    const ScopedEnv scalar("PDMESH_FORCE_LOOP", "scalar");
    CHECK(resolve_force_loop(ForceLoop::Auto, "CPU") == ForceLoop::Scalar);
    CHECK(resolve_force_loop(ForceLoop::Vector, "CPU") == ForceLoop::Vector);  // explicit wins
  }
  {
    const ScopedEnv automatic("PDMESH_FORCE_LOOP", "auto");
    CHECK(resolve_force_loop(ForceLoop::Auto, "GPU") == ForceLoop::Scalar);
  }
  {
    const ScopedEnv bad("PDMESH_FORCE_LOOP", "fast");
    REQUIRE_THROWS_AS(resolve_force_loop(ForceLoop::Auto, "CPU"), InputError);
    REQUIRE_THROWS_WITH(resolve_force_loop(ForceLoop::Auto, "CPU"),
                        "the environment variable PDMESH_FORCE_LOOP must be auto, vector or scalar, got 'fast'");
  }
  CHECK(parse_force_loop("vector", "--force-loop") == ForceLoop::Vector);
  REQUIRE_THROWS_WITH(parse_force_loop("Scalar", "--force-loop"), Catch::Contains("--force-loop must be"));
  CHECK(std::string(force_loop_name(ForceLoop::Scalar)) == "scalar");
  BenchArguments bench;
  bench.force_loop = "wide";
  REQUIRE_THROWS_WITH(run_bench(bench), Catch::Contains("bench: --force-loop must be auto, vector or scalar"));
}

TEST_CASE("the program carries exactly one force-loop define, and the kernels refuse anything else", "[opencl]") {
  const auto scalar = step_program_defines(ocl::Precision::Double, 64, ForceLoop::Scalar);
  CHECK(scalar.at("PDMESH_FORCE_LOOP_SCALAR") == "1");
  CHECK(scalar.at("PDMESH_FORCE_LOOP_VECTOR") == "0");
  CHECK(scalar.at("REAL") == "double");
  const auto vector = step_program_defines(ocl::Precision::Float, 64, ForceLoop::Vector);
  CHECK(vector.at("PDMESH_FORCE_LOOP_VECTOR") == "1");
  CHECK(vector.at("PDMESH_FORCE_LOOP_SCALAR") == "0");
  // The GPU shape refreshes clearance budgets in refresh_budgets, the CPU shape inside device_step.
  CHECK(scalar.at("PDMESH_REFRESH_KERNEL") == "1");
  CHECK(vector.at("PDMESH_REFRESH_KERNEL") == "0");
  REQUIRE_THROWS_AS(step_program_defines(ocl::Precision::Double, 64, ForceLoop::Auto), DeviceError);
  const std::string source = program_source(step_program_files(), scalar);
  // The defines come first, in name order (the map's), the first one opening the source.
  CHECK(source.rfind(fmt::format("#define {} {}\n", scalar.begin()->first, scalar.begin()->second), 0) == 0);
  CHECK(source.find("#define PDMESH_DOUBLE 1\n") < source.find("#define REAL double\n"));
  // The slots of the words a neighbour build leaves for the host, one definition for host and kernels.
  CHECK(scalar.at("BIN_FIRST_INVALID") == std::to_string(kBinFirstInvalid));
  CHECK(scalar.at("BIN_LEVEL_COUNT") == std::to_string(kBinHead));
  CHECK(scalar.at("ROW_SPILLED") == std::to_string(kRowSpilled));
  CHECK(scalar.at("ROW_SPARE_FULL") == std::to_string(kRowSpareFull));
  CHECK(scalar.at("ROW_RATIO") == std::to_string(kRowCounters - 1));
  CHECK(scalar.at("ROW_RATIO_SCALE") == std::to_string(kRowRatioScale));
  CHECK(scalar.at("SKIN_CLASS_STEPS") == std::to_string(kSkinClassSteps));
  CHECK(scalar.at("MAX_GAP_FRACTION") == "REAL_C(0.45)");  // BoundaryHandler::kMaxGapFraction
  // The partial sums' widths and the step counters' slots, also one definition for both sides.
  CHECK(scalar.at("STEP_PARTIALS") == std::to_string(kStepPartials));
  CHECK(scalar.at("BOUNDARY_PARTIALS") == std::to_string(kBoundaryPartials));
  CHECK(scalar.at("COUNTER_CANDIDATES") == std::to_string(ocl::kCounterCandidates));
  CHECK(scalar.at("COUNTER_NON_FINITE") == std::to_string(ocl::kCounterNonFinite));
  CHECK(scalar.at("COUNTER_HOST") == std::to_string(ocl::kCounterHost));
  CHECK(source.find("#define PDMESH_FORCE_LOOP_SCALAR 1\n") != std::string::npos);
  CHECK(source.find("// ---- forces.cl ----") != std::string::npos);

  Context& ctx = test::test_context();
  for (const ForceLoop loop : {ForceLoop::Vector, ForceLoop::Scalar}) {
    const StepProgram program(ctx, ocl::Precision::Float, loop);
    CHECK(program.force_loop == loop);
  }
  auto neither = vector;
  neither["PDMESH_FORCE_LOOP_VECTOR"] = "0";
  REQUIRE_THROWS_WITH(ctx.build(step_program_files(), neither),
                      Catch::Contains("exactly one of PDMESH_FORCE_LOOP_VECTOR and PDMESH_FORCE_LOOP_SCALAR"));
}

TEST_CASE("bench reports the force loop and the commands per iteration", "[opencl][bench]") {
  const std::filesystem::path out = pdmesh_test::fresh_path("bench_commands.md");
  BenchArguments args;
  args.cases = {"circle_circle"};
  args.cases_dir = pdmesh::test::source_dir() + "/cases";
  args.iterations = 6;
  args.warmup = 0;
  args.skip_host = true;
  args.force_loop = "scalar";
  args.out = out.string();
  REQUIRE(run_bench(args) == 0);
  std::ifstream f(out);
  std::stringstream text;
  text << f.rdbuf();
  std::filesystem::remove(out);
  const std::string table = text.str();
  INFO(table);
  CHECK(table.find("launches / reads / writes / copies / waits") != std::string::npos);
  CHECK(table.find("(double, scalar loop)") != std::string::npos);
  CHECK(table.find(" it. in ") != std::string::npos);  // the iterations of at least one window were counted
  // The pair-force floor at the case's node count, on the CPU and on the device: their lines, and the
  // device row's ratio to its device's floor (the last two cells: "device T" and ms/iteration over T).
  CHECK(table.find("circle_circle: pair-force floor at ") != std::string::npos);
  CHECK(table.find("circle_circle: device pair-force floor at ") != std::string::npos);
  CHECK(table.find("| x floor") != std::string::npos);
  const std::size_t row = table.find("| circle_circle | opencl");
  REQUIRE(row != std::string::npos);
  const std::string line = table.substr(row, table.find('\n', row) - row);
  std::vector<std::string> cells;
  for (std::size_t b = 1, e; (e = line.find(" |", b)) != std::string::npos; b = e + 2)
    cells.push_back(line.substr(b + 1, e - b - 1));
  REQUIRE(cells.size() == 17);
  const std::string floor = cells[15];
  REQUIRE(floor.rfind("device ", 0) == 0);
  const double ms = std::stod(cells[4]), floor_ms = std::stod(floor.substr(7)), ratio = std::stod(cells[16]);
  CHECK(ratio > 0.0);
  // Both printed rounded: ms to 3 decimals, the floor to 3, the ratio to 2.
  CHECK(std::abs(ratio - ms / floor_ms) <= 1.1 * (0.005 + 0.0005 / floor_ms + 0.0005 * ms / (floor_ms * floor_ms)));
}
