// The pair-force floor in `pdmesh bench`'s tables: measured at a case's node count, on the host CPU
// (sim/pair_floor.hpp) for the host reference's rows and on each OpenCL device (opencl/device_floor.hpp)
// for that device's rows, once per node count, and the table cells that give a simulation's
// per-iteration time against it.
#pragma once
#include <cstddef>
#include <string>

#include "opencl/device_floor.hpp"
#include "opencl/devices.hpp"
#include "sim/pair_floor.hpp"

namespace pdmesh {

// The floor at `nodes` nodes, best of `repeat` (>= 1), with pdmesh's cut-off and a; measured once per
// node count and repeat in a process. Prints its line (format_floor) to stderr.
const FloorResult& bench_floor(std::size_t nodes, int repeat, double cutoff = 1.5, double lj_a = 15.0);

// Table cells: "scalar / vector" floor in ms per iteration, and the ratio of `seconds_per_iteration`
// to the floor (the faster loop); "-" and "-" without a floor.
std::string floor_ms_cell(const FloorResult* floor);
std::string floor_ratio_cell(const FloorResult* floor, double seconds_per_iteration);
// The same for CPU time (every thread of the process): the faster loop's CPU ms per iteration, and the
// ratio of `cpu_seconds_per_iteration` to it.
std::string floor_cpu_ms_cell(const FloorResult* floor);
std::string floor_cpu_ratio_cell(const FloorResult* floor, double cpu_seconds_per_iteration);

// The floor on `device` in `precision` at `nodes` nodes, best of `repeat` (>= 1) kernel times, with
// pdmesh's cut-off and a; measured once per device, precision, node count and repeat in a process.
// Prints its line (format_device_floor) to stderr. Null, with the reason on stderr, when the device
// cannot run it (DeviceError, or LimitError: an array past its largest allocation): its rows then have
// no floor.
const ocl::DeviceFloorResult* bench_device_floor(const ocl::DeviceInfo& device, ocl::Precision precision,
                                                 std::size_t nodes, int repeat, double cutoff = 1.5,
                                                 double lj_a = 15.0);

// Table cells of a device row: "device T" (the floor's kernel ms per iteration) and the ratio of
// `seconds_per_iteration` to it; "-" and "-" without a floor.
std::string device_floor_ms_cell(const ocl::DeviceFloorResult* floor);
std::string device_floor_ratio_cell(const ocl::DeviceFloorResult* floor, double seconds_per_iteration);

}  // namespace pdmesh
