// Runs that go wrong (issue #7): non-finite forces or moves stop both backends at once with the
// node and its neighbourhood and hand over the last good state; a lost OpenCL device (fault hook
// PDMESH_TEST_FAIL_CL_AT) leaves a checkpoint that resumes; too little device memory is refused
// with the figures; coordinates too large for the spacing are refused; damaged checkpoints are refused.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cfloat>
#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "init/initial_distribution.hpp"
#include "io/text_file.hpp"
#include "opencl/device_simulation.hpp"
#include "run_pdmesh.hpp"
#include "sim/boundary_handling.hpp"
#include "sim/checkpoint.hpp"
#include "sim/simulation.hpp"
#include "spacing/resolution_check.hpp"
#include "spacing/spacing_field.hpp"
#include "device_run_fixtures.hpp"
#include "step_backend_inputs.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;
using Catch::Contains;
using pdmesh_test::fresh_path;
using pdmesh_test::run_pdmesh;

namespace {

// The square [-1, 1]^2 as one closed curve with points every 0.25 (the Boundary nodes), uniform
// spacing 0.25 (about 90 nodes).
struct SquareCase {
  Geometry geometry;
  std::unique_ptr<GeometryTree> tree;
  ExpressionSpacing spacing{"0.25"};
  NodeSet nodes;
  SquareCase() {
    RawCurve square{"square", {{-1, -1}}, "square", 1, {}};
    for (const Vec2 d : {Vec2{1, 0}, Vec2{0, 1}, Vec2{-1, 0}, Vec2{0, -1}})
      for (int k = 1; k <= 8; ++k) square.points.push_back(square.points.back() + 0.25 * d);
    square.points.back() = {-1, -1};
    geometry = build_geometry({square});
    tree = std::make_unique<GeometryTree>(geometry);
    nodes = make_initial_distribution(*tree, spacing, {InitMethod::Structured, 1, {}}).nodes;
  }
  // Puts two interior nodes 1e-30 apart at the origin: (q/r)^12 overflows, the force is infinite.
  std::pair<std::size_t, std::size_t> collide() {
    std::size_t a = 0;
    while (nodes.kind[a] != NodeKind::Interior) ++a;
    std::size_t b = a + 1;
    while (nodes.kind[b] != NodeKind::Interior) ++b;
    nodes.x[a] = {0.0, 0.0};
    nodes.x[b] = {1e-30, 0.0};
    return {a, b};
  }
};

// The reference backend, except that at one iteration one node's move becomes +inf.
class PoisonedMoves : public StepBackend {
 public:
  PoisonedMoves(int at_call, std::size_t node) : at_call_(at_call), node_(node) {}
  std::string name() const override { return "poisoned reference"; }
  void build_neighbours(const SimParticles& p, double cutoff, NeighbourList& list, NeighbourFlags& flags) override {
    reference_->build_neighbours(p, cutoff, list, flags);
  }
  void compute_forces(const SimParticles& p, const NeighbourList& list, const ForceParams& params,
                      ForceResult& out) override {
    reference_->compute_forces(p, list, params, out);
  }
  void time_step_and_move(const SimParticles& p, const ForceResult& forces, double dt_gm2, MoveResult& out) override {
    reference_->time_step_and_move(p, forces, dt_gm2, out);
    if (++calls_ == at_call_) out.dx[node_] = HUGE_VAL;
  }
  void apply_momentum(const SimParticles& p, const ForceResult& forces, double beta, double mix, MoveResult& moves,
                      MomentumState& carried) override {
    reference_->apply_momentum(p, forces, beta, mix, moves, carried);
  }
  StepSums reduce(const SimParticles& p, const ForceResult& forces, const MoveResult& moves) override {
    return reference_->reduce(p, forces, moves);
  }

 private:
  std::unique_ptr<StepBackend> reference_ = make_reference_backend();
  int at_call_, calls_ = 0;
  std::size_t node_;
};

SimOptions quiet_options(int iterations) {
  SimOptions o;
  o.iterations = iterations;
  o.dt_initial = 0.01;
  o.quiet = true;
  return o;
}

}  // namespace

