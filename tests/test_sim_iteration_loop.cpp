// Tests of the loop both simulation drivers share (sim/iteration_loop.hpp), on scripted steps: the
// history rows and statistics from the steps' sums and counts, the stop request, Interrupted from an
// iteration's computation, and which failures hand the last good state over in each FailureScope.
#include <catch2/catch.hpp>

#include <atomic>
#include <functional>
#include <vector>

#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "error_message.hpp"
#include "sim/iteration_loop.hpp"

using namespace pdmesh;

namespace {

// Three nodes; the loop reads them only for the default dt and the stopping rule (both unused here).
NodeSet three_nodes() {
  NodeSet nodes;
  nodes.add({0.0, 0.0}, 1.0, NodeKind::Fixed, 0);
  nodes.add({1.0, 0.0}, 1.0, NodeKind::Boundary, 0);
  nodes.add({0.5, 0.5}, 1.0, NodeKind::Interior, -1);
  return nodes;
}

SimOptions scripted_options(int iterations) {
  SimOptions options;
  options.iterations = iterations;
  options.dt_initial = 0.01;
  options.quiet = true;
  return options;
}

// Steps whose sums and counts depend on the iteration only; each hook can be made to throw.
class ScriptedSteps final : public IterationSteps {
 public:
  explicit ScriptedSteps(IterationLoop& loop) : loop_(loop) {}
  std::function<void(int)> on_compute, on_apply;  // called first (may throw)
  std::function<void()> on_after_iterations;
  bool allow_stop = true;
  int rows = 0, ended = 0;
  std::vector<double> dts;  // gm.dt() as each computation saw it

  std::string backend_name() const override { return "scripted"; }
  IterationStep compute(int iteration, const GlobalTimeStep& gm) override {
    if (on_compute) on_compute(iteration);
    dts.push_back(gm.dt());
    IterationStep step;
    step.sums = StepSums{2, 4.0 * iteration, 10.0 - iteration, 1.0};
    step.pairs_examined = 10;
    step.pairs_within = 6;
    step.coincident_pairs = 1;
    return step;
  }
  IterationMoves apply(int iteration) override {
    if (on_apply) on_apply(iteration);
    IterationMoves moves;
    moves.boundary = BoundaryCounts{1, 2};
    if (iteration == 2) moves.event = PopulationCounts{3, 0, 1, 0, 0, 0};
    moves.fixed = 1;
    moves.on_boundary = 2;
    moves.interior = 3;
    return moves;
  }
  void after_row() override { ++rows; }
  bool may_stop() const override { return allow_stop; }
  void after_iterations() override {
    if (on_after_iterations) on_after_iterations();
  }
  SimState failure_state() override {
    SimState s;
    s.iterations_done = loop_.done();
    s.history = loop_.history();
    return s;
  }
  void end_run(SimResult& result) override {
    ++ended;
    result.state.iterations_done = loop_.done();
  }

 private:
  IterationLoop& loop_;
};

}  // namespace

TEST_CASE("the loop records each iteration's row and statistics from the steps", "[sim]") {
  const NodeSet nodes = three_nodes();
  const SimOptions options = scripted_options(4);
  IterationLoop loop(nodes, options);
  ScriptedSteps steps(loop);
  std::vector<int> seen;
  SimCallbacks callbacks;
  callbacks.on_iteration = [&](const HistoryRow& row) { seen.push_back(row.iteration); };
  const SimResult result = loop.run(steps, callbacks, FailureScope::Step);

  REQUIRE(result.history.size() == 4);
  CHECK(seen == std::vector<int>{1, 2, 3, 4});
  CHECK(steps.rows == 4);
  CHECK(steps.ended == 1);
  CHECK(result.state.iterations_done == 4);
  CHECK_FALSE(result.stopped);
  CHECK_FALSE(result.converged);
  CHECK(result.stats.backend == "scripted");
  CHECK(result.stats.dt_initial == 0.01);
  const HistoryRow& row = result.history[1];
  CHECK(row.iteration == 2);
  CHECK(row.average_force == 4.0);    // 8 / 2 moving nodes
  CHECK(row.average_kinetic == 0.5);  // 1 / 2
  CHECK(row.max_force == 8.0);
  CHECK(row.dt_gm == 0.01);
  CHECK(row.snapped == 1);
  CHECK(row.clamped == 2);
  CHECK(row.fixed == 1);
  CHECK(row.boundary == 2);
  CHECK(row.interior == 3);
  CHECK(row.inserted == 3);
  CHECK(row.removed == 1);
  CHECK(result.history[0].inserted == 0);
  CHECK(result.stats.pairs_examined == 40);
  CHECK(result.stats.pairs_within == 24);
  CHECK(result.stats.coincident_pairs == 4);
  CHECK(result.stats.snapped == 4);
  // Every computation saw the rule's dt before that iteration's update (the first value only sets the reference).
  CHECK(steps.dts == std::vector<double>{0.01, 0.01, 0.01, 0.01});
}

TEST_CASE("the loop continues a resumed run after its iterations and keeps its history", "[sim]") {
  const NodeSet nodes = three_nodes();
  SimState saved;
  saved.iterations_done = 2;
  saved.dt_initial = 0.02;
  saved.time_step.dt = 0.03;
  saved.history.resize(2);
  SimOptions options = scripted_options(5);
  options.resume = &saved;
  IterationLoop loop(nodes, options);
  ScriptedSteps steps(loop);
  const SimResult result = loop.run(steps, {}, FailureScope::Step);
  REQUIRE(result.history.size() == 5);
  CHECK(result.history[2].iteration == 3);
  CHECK(result.history[2].dt_gm == 0.03);
  CHECK(result.stats.dt_initial == 0.02);
  CHECK(steps.rows == 3);
}

