// Device time per kernel from profiling events; see kernel_profile.hpp.
#include "opencl/kernel_profile.hpp"

#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <utility>
#include <vector>

namespace pdmesh::ocl {
namespace {

struct Profile {
  std::mutex mutex;
  std::vector<std::pair<std::string, cl::Event>> pending;
  std::map<std::string, KernelTime> totals;
  std::string file;
};

// Never destroyed: events still pending at exit are not released, since the platform may be unloading.
Profile& profile() {
  static Profile* p = new Profile;
  return *p;
}

void write_totals() {
  Profile& p = profile();
  std::lock_guard lock(p.mutex);
  if (p.totals.empty()) return;
  if (std::FILE* f = std::fopen(p.file.c_str(), "w")) {
    std::fprintf(f, "kernel\tlaunches\tseconds\n");
    for (const auto& [name, t] : p.totals)
      std::fprintf(f, "%s\t%llu\t%.9f\n", name.c_str(), static_cast<unsigned long long>(t.launches), t.seconds);
    std::fclose(f);
  }
}

}  // namespace

bool kernel_profiling() {
  static const bool on = [] {
    const char* v = std::getenv("PDMESH_KERNEL_PROFILE");
    if (v == nullptr || *v == '\0') return false;
    profile().file = v;
    std::atexit(write_totals);
    return true;
  }();
  return on;
}

void keep_kernel_event(const std::string& name, cl::Event event) {
  Profile& p = profile();
  std::lock_guard lock(p.mutex);
  p.pending.emplace_back(name, std::move(event));
}

void collect_kernel_times() {
  Profile& p = profile();
  std::lock_guard lock(p.mutex);
  for (auto& [name, event] : p.pending) {
    cl_ulong start = 0, end = 0;
    if (event.getProfilingInfo(CL_PROFILING_COMMAND_START, &start) != CL_SUCCESS ||
        event.getProfilingInfo(CL_PROFILING_COMMAND_END, &end) != CL_SUCCESS)
      continue;  // not a profiled queue's event: nothing to add
    KernelTime& t = p.totals[name];
    ++t.launches;
    t.seconds += static_cast<double>(end - start) * 1e-9;
  }
  p.pending.clear();
}

std::map<std::string, KernelTime> kernel_times() {
  Profile& p = profile();
  std::lock_guard lock(p.mutex);
  return p.totals;
}

}  // namespace pdmesh::ocl
