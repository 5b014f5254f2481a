// Inputs for the StepBackend tests (test_step_backends.cpp): random, graded 1000x, degenerate, and
// awkward sizes around the work-group size 64 (0, 1, 63, 64, 65, 101), all from fixed seeds; and the
// shared OpenCL context of the device tests, with a canary tail on every buffer, released when the run ends.
#pragma once
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "opencl/context.hpp"
#include "opencl/devices.hpp"
#include "opencl/step_program.hpp"
#include "sim/reference/reference_backend.hpp"
#include "sim_fixtures.hpp"
#include "test_run_end.hpp"

namespace pdmesh::test {

struct Input {
  std::string name;
  SimParticles p;
  double cutoff = 1.5;
};

// Sentinel elements after the end of every device buffer the tests' backends allocate: at least
// one work-group, so a kernel that lets the rounded-up items (global size rounded to WG_SIZE) write
// lands in it. Every download checks the tail and throws DeviceError naming the buffer.
inline constexpr std::size_t kCanaryTail = 64;

// The context and the programs tests share: released when the test run ends (test_run_end.hpp), not
// by static destructors after main.
struct TestDevice {
  std::unique_ptr<ocl::Context> context;
  std::unique_ptr<ocl::StepProgram> programs[2];  // double, float
};
inline TestDevice& test_device() {
  static TestDevice d;
  return d;
}

// CI always has PoCL: no device must fail loudly, not skip.
inline ocl::Context& test_context() {
  TestDevice& d = test_device();
  if (!d.context) {
    auto info = ocl::select_device("auto");
    REQUIRE(info.has_value());
    d.context = std::make_unique<ocl::Context>(*info);
    d.context->set_canary_tail(kCanaryTail);
    on_test_run_end([] {
      TestDevice& t = test_device();
      for (auto& p : t.programs) p.reset();
      t.context.reset();
    });
  }
  return *d.context;
}

// The simulation program on test_context(), built once per precision.
inline ocl::StepProgram& test_program(ocl::Precision precision) {
  ocl::Context& ctx = test_context();
  auto& p = test_device().programs[precision == ocl::Precision::Double ? 0 : 1];
  if (!p) p = std::make_unique<ocl::StepProgram>(ctx, precision);
  return *p;
}

using pdmesh_test::uniform;

// Float backends see float inputs: the oracle gets the same rounded values.
inline void round_to_float(SimParticles& p) {
  for (auto* v : {&p.x, &p.y, &p.q, &p.tx, &p.ty})
    for (double& e : *v) e = static_cast<double>(static_cast<float>(e));
}
inline void round_to_float(ForceResult& f) {
  for (auto* v : {&f.fx, &f.fy, &f.r0, &f.dt2_limit})
    for (double& e : *v) e = static_cast<double>(static_cast<float>(e));
}

// Makes every `every`-th node a boundary node (prev/next the nodes beside it, a random unit tangent)
// and every 17th a fixed node.
inline void mix_kinds(SimParticles& p, std::mt19937_64& rng, std::size_t every) {
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (i % 17 == 16) p.kind[i] = kSimFixed;
    if (n >= 3 && i % every == every - 1 && p.kind[i] == kSimInterior) {
      p.kind[i] = kSimBoundary;
      p.prev[i] = static_cast<std::int32_t>((i + n - 1) % n);
      p.next[i] = static_cast<std::int32_t>((i + 1) % n);
      const double a = 2.0 * M_PI * uniform(rng);
      p.tx[i] = std::cos(a);
      p.ty[i] = std::sin(a);
    }
  }
}

inline Input random_input(std::size_t n, std::uint64_t seed, bool is_float) {
  Input in{"random " + std::to_string(n), {}, 1.5};
  std::mt19937_64 rng(seed);
  const double side = std::sqrt(static_cast<double>(n) + 1.0) * 0.08;
  for (std::size_t i = 0; i < n; ++i)
    pdmesh_test::add(in.p, side * uniform(rng), side * uniform(rng), 0.06 + 0.06 * uniform(rng));
  mix_kinds(in.p, rng, 10);
  if (is_float) round_to_float(in.p);
  return in;
}

// Radius 1e-3 .. 1 (log-uniform), q = 0.2 radius: spacing over 1000x, ~4 neighbours per node.
inline Input graded_input(bool is_float) {
  Input in{"graded 1000x", {}, 1.5};
  std::mt19937_64 rng(42);
  for (int i = 0; i < 600; ++i) {
    const double r = std::pow(10.0, -3.0 * uniform(rng)), a = 2.0 * M_PI * uniform(rng);
    pdmesh_test::add(in.p, r * std::cos(a), r * std::sin(a), 0.2 * r);
  }
  mix_kinds(in.p, rng, 25);
  if (is_float) round_to_float(in.p);
  return in;
}

