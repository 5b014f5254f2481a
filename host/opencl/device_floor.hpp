// The pair-force floor of an OpenCL device: the floor iteration of sim/pair_floor.hpp (the same seeded
// lattice sorted by cells, every candidate of a node's 3 x 3 cells tested against the cut-off, eq. 5.11,
// the move into a second array) run by kernels/pair_floor.cl, one work-item per node, in the device's
// REAL. `pdmesh bench` gives a device run's ms per iteration as a ratio to it, as it gives the host
// reference's to the CPU's floor: a CPU floor says nothing of a GPU.
// The kernel is the plain one-node-per-work-item gather, the shape of the simulation's own force
// kernel; it is not tuned further (no local-memory tiles), so on a GPU it is a floor for that shape.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "opencl/context.hpp"
#include "sim/pair_floor.hpp"

namespace pdmesh::ocl {

struct DeviceFloorResult {
  std::string device;  // the device's name
  Precision precision = Precision::Double;
  std::size_t nodes = 0;
  double bytes = 0.0;           // per iteration: x, y, q read and two arrays written per node, 4 B per cell
  double device_seconds = 0.0;  // the best repeat's kernel time (CL_PROFILING_COMMAND_END - START)
  double wall_seconds = 0.0;    // the best repeat's wall time from the enqueue to the end of clFinish
  // The process's CPU time (every thread: a CPU device's work is on its threads) over the repeat of
  // the best kernel time: on a loaded machine the figure to compare with the CPU floor's.
  double cpu_seconds = 0.0;
  int repeats = 0;
};

// The lattice on ctx's device (`lattice` must outlive the DeviceFloor) with the floor program built (DeviceError:
// Double without fp64, a failed build, a work-group the kernel cannot run). Its own in-order queue with profiling,
// whatever PDMESH_KERNEL_PROFILE says.
class DeviceFloor {
 public:
  DeviceFloor(Context& ctx, const FloorLattice& lattice, Precision precision);
  ~DeviceFloor();
  DeviceFloor(const DeviceFloor&) = delete;
  DeviceFloor& operator=(const DeviceFloor&) = delete;

  // One floor iteration, waited for: its kernel time, wall time and the process's CPU time in seconds.
  struct Times {
    double device = 0.0, wall = 0.0, cpu = 0.0;
  };
  Times run(double dt2);
  // The last iteration's new positions, as doubles.
  void download(std::vector<double>& new_x, std::vector<double>& new_y);
  double bytes() const;

  struct State;

 private:
  std::unique_ptr<State> state_;
};

// Builds the lattice of `options`, runs one untimed iteration, then options.repeats timed ones
// (InputError: options out of range, as make_floor_lattice).
DeviceFloorResult measure_device_floor(Context& ctx, const FloorOptions& options, Precision precision);

// One line: "device pair-force floor at N nodes on DEVICE (double): kernel T ms, wall W ms with a finish, ...".
std::string format_device_floor(const DeviceFloorResult& result);

}  // namespace pdmesh::ocl
