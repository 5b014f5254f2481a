// One test body per simulation step, run against every StepBackend (the C++ reference, OpenCL in
// double and in float on the first OpenCL device: PoCL's CPU device in CI), with identical inputs
// and the oracle (brute-force lists, the reference functions) computed on the same (rounded) inputs.
// Stability bound: off (thesis) and c = 1. Tolerances (require_close: |device - oracle| <= tol * max(|oracle|, floor)):
//   double: 1e-12 (the kernels repeat the reference's expressions; only sum order may differ);
//           compute_forces with either force loop (vector, scalar): 0, bit for bit
//   float:  forces 1e-4 of the node's sum of |pair forces|, everything else 1e-5 relative.
// Integer outputs (counts, neighbour sets, flags, pairs) must match exactly; in float a pair may
// differ only when its distance is within 1e-5 (relative) of the cut-off.
// Canary: the OpenCL backends run on test_context(), whose buffers carry kCanaryTail sentinel
// elements after their end; every output download checks them, so a kernel writing past an output
// (e.g. from the work-items past n) fails the call with a DeviceError naming the buffer.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

#include "core/errors.hpp"
#include "opencl/opencl_backend.hpp"
#include "sim/reference/reference_backend.hpp"
#include "step_backend_inputs.hpp"

using namespace pdmesh;
using namespace pdmesh::test;

namespace {

struct HostReference {
  static constexpr bool is_float = false;
  static constexpr double tol = 1e-12, force_tol = 1e-12;
  static std::unique_ptr<StepBackend> make() { return make_reference_backend(); }
};
// The device's own force loop (PoCL: the vector one), and the other shape (kernels/forces.cl) forced,
// so both run in CI without a GPU.
struct OpenclDouble {
  static constexpr bool is_float = false;
  static constexpr double tol = 1e-12, force_tol = 1e-12;
  static std::unique_ptr<StepBackend> make() {
    return ocl::make_opencl_backend(test_context(), ocl::Precision::Double);
  }
};
struct OpenclFloat {
  static constexpr bool is_float = true;
  static constexpr double tol = 1e-5, force_tol = 1e-4;
  static std::unique_ptr<StepBackend> make() { return ocl::make_opencl_backend(test_context(), ocl::Precision::Float); }
};
template <ocl::ForceLoop Loop>
struct OpenclDoubleLoop : OpenclDouble {
  // Both loops sum each row in row order, as the reference does: the forces are equal bit for bit.
  static constexpr double tol = 0.0, force_tol = 0.0;
  static std::unique_ptr<StepBackend> make() {
    return ocl::make_opencl_backend(test_context(), ocl::Precision::Double, Loop);
  }
};
template <ocl::ForceLoop Loop>
struct OpenclFloatLoop : OpenclFloat {
  static std::unique_ptr<StepBackend> make() {
    return ocl::make_opencl_backend(test_context(), ocl::Precision::Float, Loop);
  }
};
using OpenclDoubleScalar = OpenclDoubleLoop<ocl::ForceLoop::Scalar>;
using OpenclDoubleVector = OpenclDoubleLoop<ocl::ForceLoop::Vector>;
using OpenclFloatScalar = OpenclFloatLoop<ocl::ForceLoop::Scalar>;
using OpenclFloatVector = OpenclFloatLoop<ocl::ForceLoop::Vector>;

// The one tolerance helper: relative to the oracle, scale floored per element.
void require_close(const char* what, const std::vector<double>& oracle, const std::vector<double>& got,
                   const std::vector<double>& floor, double tol) {
  REQUIRE(got.size() == oracle.size());
  std::size_t bad = 0;
  for (std::size_t i = 0; i < oracle.size(); ++i) {
    if (std::isinf(oracle[i]) && got[i] == oracle[i]) continue;  // "no bound" (HUGE_VAL) on both sides
    const double scale = std::max(std::fabs(oracle[i]), floor.empty() ? 0.0 : floor[i]);
    if (!(std::fabs(got[i] - oracle[i]) <= tol * scale)) {
      if (++bad <= 5)
        FAIL_CHECK(what << "[" << i << "]: oracle " << oracle[i] << ", backend " << got[i] << ", tol " << tol << " x "
                        << scale);
    }
  }
  REQUIRE(bad == 0);
}

std::vector<int> row_of(const NeighbourList& l, std::size_t i) {
  const auto s = static_cast<std::size_t>(l.stride);
  const auto c = std::min<std::size_t>(static_cast<std::size_t>(l.count[i]), s);
  std::vector<int> r(l.index.begin() + static_cast<std::ptrdiff_t>(i * s),
                     l.index.begin() + static_cast<std::ptrdiff_t>(i * s + c));
  std::sort(r.begin(), r.end());
  return r;
}

template <class B>
void check_neighbours(const Input& in) {
  INFO("input " << in.name << ", " << in.p.size() << " nodes");
  auto backend = B::make();
  NeighbourList list, oracle;
  NeighbourFlags flags, oflags;
  build_neighbours_growing(*backend, in.p, in.cutoff, list, flags);
  oracle.stride = list.stride;
  reference::build_neighbours_brute_force(in.p, in.cutoff, oracle, oflags);
  REQUIRE(flags.overflow == 0);
  REQUIRE(oflags.overflow == 0);
  REQUIRE(flags.first_invalid == -1);
  if (in.name == "dense cluster") REQUIRE(flags.max_count == 39);  // over the default stride 16, grown
  if (!B::is_float) {
    REQUIRE(list.count == oracle.count);
    REQUIRE(flags.max_count == oflags.max_count);
    REQUIRE(flags.pairs_within == oflags.pairs_within);
  }
  for (std::size_t i = 0; i < in.p.size(); ++i) {
    const std::vector<int> a = row_of(list, i), b = row_of(oracle, i);
    if (a == b) continue;
    REQUIRE(B::is_float);
    std::vector<int> diff;
    std::set_symmetric_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(diff));
    for (int j : diff) {
      const double dx = in.p.x[static_cast<std::size_t>(j)] - in.p.x[i],
                   dy = in.p.y[static_cast<std::size_t>(j)] - in.p.y[i];
      const double r = in.cutoff * in.p.q[i];
      INFO("node " << i << " neighbour " << j);
      REQUIRE(std::fabs((dx * dx + dy * dy) / (r * r) - 1.0) < 1e-5);
    }
  }
}