TEST_CASE("a stop request ends the run after an iteration where the steps allow it", "[sim]") {
  const NodeSet nodes = three_nodes();
  std::atomic<bool> stop{false};
  SimOptions options = scripted_options(10);
  options.stop = &stop;
  IterationLoop loop(nodes, options);
  ScriptedSteps steps(loop);
  steps.allow_stop = false;
  SimCallbacks callbacks;
  callbacks.on_iteration = [&](const HistoryRow& row) {
    if (row.iteration == 3) stop = true;
    steps.allow_stop = row.iteration >= 5;  // the device run: only at the end of a window
  };
  const SimResult result = loop.run(steps, callbacks, FailureScope::Step);
  CHECK(result.stopped);
  CHECK(result.history.size() == 5);
  CHECK(result.state.iterations_done == 5);
}

TEST_CASE("Interrupted from an iteration's computation stops the run after the previous iteration", "[sim]") {
  const NodeSet nodes = three_nodes();
  const SimOptions options = scripted_options(10);
  IterationLoop loop(nodes, options);
  ScriptedSteps steps(loop);
  steps.on_compute = [](int iteration) {
    if (iteration == 4) throw Interrupted("stop");
  };
  const SimResult result = loop.run(steps, {}, FailureScope::Step);
  CHECK(result.stopped);
  CHECK(result.history.size() == 3);
  CHECK(result.state.iterations_done == 3);
}

TEST_CASE("FailureScope::Step hands the last good state over for a computation's SimulationError only", "[sim]") {
  const NodeSet nodes = three_nodes();
  const SimOptions options = scripted_options(10);
  std::vector<int> handed;
  SimCallbacks callbacks;
  callbacks.on_failure = [&](const SimState& s) { handed.push_back(s.iterations_done); };
  SECTION("from the computation: the state after the previous iteration") {
    IterationLoop loop(nodes, options);
    ScriptedSteps steps(loop);
    steps.on_compute = [](int iteration) {
      if (iteration == 3) throw SimulationError("non-finite");
    };
    CHECK_THROWS_AS(loop.run(steps, callbacks, FailureScope::Step), SimulationError);
    CHECK(handed == std::vector<int>{2});
  }
  SECTION("from the moves (nodes have moved): none") {
    IterationLoop loop(nodes, options);
    ScriptedSteps steps(loop);
    steps.on_apply = [](int iteration) {
      if (iteration == 3) throw SimulationError("cannot snap");
    };
    CHECK_THROWS_AS(loop.run(steps, callbacks, FailureScope::Step), SimulationError);
    CHECK(handed.empty());
  }
  SECTION("a DeviceError from the computation (an OpenCL step backend): none, and unchanged") {
    IterationLoop loop(nodes, options);
    ScriptedSteps steps(loop);
    steps.on_compute = [](int iteration) {
      if (iteration == 2) throw DeviceError("clFinish failed");
    };
    CHECK(pdmesh_test::error_message<DeviceError>([&] { loop.run(steps, callbacks, FailureScope::Step); }) ==
          "clFinish failed");
    CHECK(handed.empty());
  }
}

TEST_CASE("FailureScope::Run hands the last good state over for any error and names where a DeviceError came",
          "[sim]") {
  const NodeSet nodes = three_nodes();
  const SimOptions options = scripted_options(4);
  std::vector<int> handed;
  SimCallbacks callbacks;
  callbacks.on_failure = [&](const SimState& s) { handed.push_back(s.iterations_done); };
  SECTION("a SimulationError from the moves") {
    IterationLoop loop(nodes, options);
    ScriptedSteps steps(loop);
    steps.on_apply = [](int iteration) {
      if (iteration == 3) throw SimulationError("cannot snap");
    };
    CHECK_THROWS_AS(loop.run(steps, callbacks, FailureScope::Run), SimulationError);
    CHECK(handed == std::vector<int>{2});
  }
  SECTION("a DeviceError in an iteration") {
    IterationLoop loop(nodes, options);
    ScriptedSteps steps(loop);
    steps.on_compute = [](int iteration) {
      if (iteration == 2) throw DeviceError("clFinish failed");
    };
    CHECK(pdmesh_test::error_message<DeviceError>([&] { loop.run(steps, callbacks, FailureScope::Run); }) ==
          "iteration 2: clFinish failed");
    CHECK(handed == std::vector<int>{1});
  }
  SECTION("a DeviceError reading the final state back") {
    IterationLoop loop(nodes, options);
    ScriptedSteps steps(loop);
    steps.on_after_iterations = [] { throw DeviceError("clEnqueueReadBuffer failed"); };
    CHECK(pdmesh_test::error_message<DeviceError>([&] { loop.run(steps, callbacks, FailureScope::Run); }) ==
          "reading back the state after iteration 4: clEnqueueReadBuffer failed");
    CHECK(handed == std::vector<int>{4});
  }
}

TEST_CASE("the loop refuses an initial dt_GM that is not a positive number", "[sim]") {
  const NodeSet nodes = three_nodes();
  SimOptions options = scripted_options(4);
  options.dt_initial = 0.0;
  CHECK(pdmesh_test::error_message<InputError>([&] { IterationLoop loop(nodes, options); }) ==
        "simulation.dt_initial must be a positive number, got 0");
}