TEST_CASE("a non-finite move of a boundary node stops the host run before anything moves", "[failures][sim]") {
  SquareCase c;
  std::size_t boundary = 0;
  while (c.nodes.kind[boundary] != NodeKind::Boundary) ++boundary;
  // The last good state is the one after 3 iterations: an unpoisoned 3-iteration run gives it.
  NodeSet clean = c.nodes;
  run_simulation(clean, *c.tree, c.spacing, quiet_options(3));

  PoisonedMoves backend(4, boundary);
  SimOptions options = quiet_options(10);
  options.backend = &backend;
  std::optional<SimState> saved;
  SimCallbacks callbacks;
  callbacks.on_failure = [&](const SimState& s) { saved = s; };
  CHECK_THROWS_WITH(run_simulation(c.nodes, *c.tree, c.spacing, options, callbacks),
                    Contains("iteration 4: non-finite move") &&
                        Contains(fmt::format("on node {} (boundary) at (", boundary)) && Contains("within"));
  REQUIRE(saved);
  CHECK(saved->iterations_done == 3);
  CHECK(saved->history.size() == 3);
  for (std::size_t i = 0; i < c.nodes.size(); ++i) {
    INFO("node " << i);
    CHECK(std::isfinite(c.nodes.x[i].x));
    CHECK(c.nodes.x[i].x == clean.x[i].x);  // bit-identical: boundary handling never ran on iteration 4
    CHECK(c.nodes.x[i].y == clean.x[i].y);
  }
}

TEST_CASE("two nodes 1e-30 apart: non-finite forces stop the host run naming both nodes", "[failures][sim]") {
  SquareCase c;
  const auto [a, b] = c.collide();
  const NodeSet before = c.nodes;
  std::optional<SimState> saved;
  SimCallbacks callbacks;
  callbacks.on_failure = [&](const SimState& s) { saved = s; };
  CHECK_THROWS_WITH(run_simulation(c.nodes, *c.tree, c.spacing, quiet_options(10), callbacks),
                    Contains("iteration 1: non-finite force") &&
                        Contains(fmt::format("on node {} (interior) at (0, 0)", a)) &&
                        Contains(fmt::format("node {} (interior) at (1.0000000000000001e-30, 0) distance 1e-30", b)));
  REQUIRE(saved);
  CHECK(saved->iterations_done == 0);
  CHECK(c.nodes.x == before.x);
}

TEST_CASE("two nodes 1e-30 apart: the device run stops too and hands over its last good state", "[failures][opencl]") {
  SquareCase c;
  const auto [a, b] = c.collide();
  const NodeSet before = c.nodes;
  SimOptions options = quiet_options(10);
  ocl::DeviceSimulator device(test::test_context(), ocl::Precision::Double);
  std::optional<SimState> saved;
  SimCallbacks callbacks;
  callbacks.on_failure = [&](const SimState& s) { saved = s; };
  CHECK_THROWS_WITH(device.run(c.nodes, *c.tree, c.spacing, options, callbacks),
                    Contains("iteration 1: non-finite force or move") &&
                        Contains(fmt::format("node {} (interior)", a)) &&
                        Contains(fmt::format("node {} (interior)", b)) && Contains("distance 1e-30"));
  REQUIRE(saved);
  CHECK(saved->iterations_done == 0);
  CHECK(saved->history.empty());
  // Read back from the device: the positions uploaded, exactly (double precision).
  CHECK(c.nodes.x == before.x);
  check_checkpoint_fits(Checkpoint{{}, c.nodes, *saved}, *c.tree, "saved");
}