template <class B>
void check_forces(const Input& in, bool r0_any, double stability, int stride = 64) {
  INFO("input " << in.name << ", " << in.p.size() << " nodes, r0_any_direction " << r0_any << ", stability "
                << stability);
  NeighbourList list;
  NeighbourFlags flags;
  list.stride = stride;
  reference::build_neighbours_brute_force(in.p, in.cutoff, list, flags);
  REQUIRE(flags.overflow == 0);
  const ForceParams params{in.cutoff, 15.0, r0_any, stability};
  ForceResult oracle, got;
  reference::compute_forces(in.p, list, params, oracle);
  B::make()->compute_forces(in.p, list, params, got);
  const std::vector<double> scale = pair_force_scale(in.p, list, params.lj_a);
  require_close("fx", oracle.fx, got.fx, scale, B::force_tol);
  require_close("fy", oracle.fy, got.fy, scale, B::force_tol);
  require_close("r0", oracle.r0, got.r0, {}, B::tol);
  REQUIRE(got.dt2_limit.size() == oracle.dt2_limit.size());
  // The bound is 2c / (sum of stiffnesses): a sum of positive terms, relative error like the forces'.
  require_close("dt2_limit", oracle.dt2_limit, got.dt2_limit, {}, B::force_tol);
  REQUIRE(got.coincident_pairs == oracle.coincident_pairs);
}

template <class B>
void check_time_step_and_reduce(const Input& in, double stability) {
  INFO("input " << in.name << ", " << in.p.size() << " nodes, stability " << stability);
  NeighbourList list;
  NeighbourFlags flags;
  list.stride = 64;
  reference::build_neighbours_brute_force(in.p, in.cutoff, list, flags);
  ForceResult forces;
  reference::compute_forces(in.p, list, {in.cutoff, 15.0, false, stability}, forces);
  if (B::is_float) round_to_float(forces);
  auto backend = B::make();
  for (double dt_gm : {1e-4, 0.01, 10.0}) {  // the global maximum binding for none, some, all nodes
    MoveResult oracle, got;
    reference::time_step_and_move(in.p, forces, dt_gm * dt_gm, oracle);
    backend->time_step_and_move(in.p, forces, dt_gm * dt_gm, got);
    require_close("dx", oracle.dx, got.dx, {}, B::tol);
    require_close("dy", oracle.dy, got.dy, {}, B::tol);
    require_close("dt2", oracle.dt2, got.dt2, {}, B::tol);
    const StepSums o = reference::reduce(in.p, forces, oracle), g = backend->reduce(in.p, forces, oracle);
    REQUIRE(g.moving == o.moving);
    require_close("sums", {o.sum_force, o.sum_kinetic, o.max_force}, {g.sum_force, g.sum_kinetic, g.max_force}, {},
                  B::tol);
  }
}

}  // namespace

