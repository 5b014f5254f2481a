// Device time per kernel, for finding where an iteration's time goes (docs/performance.md, "The
// commands"). With PDMESH_KERNEL_PROFILE=FILE in the environment, every Context's queue is created
// with profiling and every ocl::launch keeps its event; each ocl::finish adds the finished launches'
// device time (CL_PROFILING_COMMAND_END - START) to their kernel's totals, and at exit the totals are
// written to FILE (one line per kernel: name, launches, seconds, tab-separated). Without the variable
// launches take no event and nothing is written.
#pragma once
#include <cstdint>
#include <map>
#include <string>

#include "opencl/cl_include.hpp"

namespace pdmesh::ocl {

struct KernelTime {
  std::uint64_t launches = 0;
  double seconds = 0.0;
};

// Whether queues are created with profiling: PDMESH_KERNEL_PROFILE names a file (read once).
bool kernel_profiling();

// The event of a launch to be timed at the next finish (kernel_profiling() only).
void keep_kernel_event(const std::string& name, cl::Event event);

// Adds the kept events' device times to the totals (each event must have finished) and drops them.
void collect_kernel_times();

// The totals so far by kernel name, collected events only.
std::map<std::string, KernelTime> kernel_times();

}  // namespace pdmesh::ocl