// A boundary node's move that is not finite: device_step raises its flag, boundary_snap (which
// re-snaps the boundary nodes on the device, updating tangents in place) writes nothing, and the state
// handed over is the one before the step, boundary positions, tangents and arc positions included.
TEST_CASE("a non-finite boundary move stops the device run with the boundary state before the step",
          "[failures][opencl]") {
  SquareCase c;
  std::size_t b = 0;  // the boundary node at (0, -1)
  while (!(c.nodes.kind[b] == NodeKind::Boundary && c.nodes.x[b].x == 0.0 && c.nodes.x[b].y == -1.0)) ++b;
  std::size_t a = 0;
  while (c.nodes.kind[a] != NodeKind::Interior) ++a;
  c.nodes.x[a] = {1e-30, -1.0};
  const NodeSet before = c.nodes;
  const BoundaryHandler fresh(*c.tree, before);
  ocl::DeviceSimulator device(test::test_context(), ocl::Precision::Double);
  std::optional<SimState> saved;
  SimCallbacks callbacks;
  callbacks.on_failure = [&](const SimState& s) { saved = s; };
  CHECK_THROWS_WITH(
      device.run(c.nodes, *c.tree, c.spacing, quiet_options(10), callbacks),
      Contains("iteration 1: non-finite force or move") && Contains(fmt::format("node {} (boundary)", b)));
  REQUIRE(saved);
  CHECK(saved->iterations_done == 0);
  CHECK(c.nodes.x == before.x);
  CHECK(saved->tangents == fresh.tangents());
  CHECK(saved->arcs == fresh.arcs());
}

TEST_CASE("a lost OpenCL device leaves a checkpoint of a good state that resumes", "[failures][opencl][cli]") {
  const std::string kase = PDMESH_SOURCE_DIR "/cases/circle_circle";
  for (const char* fault : {"300", "300:-2"}) {
    const bool not_available = std::string(fault).find(":-2") != std::string::npos;
    INFO("PDMESH_TEST_FAIL_CL_AT=" << fault);
    const fs::path dir = fresh_path("lost");
    const std::string args = "mesh '" + kase + "' --out '" + dir.string() + "' --formats msh -q";
    const auto r =
        run_pdmesh(args + " --device opencl --iterations 1000", std::string("PDMESH_TEST_FAIL_CL_AT=") + fault);
    INFO(r.output);
    CHECK(r.status == 1);
    CHECK_THAT(r.output, Contains("pdmesh: error: iteration ") &&
                             Contains(not_available ? "CL_DEVICE_NOT_AVAILABLE (-2)" : "CL_OUT_OF_RESOURCES (-5)") &&
                             Contains("the last good state (after iteration ") && Contains("--resume"));
    REQUIRE(fs::exists(dir / "checkpoint.pdmesh"));
    const Checkpoint saved = read_checkpoint(dir / "checkpoint.pdmesh");
    CHECK(saved.state.iterations_done >= 0);
    CHECK(saved.state.iterations_done < 1000);
    CHECK(saved.state.history.size() == static_cast<std::size_t>(saved.state.iterations_done));
    // It continues on the host (the device being gone), five more iterations.
    const int until = saved.state.iterations_done + 5;
    const auto resumed =
        run_pdmesh(args + " --device host --iterations " + std::to_string(until) + " --resume '" + dir.string() + "'");
    INFO(resumed.output);
    CHECK(resumed.status == 0);
    CHECK(read_text_file(dir / "history.csv").find("\n" + std::to_string(until) + ",") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "checkpoint.pdmesh"));
    fs::remove_all(dir);
  }
}

TEST_CASE("a device lost at any call: exit 1, and a checkpoint that resumes once the iterations began",
          "[failures][opencl][cli]") {
  // Every 53rd OpenCL call from the first until a run gets through: setup, first build, steps,
  // rebuilds, the final read-back. Failures before the first iteration leave no checkpoint.
  const std::string kase = PDMESH_SOURCE_DIR "/cases/circle_circle";
  const fs::path dir = fresh_path("sweep");
  int with_checkpoint = 0;
  for (int at = 1;; at += 53) {
    INFO("PDMESH_TEST_FAIL_CL_AT=" << at);
    fs::remove_all(dir);
    const std::string args = "mesh '" + kase + "' --out '" + dir.string() + "' --formats msh -q --iterations 30";
    const auto r = run_pdmesh(args + " --device opencl", "PDMESH_TEST_FAIL_CL_AT=" + std::to_string(at));
    INFO(r.output);
    if (r.status == 0) break;  // past the last call
    REQUIRE(r.status == 1);
    CHECK_THAT(r.output, Contains("pdmesh: error: ") && Contains("CL_OUT_OF_RESOURCES (-5)"));
    if (!fs::exists(dir / "checkpoint.pdmesh")) {
      CHECK_THAT(r.output, !Contains("iteration"));
      continue;
    }
    ++with_checkpoint;
    CHECK_THAT(r.output, Contains("the last good state (after iteration "));
    const auto resumed = run_pdmesh(args + " --device host --resume '" + dir.string() + "'");
    INFO(resumed.output);
    CHECK(resumed.status == 0);
  }
  CHECK(with_checkpoint >= 5);
  fs::remove_all(dir);
}