TEMPLATE_TEST_CASE("build_neighbours matches brute force on every input", "[opencl][backend]", HostReference,
                   OpenclDouble, OpenclFloat) {
  REQUIRE(test_context().canary_tail() == kCanaryTail);  // the device outputs below are canary-checked
  for (const Input& in : all_inputs(TestType::is_float)) check_neighbours<TestType>(in);
}

TEMPLATE_TEST_CASE("compute_forces matches the reference on every input", "[opencl][backend]", HostReference,
                   OpenclDoubleVector, OpenclFloatVector, OpenclDoubleScalar, OpenclFloatScalar) {
  for (const Input& in : all_inputs(TestType::is_float)) {
    check_forces<TestType>(in, false, 0.0);
    check_forces<TestType>(in, true, 0.0);
    check_forces<TestType>(in, false, 1.0);
  }
}

// The vector loop packs the entries that count into a buffer of 64 and computes r0 from it; longer rows
// are computed as the buffer fills and r0 comes from a second walk of the row (kernels/forces.cl).
TEMPLATE_TEST_CASE("compute_forces matches the reference on rows longer than the packing buffer", "[opencl][backend]",
                   HostReference, OpenclDoubleVector, OpenclFloatVector, OpenclDoubleScalar, OpenclFloatScalar) {
  const Input in = long_rows_input(TestType::is_float);
  NeighbourList list;
  NeighbourFlags flags;
  list.stride = 256;
  reference::build_neighbours_brute_force(in.p, in.cutoff, list, flags);
  REQUIRE(*std::max_element(list.count.begin(), list.count.end()) > 128);  // two buffers' worth and more
  check_forces<TestType>(in, false, 0.0, 256);
  check_forces<TestType>(in, true, 1.0, 256);
}

TEMPLATE_TEST_CASE("time_step_and_move and reduce match the reference on every input", "[opencl][backend]",
                   HostReference, OpenclDouble, OpenclFloat) {
  for (const Input& in : all_inputs(TestType::is_float)) {
    check_time_step_and_reduce<TestType>(in, 0.0);
    check_time_step_and_reduce<TestType>(in, 1.0);
  }
}

// Forces whose square is past FLT_MAX (|F| > ~1.8e19: a node closer than ~q/30 to another in float)
// still give dt^2 = 2 r0 / (3 |F|) and a move of r0 / 3; before the float norm was scaled, dt^2 was 0.
TEMPLATE_TEST_CASE("time_step_and_move and reduce stay finite for forces past float's squared range",
                   "[opencl][backend]", HostReference, OpenclDouble, OpenclFloat) {
  Input in = random_input(6, 11, TestType::is_float);
  for (auto& k : in.p.kind) k = kSimInterior;
  ForceResult forces;
  forces.fx = {3e20, -1e25, 2e19, 0.0, 1e30, 5.0};
  forces.fy = {-1e20, 4e24, 0.0, -7e33, 1e30, -2.0};
  forces.r0 = {0.01, 0.003, 0.02, 0.5, 1e-4, 0.1};
  if (TestType::is_float) round_to_float(forces);
  auto backend = TestType::make();
  MoveResult oracle, got;
  reference::time_step_and_move(in.p, forces, 1.0, oracle);
  backend->time_step_and_move(in.p, forces, 1.0, got);
  for (std::size_t i = 0; i + 1 < in.p.size(); ++i) {  // the large forces: each moves by r0 / 3 exactly
    INFO("node " << i);
    CHECK(std::hypot(oracle.dx[i], oracle.dy[i]) == Approx(forces.r0[i] / 3.0).epsilon(1e-12));
    CHECK(got.dt2[i] > 0.0);
  }
  require_close("dx", oracle.dx, got.dx, {}, TestType::tol);
  require_close("dy", oracle.dy, got.dy, {}, TestType::tol);
  require_close("dt2", oracle.dt2, got.dt2, {}, TestType::tol);
  const StepSums o = reference::reduce(in.p, forces, oracle), g = backend->reduce(in.p, forces, oracle);
  REQUIRE(std::isfinite(g.sum_force));
  REQUIRE(std::isfinite(g.sum_kinetic));
  require_close("sums", {o.sum_force, o.sum_kinetic, o.max_force}, {g.sum_force, g.sum_kinetic, g.max_force}, {},
                TestType::tol);
}

