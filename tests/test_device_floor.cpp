// The pair-force floor on an OpenCL device (opencl/device_floor.hpp, kernels/pair_floor.cl): one test
// body for the host's threaded floor iteration and the device's, each against floor_rows_scalar over
// every cell row (the oracle), bit for bit in double; the float kernel close to it; the measurement's
// figures.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "opencl/device_floor.hpp"
#include "sim/pair_floor.hpp"
#include "step_backend_inputs.hpp"

using namespace pdmesh;

namespace {

constexpr double kDt2 = 1e-3;

// The floor lattice of `nodes` nodes, and the same points with q varied in [0.8, 1.2] (sigma the pair's
// mean of two values, cells sized by the largest q), re-binned.
std::vector<FloorLattice> lattices(std::size_t nodes) {
  FloorOptions o;
  o.nodes = nodes;
  o.repeats = 1;
  FloorLattice uniform = make_floor_lattice(o);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.8, 1.2);
  std::vector<double> q(uniform.size());
  for (double& v : q) v = u(rng);
  FloorLattice graded;
  graded.cutoff = uniform.cutoff;
  graded.lj_a = uniform.lj_a;
  bin_floor_points(uniform.x, uniform.y, q, graded);
  return {uniform, graded};
}

struct HostFloorIteration {
  static void run(const FloorLattice& l, std::vector<double>& nx, std::vector<double>& ny) {
    floor_iteration(l, FloorLoop::Scalar, kDt2, nx, ny, 0);
  }
};

struct DeviceFloorIteration {
  static void run(const FloorLattice& l, std::vector<double>& nx, std::vector<double>& ny) {
    ocl::DeviceFloor floor(test::test_context(), l, ocl::Precision::Double);
    floor.run(kDt2);
    floor.download(nx, ny);
  }
};

}  // namespace

TEMPLATE_TEST_CASE("floor iteration: the new positions are floor_rows_scalar's bit for bit in double",
                   "[opencl][floor]", HostFloorIteration, DeviceFloorIteration) {
  for (std::size_t nodes : {65u, 3000u}) {
    for (const FloorLattice& l : lattices(nodes)) {
      INFO(nodes << " nodes, q from " << l.q.front() << ", " << l.cells_x << " x " << l.cells_y << " cells");
      std::vector<double> want_x(l.size()), want_y(l.size()), got_x, got_y;
      floor_rows_scalar(l, 0, l.cells_y, kDt2, want_x.data(), want_y.data());
      TestType::run(l, got_x, got_y);
      REQUIRE(got_x.size() == l.size());
      REQUIRE(got_y.size() == l.size());
      std::size_t moved = 0;
      for (std::size_t i = 0; i < l.size(); ++i) {
        INFO("node " << i);
        REQUIRE(got_x[i] == want_x[i]);
        REQUIRE(got_y[i] == want_y[i]);
        moved += got_x[i] != l.x[i] || got_y[i] != l.y[i];
      }
      // Jittered: nearly every node feels a net force.
      REQUIRE(moved > l.size() * 9 / 10);
    }
  }
}

TEST_CASE("floor iteration in float stays within float's rounding of the host's", "[opencl][floor]") {
  for (const FloorLattice& l : lattices(3000)) {
    std::vector<double> want_x(l.size()), want_y(l.size()), got_x, got_y;
    floor_rows_scalar(l, 0, l.cells_y, kDt2, want_x.data(), want_y.data());
    ocl::DeviceFloor floor(test::test_context(), l, ocl::Precision::Float);
    floor.run(kDt2);
    floor.download(got_x, got_y);
    REQUIRE(got_x.size() == l.size());
    for (std::size_t i = 0; i < l.size(); ++i) {
      INFO("node " << i << " at " << l.x[i] << ", " << l.y[i]);
      // Positions up to ~60 (2^-18 per float step there); the moves' own rounding is well below.
      REQUIRE(std::abs(got_x[i] - want_x[i]) <= 1e-4);
      REQUIRE(std::abs(got_y[i] - want_y[i]) <= 1e-4);
    }
  }
}

TEST_CASE("device floor measurement: times, bytes and its line", "[opencl][floor]") {
  FloorOptions o;
  o.nodes = 2000;
  o.repeats = 2;
  const ocl::DeviceFloorResult r = ocl::measure_device_floor(test::test_context(), o, ocl::Precision::Double);
  const FloorLattice l = make_floor_lattice(o);
  REQUIRE(r.nodes == 2000);
  REQUIRE(r.bytes == 40.0 * 2000 + 4.0 * static_cast<double>(l.cell_start.size()));
  REQUIRE(r.device_seconds > 0.0);
  REQUIRE(r.wall_seconds > 0.0);
  REQUIRE(r.cpu_seconds >= 0.0);
  REQUIRE(r.repeats == 2);
  const std::string line = ocl::format_device_floor(r);
  REQUIRE(line.find("2000 nodes") != std::string::npos);
  REQUIRE(line.find("double") != std::string::npos);
  o.repeats = 0;
  REQUIRE_THROWS_WITH(ocl::measure_device_floor(test::test_context(), o, ocl::Precision::Double),
                      Catch::Contains("repeats"));
}