TEST_CASE("device memory: the need is counted per node and refused with the figures", "[failures][opencl]") {
  // 1000 nodes, 100 on curves, no field, double: 1000 (16 * 8 + 1 + 28 + 8) + the compact rows at
  // 16 entries per node 1000 * 16 * 4 + 100 (6 * 8 + 12).
  const ocl::DeviceMemoryNeed need = ocl::device_memory_need(1000, 100, 0, 8);
  CHECK(need.largest == 64000);
  CHECK(need.total == 165000 + 64000 + 6000);
  // The rows at the size they grew to (40 entries per node).
  CHECK(ocl::device_memory_need(1000, 100, 0, 8, 40).largest == 4 * 1000 * 40);
  CHECK(ocl::device_memory_need(1000, 100, 0, 8, 40).total == 165000 + 4 * 1000 * 40 + 6000);
  ocl::DeviceInfo device;
  device.name = "test device";
  device.global_memory = need.total;
  device.max_allocation = need.largest;
  CHECK_NOTHROW(ocl::check_device_memory(device, 1000, 100, 0, 8));
  device.global_memory = need.total - 1;
  CHECK_THROWS_AS(ocl::check_device_memory(device, 1000, 100, 0, 8), LimitError);
  CHECK_THROWS_WITH(ocl::check_device_memory(device, 1000, 100, 0, 8),
                    Contains("1000 nodes need at least 235000 bytes of device memory in double") &&
                        Contains("test device has 234999 bytes") && Contains("allows 64000 bytes per buffer") &&
                        Contains("--precision float (at least 168600 bytes)") && Contains("--device host") &&
                        Contains("coarser spacing"));
  device.global_memory = need.total;
  device.max_allocation = need.largest - 1;
  CHECK_THROWS_AS(ocl::check_device_memory(device, 1000, 100, 0, 8), LimitError);
  // In float the advice is not to use float.
  CHECK_THROWS_WITH(ocl::check_device_memory(device, 1000, 100, 0, 4),
                    Contains("in float") && !Contains("--precision float"));
}

TEST_CASE("device memory: neighbour rows that outgrow the device's largest buffer are refused", "[failures][opencl]") {
  // A device that holds the initial estimate of 16 entries per node but not the rows the first
  // build finds (circle_circle's need more than 16 per node: the check_entries hook refuses the growth
  // before the index buffer is allocated): the run stops with the figures and the saved state.
  const test::Case c = test::load_case("circle_circle");
  const std::uint64_t n = c.initial.size();
  ocl::DeviceInfo info = test::test_context().device();
  info.max_allocation = 4 * n * 16;
  ocl::Context small(info);
  NodeSet nodes = c.initial;
  std::optional<SimState> saved;
  SimCallbacks callbacks;
  callbacks.on_failure = [&](const SimState& s) { saved = s; };
  CHECK_THROWS_WITH(ocl::run_device_simulation(nodes, *c.inputs->tree, *c.inputs->spacing, test::options_for(c, 3),
                                               small, ocl::Precision::Double, callbacks),
                    Contains("the neighbour rows at ") && Contains(" entries per node") &&
                        Contains("nodes have that many neighbours within the list radius on average") &&
                        Contains(fmt::format("allows {} bytes per buffer", 4 * n * 16)));
  REQUIRE(saved);
  CHECK(saved->iterations_done == 0);
}

TEST_CASE("a device with too little memory is refused before allocating, exit 2", "[failures][opencl][cli]") {
  const fs::path dir = fresh_path("memory");
  const auto r = run_pdmesh("mesh '" PDMESH_SOURCE_DIR "/cases/square200' --out '" + dir.string() +
                                "' --device opencl --iterations 5 --formats msh -q",
                            "PDMESH_TEST_DEVICE_MEMORY=26000");  // float would fit: the message says so
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Contains("pdmesh: error: ") && Contains("nodes need at least") &&
                           Contains("bytes of device memory in double") &&
                           Contains("has 26000 bytes of global memory") && Contains("--precision float") &&
                           Contains("--device host"));
  CHECK_FALSE(fs::exists(dir / "checkpoint.pdmesh"));
  fs::remove_all(dir);
}

