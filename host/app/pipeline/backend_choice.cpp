// The simulation backend of a run; see backend_choice.hpp.
#include "app/pipeline/backend_choice.hpp"

#include <atomic>
#include <cstdlib>
#include <fmt/format.h>

#include "core/errors.hpp"
#include "opencl/device_simulation.hpp"
#include "opencl/devices.hpp"
#include "opencl/opencl_backend.hpp"
#include "opencl/precision_probe.hpp"

namespace pdmesh {
namespace {

std::string first_line(const std::string& s) { return s.substr(0, s.find('\n')); }

std::atomic<std::size_t> setups{0};

ocl::Precision device_precision(Precision requested, const ocl::DeviceInfo& device, ocl::Context& ctx,
                                const std::function<void(const std::string&)>& note) {
  if (requested == Precision::Float) return ocl::Precision::Float;
  if (requested == Precision::Double) {
    if (device.fp64) return ocl::Precision::Double;
    note(fmt::format("note: {} has no double precision (cl_khr_fp64); simulating in float", device.name));
    return ocl::Precision::Float;
  }
  const ocl::PrecisionChoice choice =
      ocl::choose_precision_auto(device, [&ctx] { return ocl::measure_fp64_slowdown(ctx); });
  note("precision auto: " + choice.reason);
  return choice.precision;
}

ChosenBackend host_backend(Precision precision, const std::function<void(const std::string&)>& note) {
  if (precision == Precision::Float)
    note("note: the host reference computes in double precision; --precision float is ignored");
  ChosenBackend chosen;
  chosen.simulator = make_host_simulator();
  return chosen;
}

}  // namespace

ChosenBackend choose_among(const std::vector<ocl::DeviceInfo>& candidates, bool fall_back, Precision precision,
                           const std::function<void(const std::string&)>& note) {
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const ocl::DeviceInfo& d = candidates[k];
    ChosenBackend chosen;
    try {
      chosen.context = std::make_unique<ocl::Context>(d);
      const ocl::Precision p = device_precision(precision, d, *chosen.context, note);
      chosen.simulator = std::make_unique<ocl::DeviceSimulator>(*chosen.context, p);
      return chosen;
    } catch (const DeviceError& e) {
      if (!fall_back) throw;
      // A driver that cannot build the program (or run its work-group size) must not end a run that
      // another device or the host can do.
      const std::string next = k + 1 < candidates.size() ? fmt::format("opencl:{}:{} ({})", candidates[k + 1].platform,
                                                                       candidates[k + 1].device, candidates[k + 1].name)
                                                         : std::string("the host reference");
      note(fmt::format("note: --device auto: opencl:{}:{} ({}) cannot run the simulation: {}; trying {}", d.platform,
                       d.device, d.name, first_line(e.what()), next));
    }
  }
  return host_backend(precision, note);
}

namespace {
double auto_host_below() {
  static const double below = [] {
    const char* v = std::getenv("PDMESH_TEST_AUTO_HOST_BELOW");
    return v != nullptr ? std::atof(v) : kAutoHostBelowNodes;
  }();
  return below;
}
}  // namespace

std::size_t backend_setups() { return setups.load(); }

bool auto_prefers_host(const std::string& device, double nodes) {
  return device == "auto" && nodes < auto_host_below();
}

ChosenBackend choose_backend_for(const std::string& device, Precision precision, double nodes,
                                 const std::function<void(const std::string&)>& note) {
  if (!auto_prefers_host(device, nodes)) return choose_backend(device, precision, note);
  ++setups;
  note(
      fmt::format("device auto: the host reference for {:.0f} nodes (below {:.0f}, a whole run on the host ends "
                  "sooner than on an OpenCL device; docs/devices.md)",
                  nodes, auto_host_below()));
  ChosenBackend chosen;
  chosen.simulator = make_host_simulator();
  return chosen;
}

ChosenBackend choose_backend(const std::string& device, Precision precision,
                             const std::function<void(const std::string&)>& note) {
  ++setups;
  if (device == "host") return host_backend(precision, note);
  if (device != "auto")
    return choose_among({*ocl::select_device(device)}, false, precision, note);  // InputError when absent
  const std::vector<ocl::DeviceInfo> candidates = ocl::auto_order(ocl::list_devices());
  if (candidates.empty()) {
    note("note: no OpenCL platform or device found; simulating on the host reference");
    return host_backend(precision, note);
  }
  return choose_among(candidates, true, precision, note);
}

ChosenBackend choose_metric_backend(const std::string& device, Precision precision,
                                    const std::function<void(const std::string&)>& note) {
  ++setups;
  if (device == "host") return host_backend(precision, note);
  if (device == "auto") {
    note(
        "device auto: the host reference for a run with a metric field (the device-resident simulation has no "
        "metric mode yet)");
    ChosenBackend chosen;
    chosen.simulator = make_host_simulator();
    return chosen;
  }
  const ocl::DeviceInfo d = *ocl::select_device(device);  // InputError when absent
  ChosenBackend chosen;
  chosen.context = std::make_unique<ocl::Context>(d);
  const ocl::Precision p = device_precision(precision, d, *chosen.context, note);
  chosen.simulator =
      make_host_simulator(ocl::make_opencl_backend(*chosen.context, p),
                          fmt::format("opencl:{}:{} ({}, {}, {}, host-driven steps: a metric run)", d.platform,
                                      d.device, d.name, d.type, p == ocl::Precision::Double ? "double" : "float"));
  return chosen;
}

}  // namespace pdmesh