TEMPLATE_TEST_CASE("a node over capacity sets the overflow flag and the host retry grows the stride",
                   "[opencl][backend]", HostReference, OpenclDouble, OpenclFloat) {
  const Input in = crowded_input(TestType::is_float);
  auto backend = TestType::make();
  NeighbourList list;
  list.stride = 8;
  NeighbourFlags flags;
  backend->build_neighbours(in.p, in.cutoff, list, flags);
  CHECK(flags.overflow == 1);
  CHECK(flags.max_count == 39);  // the 40-node cluster: every member sees the 39 others
  CHECK(list.stride == 8);       // build_neighbours never grows the stride itself
  NeighbourList oracle;
  oracle.stride = 8;
  NeighbourFlags oflags;
  reference::build_neighbours_brute_force(in.p, in.cutoff, oracle, oflags);
  CHECK(list.count == oracle.count);
  for (std::size_t i = 0; i < in.p.size(); ++i) CHECK(row_of(list, i) == row_of(oracle, i));  // the 8 smallest
  build_neighbours_growing(*backend, in.p, in.cutoff, list, flags);
  CHECK(flags.overflow == 0);
  CHECK(list.stride == 40);
}

TEMPLATE_TEST_CASE("an invalid node is reported by index", "[opencl][backend]", HostReference, OpenclDouble,
                   OpenclFloat) {
  Input in = random_input(13, 3, TestType::is_float);
  in.p.q[7] = 0.0;
  in.p.x[9] = std::nan("");
  NeighbourList list;
  NeighbourFlags flags;
  TestType::make()->build_neighbours(in.p, in.cutoff, list, flags);
  CHECK(flags.first_invalid == 7);
  REQUIRE_THROWS_AS(build_neighbours_growing(*TestType::make(), in.p, in.cutoff, list, flags), SimulationError);
}

// Heavy-ball momentum (StepBackend::apply_momentum) on every input, from carried moves of all sizes:
// none, some against the force, some past the r0 / 3 cap; without and with the carried move steered
// towards the force (mix). Double: bit for bit (the kernel repeats the reference's expressions,
// FP_CONTRACT OFF); float: the backend's tolerance.
TEMPLATE_TEST_CASE("apply_momentum matches the reference on every input", "[opencl][backend][momentum]", HostReference,
                   OpenclDouble, OpenclFloat) {
  for (const Input& in : all_inputs(TestType::is_float)) {
    INFO("input " << in.name << ", " << in.p.size() << " nodes");
    NeighbourList list;
    NeighbourFlags flags;
    list.stride = 64;
    reference::build_neighbours_brute_force(in.p, in.cutoff, list, flags);
    ForceResult forces;
    reference::compute_forces(in.p, list, {in.cutoff, 15.0, false, 1.0}, forces);
    if (TestType::is_float) round_to_float(forces);
    MoveResult g;
    reference::time_step_and_move(in.p, forces, 0.01 * 0.01, g);
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    MomentumState start;
    for (std::size_t i = 0; i < in.p.size(); ++i) {
      // Carried moves from 0 to 3 r0: the cap binds for some, the dot test for others.
      const double scale = (i % 4) * in.p.q[i];
      start.px.push_back(scale * u(rng));
      start.py.push_back(scale * u(rng));
    }
    if (TestType::is_float)
      for (auto* v : {&start.px, &start.py, &g.dx, &g.dy})
        for (double& x : *v) x = static_cast<double>(static_cast<float>(x));
    auto backend = TestType::make();
    for (const auto& [beta, mix] :
         {std::pair{0.5, 0.0}, std::pair{0.9, 0.0}, std::pair{0.9, 0.2}, std::pair{0.5, 0.7}}) {
      INFO("beta " << beta << ", mix " << mix);
      MoveResult oracle = g, got = g;
      MomentumState oracle_p = start, got_p = start;
      reference::apply_momentum(in.p, forces, beta, mix, oracle, oracle_p);
      backend->apply_momentum(in.p, forces, beta, mix, got, got_p);
      const double tol = TestType::is_float ? TestType::tol : 0.0;
      const std::vector<double> floor(in.p.q.begin(), in.p.q.end());  // moves relative to the spacing
      require_close("dx", oracle.dx, got.dx, floor, tol);
      require_close("dy", oracle.dy, got.dy, floor, tol);
      require_close("px", oracle_p.px, got_p.px, floor, tol);
      require_close("py", oracle_p.py, got_p.py, floor, tol);
    }
  }
}
