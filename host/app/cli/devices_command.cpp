// `pdmesh devices`: the OpenCL device list, what `--device auto` would pick, and an optional check
// of each device (app/cli/device_check).
#include "app/cli/devices_command.hpp"

#include <fmt/format.h>

#include "app/cli/device_check.hpp"
#include "opencl/devices.hpp"

namespace pdmesh {

int run_devices(bool check) {
  const auto devices = ocl::list_devices();
  fmt::print("OpenCL devices ({}):\n{}", devices.size(), ocl::describe_all(devices));
  const auto chosen = ocl::select_device("auto");
  fmt::print("--device auto picks: {}\n",
             chosen ? fmt::format("opencl:{}:{} ({})", chosen->platform, chosen->device, chosen->name)
                    : std::string("host (no OpenCL device)"));
  int status = 0;
  if (check) {
    for (const auto& d : ocl::auto_order(devices)) {
      const DeviceCheck c = check_device(d);
      fmt::print("check opencl:{}:{}: {}\n", d.platform, d.device,
                 !c.ok             ? "FAILED"
                 : c.bit_identical ? "ok"
                                   : "ok, not bit-identical with the host");
      for (const std::string& line : c.lines) fmt::print("  {}\n", line);
      if (!c.ok) status = 1;
    }
  }
  return status;
}

}  // namespace pdmesh
