// Enumerates OpenCL platforms and devices and applies the --device rule (auto: auto_order's first).
#include "opencl/devices.hpp"

#include <algorithm>
#include <cstdlib>
#include <tuple>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "opencl/cl_errors.hpp"

namespace pdmesh::ocl {
namespace {

std::string type_name(cl_device_type t) {
  if (t & CL_DEVICE_TYPE_GPU) return "GPU";
  if (t & CL_DEVICE_TYPE_CPU) return "CPU";
  if (t & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
  return "other";
}

template <cl_device_info Name, typename T>
T info(const cl::Device& d, const char* what) {
  T value{};
  check(d.getInfo(Name, &value), fmt::format("clGetDeviceInfo({})", what));
  return value;
}

}  // namespace

std::vector<DeviceInfo> list_devices() {
  std::vector<DeviceInfo> out;
  std::vector<cl::Platform> platforms;
  // No ICD or no platform is not an error here: the caller decides (auto falls back to the host).
  if (cl::Platform::get(&platforms) != CL_SUCCESS) return out;
  for (std::size_t p = 0; p < platforms.size(); ++p) {
    std::vector<cl::Device> devices;
    if (platforms[p].getDevices(CL_DEVICE_TYPE_ALL, &devices) != CL_SUCCESS) continue;
    std::string pname;
    platforms[p].getInfo(CL_PLATFORM_NAME, &pname);
    for (std::size_t d = 0; d < devices.size(); ++d) {
      DeviceInfo i;
      i.platform = static_cast<int>(p);
      i.device = static_cast<int>(d);
      i.platform_name = pname.c_str();  // drop the trailing NUL some drivers include
      i.handle = devices[d];
      i.name = info<CL_DEVICE_NAME, std::string>(devices[d], "CL_DEVICE_NAME").c_str();
      i.version = info<CL_DEVICE_VERSION, std::string>(devices[d], "CL_DEVICE_VERSION").c_str();
      i.type = type_name(info<CL_DEVICE_TYPE, cl_device_type>(devices[d], "CL_DEVICE_TYPE"));
      i.compute_units = info<CL_DEVICE_MAX_COMPUTE_UNITS, cl_uint>(devices[d], "CL_DEVICE_MAX_COMPUTE_UNITS");
      i.global_memory = info<CL_DEVICE_GLOBAL_MEM_SIZE, cl_ulong>(devices[d], "CL_DEVICE_GLOBAL_MEM_SIZE");
      i.max_allocation = info<CL_DEVICE_MAX_MEM_ALLOC_SIZE, cl_ulong>(devices[d], "CL_DEVICE_MAX_MEM_ALLOC_SIZE");
      // Test-only (docs/robustness.md): PDMESH_TEST_DEVICE_MEMORY=BYTES caps both memory figures, to
      // exercise the out-of-device-memory refusal on a device that has plenty.
      if (const char* cap = std::getenv("PDMESH_TEST_DEVICE_MEMORY")) {
        const std::uint64_t bytes = std::strtoull(cap, nullptr, 10);
        if (bytes > 0) {
          i.global_memory = std::min<std::uint64_t>(i.global_memory, bytes);
          i.max_allocation = std::min<std::uint64_t>(i.max_allocation, bytes);
        }
      }
      i.max_work_group = info<CL_DEVICE_MAX_WORK_GROUP_SIZE, std::size_t>(devices[d], "CL_DEVICE_MAX_WORK_GROUP_SIZE");
      i.fp64 = info<CL_DEVICE_DOUBLE_FP_CONFIG, cl_device_fp_config>(devices[d], "CL_DEVICE_DOUBLE_FP_CONFIG") != 0;
      // Deprecated since OpenCL 2.0 (still answered by the drivers we know): a device that does not
      // answer counts as discrete, which only affects auto's order.
      cl_bool unified = CL_FALSE;
      i.unified_memory =
          devices[d].getInfo(CL_DEVICE_HOST_UNIFIED_MEMORY, &unified) == CL_SUCCESS && unified != CL_FALSE;
      out.push_back(std::move(i));
    }
  }
  return out;
}

std::string describe(const DeviceInfo& d) {
  return fmt::format("opencl:{}:{}  {:<4} {} [{}] ({} compute units, {:.1f} GiB{}, max work-group {}, {})", d.platform,
                     d.device, d.type, d.name, d.platform_name, d.compute_units,
                     static_cast<double>(d.global_memory) / (1024.0 * 1024.0 * 1024.0),
                     d.type == "GPU" ? (d.unified_memory ? " shared with the host" : " of its own") : "",
                     d.max_work_group, d.fp64 ? "fp64" : "no fp64");
}

std::string describe_all(const std::vector<DeviceInfo>& devices) {
  if (devices.empty()) return "  (no OpenCL platform or device found: is an ICD such as pocl-opencl-icd installed?)\n";
  std::string s;
  for (const auto& d : devices) s += "  " + describe(d) + "\n";
  return s;
}

std::vector<DeviceInfo> auto_order(std::vector<DeviceInfo> devices) {
  // A discrete GPU has its own memory and, on a laptop, is the fast one beside an integrated GPU that
  // often lacks fp64; CPU devices come after every GPU.
  const auto rank = [](const DeviceInfo& d) {
    const int type = d.type == "GPU" ? 0 : d.type == "CPU" ? 1 : 2;
    return std::make_tuple(type, d.unified_memory ? 1 : 0, d.fp64 ? 0 : 1, -static_cast<long long>(d.compute_units));
  };
  std::stable_sort(devices.begin(), devices.end(),
                   [&](const DeviceInfo& a, const DeviceInfo& b) { return rank(a) < rank(b); });
  return devices;
}

std::optional<DeviceInfo> select_device(const std::string& spec) {
  auto devices = auto_order(list_devices());
  if (spec == "auto") {
    if (!devices.empty()) return devices.front();
    return std::nullopt;
  }
  if (spec == "opencl") {
    if (devices.empty()) throw InputError("--device opencl: no OpenCL device is available.\n" + describe_all(devices));
    return devices.front();
  }
  int p = -1, d = -1;
  char tail = 0;
  if (std::sscanf(spec.c_str(), "opencl:%d:%d%c", &p, &d, &tail) != 2 || p < 0 || d < 0)
    throw InputError(fmt::format("--device '{}': expected auto, host, opencl or opencl:P:D (e.g. opencl:0:0)", spec));
  for (const auto& dev : devices)
    if (dev.platform == p && dev.device == d) return dev;
  throw InputError(fmt::format("--device {}: no such OpenCL device. Available:\n{}", spec, describe_all(devices)));
}

}  // namespace pdmesh::ocl
