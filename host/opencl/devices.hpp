// OpenCL platform and device discovery (`pdmesh devices`) and the --device selection rule.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "opencl/cl_include.hpp"

namespace pdmesh::ocl {

struct DeviceInfo {
  int platform = 0;  // index in the platform list
  int device = 0;    // index within the platform
  std::string platform_name;
  std::string name;
  std::string type;  // "GPU", "CPU", "accelerator", "other"
  std::string version;
  unsigned compute_units = 0;
  std::uint64_t global_memory = 0;   // bytes
  std::uint64_t max_allocation = 0;  // bytes
  std::size_t max_work_group = 0;
  bool fp64 = false;
  bool unified_memory = false;  // CL_DEVICE_HOST_UNIFIED_MEMORY: an integrated GPU or a CPU device
  cl::Device handle;
};

// Every device of every platform. An absent ICD loader or no platform gives an empty list (no throw).
std::vector<DeviceInfo> list_devices();

// One line per device, for `pdmesh devices` and for error messages: "opencl:0:0  CPU  pthread-... (2 CUs, 23.4 GiB,
// fp64)".
std::string describe(const DeviceInfo& d);
std::string describe_all(const std::vector<DeviceInfo>& devices);

// The devices in the order `--device auto` tries them, best first: GPUs, then CPU devices, then the
// rest. Among GPUs a discrete one (no host-unified memory) comes first, then one with fp64, then the
// one with the most compute units; platform order breaks ties (stable).
std::vector<DeviceInfo> auto_order(std::vector<DeviceInfo> devices);

// Resolves an "opencl" or "opencl:P:D" spec, or "auto" (the first of auto_order; "opencl" likewise).
// Returns nothing for "auto" when no device exists; throws InputError (exit 2) listing what is available when
// an explicit opencl spec cannot be met, InputError when the spec is malformed.
std::optional<DeviceInfo> select_device(const std::string& spec);

}  // namespace pdmesh::ocl