TEST_CASE("coordinates double precision cannot resolve at the spacing are refused with the figures",
          "[failures][geometry]") {
  // At 2^40 doubles are 2^-12 apart; 1e4 quanta are 2.44140625.
  const double m = 0x1p40;
  const auto square = [m](double side) {
    return build_geometry(
        {RawCurve{"sq", {{m, m}, {m + side, m}, {m + side, m + side}, {m, m + side}, {m, m}}, "sq.crv", 2, {}}});
  };
  const ExpressionSpacing wide("4");
  CHECK_NOTHROW(check_coordinate_resolution(square(4), wide));
  CHECK_THROWS_AS(check_coordinate_resolution(square(2), wide), LimitError);
  CHECK_THROWS_WITH(check_coordinate_resolution(square(2), wide),
                    Contains("sq.crv:2: the segment 0 of curve 'sq'") &&
                        Contains("is 2, but the coordinates reach 1.09951e+12") &&
                        Contains("doubles are 0.000244 apart") && Contains("(2.44)"));
  // The segments are fine, the spacing is not.
  CHECK_THROWS_WITH(check_coordinate_resolution(square(4), ExpressionSpacing("2")),
                    Contains("the spacing at (") && Contains("is 2, but"));
  // Near the origin the same sizes are fine.
  const Geometry small =
      build_geometry({RawCurve{"sq", {{0, 0}, {1e-9, 0}, {1e-9, 1e-9}, {0, 1e-9}, {0, 0}}, "s", 1, {}}});
  CHECK_NOTHROW(check_coordinate_resolution(small, ExpressionSpacing("1e-10")));
}

TEST_CASE("a checkpoint that does not fit the geometry is refused", "[failures][resume]") {
  SquareCase c;
  SimOptions options = quiet_options(3);
  const SimResult r = run_simulation(c.nodes, *c.tree, c.spacing, options);
  const Checkpoint good{{}, c.nodes, r.state};
  CHECK_NOTHROW(check_checkpoint_fits(good, *c.tree, "cp"));
  std::size_t boundary = 0;
  while (c.nodes.kind[boundary] != NodeKind::Boundary) ++boundary;
  std::size_t interior = 0;
  while (c.nodes.kind[interior] != NodeKind::Interior) ++interior;
  const auto refused = [&](const std::function<void(Checkpoint&)>& damage, const std::string& text) {
    Checkpoint bad = good;
    damage(bad);
    CHECK_THROWS_WITH(check_checkpoint_fits(bad, *c.tree, "cp"),
                      Contains("cp: the checkpoint does not fit the case's geometry: ") && Contains(text));
  };
  refused([](Checkpoint& k) { k.nodes.curve_nodes.emplace_back(); }, "node lists for 2 curves, the geometry has 1");
  refused(
      [&](Checkpoint& k) {
        k.nodes.x[interior] = {5.0, 0.0};
      },
      fmt::format("node {} at (5, 0) is outside", interior));
  refused([&](Checkpoint& k) { k.nodes.q[interior] = 0.0; }, "has spacing 0");
  refused([&](Checkpoint& k) { k.nodes.curve[interior] = 0; },
          fmt::format("node {} (interior) names curve 0", interior));
  refused(
      [&](Checkpoint& k) {
        k.nodes.kind[interior] = NodeKind::Boundary;
        k.nodes.curve[interior] = 0;
      },
      fmt::format("boundary node {} is listed 0 times", interior));
  refused([&](Checkpoint& k) { std::swap(k.state.arcs[0][1], k.state.arcs[0][2]); }, "arc position 2 is");
  refused([&](Checkpoint& k) { k.state.arcs[0].back() *= 2; }, "ends at arc position");
  refused([&](Checkpoint& k) { k.nodes.curve_nodes[0].front() = static_cast<int>(boundary); }, "at position 0");
  refused([&](Checkpoint& k) { k.state.time_step.dt = 0; }, "is not positive");
  refused([&](Checkpoint& k) { k.state.history[1].iteration = 7; }, "history row 2 is iteration 7");
}