// Coincident nodes: 5 positions duplicated (one of them three times).
inline Input coincident_input(bool is_float) {
  Input in = random_input(50, 7, is_float);
  in.name = "coincident";
  for (std::size_t k : {3u, 8u, 20u, 31u, 44u, 44u}) pdmesh_test::add(in.p, in.p.x[k], in.p.y[k], in.p.q[k]);
  return in;
}

// A 10 x 10 integer lattice with cutoff * q = 1: every pair at distance 1 lies exactly on the cut-off
// and every node exactly on a cell edge.
inline Input lattice_input() {
  Input in{"lattice on cell edges", {}, 2.0};
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < 10; ++i) pdmesh_test::add(in.p, i, j, 0.5);
  return in;
}

// 40 nodes in a cluster of radius 0.01 (q = 0.1) and 20 far apart: the cluster overflows stride 8.
inline Input crowded_input(bool is_float) {
  Input in{"crowded", {}, 1.5};
  std::mt19937_64 rng(5);
  for (int i = 0; i < 40; ++i) pdmesh_test::add(in.p, 0.01 * uniform(rng), 0.01 * uniform(rng), 0.1);
  for (int i = 0; i < 20; ++i) pdmesh_test::add(in.p, 10.0 + 3.0 * i, 5.0, 0.1);
  if (is_float) round_to_float(in.p);
  return in;
}

// A cell over capacity at sane distances: 40 nodes on a jittered 7 x 6 lattice of pitch 1/60 (q = 0.1,
// every pair within the cut-off 0.15, so each row holds 39 > the default stride 16; nearest pairs
// >= 0.01 apart, so forces stay within float range), 5 nodes far away, empty cells between.
inline Input dense_cluster_input(bool is_float) {
  Input in{"dense cluster", {}, 1.5};
  std::mt19937_64 rng(11);
  const double pitch = 1.0 / 60.0;
  for (int i = 0; i < 40; ++i)
    pdmesh_test::add(in.p, pitch * (i % 7 + 0.4 * (uniform(rng) - 0.5)), pitch * (i / 7 + 0.4 * (uniform(rng) - 0.5)),
                     0.1);
  for (int i = 0; i < 5; ++i) pdmesh_test::add(in.p, 7.0 + 2.0 * i, -3.0, 0.1);
  mix_kinds(in.p, rng, 9);
  if (is_float) round_to_float(in.p);
  return in;
}

// Rows longer than the vector force loop's packing buffer (kernels/forces.cl, PACK_CAP = 64): 144
// nodes on a jittered 12 x 12 lattice of pitch 1/80 (q = 0.1: nearly every pair within the cut-off 0.15,
// rows of ~140 entries; nearest pairs >= 0.0075 apart, forces within float range), three of them
// duplicated (coincident pairs inside long rows), boundary and fixed nodes mixed in. Not in all_inputs:
// only the force test needs it (a stride of 256).
inline Input long_rows_input(bool is_float) {
  Input in{"long rows", {}, 1.5};
  std::mt19937_64 rng(13);
  const double pitch = 1.0 / 80.0;
  for (int i = 0; i < 144; ++i)
    pdmesh_test::add(in.p, pitch * (i % 12 + 0.4 * (uniform(rng) - 0.5)), pitch * (i / 12 + 0.4 * (uniform(rng) - 0.5)),
                     0.1);
  for (std::size_t k : {5u, 70u, 131u}) pdmesh_test::add(in.p, in.p.x[k], in.p.y[k], in.p.q[k]);
  mix_kinds(in.p, rng, 9);
  if (is_float) round_to_float(in.p);
  return in;
}

inline std::vector<Input> all_inputs(bool is_float) {
  std::vector<Input> v;
  for (std::size_t n : {0u, 1u, 63u, 64u, 65u, 101u}) v.push_back(random_input(n, 1000 + n, is_float));
  v.push_back(graded_input(is_float));
  v.push_back(coincident_input(is_float));
  v.push_back(lattice_input());
  v.push_back(dense_cluster_input(is_float));
  return v;
}

// Per node: the sum of the magnitudes of its pair forces (the scale a force error is measured on).
inline std::vector<double> pair_force_scale(const SimParticles& p, const NeighbourList& list, double lj_a) {
  std::vector<double> s(p.size(), 0.0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (int k = 0; k < list.count[i]; ++k) {
      const auto j =
          static_cast<std::size_t>(list.index[i * static_cast<std::size_t>(list.stride) + static_cast<std::size_t>(k)]);
      const double dx = p.x[j] - p.x[i], dy = p.y[j] - p.y[i], r2 = dx * dx + dy * dy;
      if (r2 > 0.0) s[i] += std::fabs(reference::lj_pair_magnitude(0.5 * (p.q[i] + p.q[j]), 1.0 / r2, lj_a));
    }
  }
  return s;
}

}  // namespace pdmesh::test
