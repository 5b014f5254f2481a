// Which simulation backend a run uses (simulation.device, simulation.precision): the host reference or
// the device-resident run on an OpenCL device, through the Simulator contract of sim/simulation.hpp.
// The app is the one place that knows both sides, so sim/ does not depend on opencl/.
#pragma once
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "opencl/context.hpp"
#include "opencl/devices.hpp"
#include "sim/simulation.hpp"

namespace pdmesh {

struct ChosenBackend {
  std::unique_ptr<ocl::Context> context;  // null on the host
  std::unique_ptr<Simulator> simulator;   // built (device: its program too) and ready to run
};

// device "host": the host reference (a float request noted as ignored). An explicit opencl spec:
// that device (InputError listing the devices when it is not there, DeviceError when the program
// does not build on it). "auto": the devices in ocl::auto_order, each tried until the program builds
// on one (a note names each that failed and why), else the host reference; none at all: the host,
// noted. The precision: double, float (also for double on a device without fp64, noted), or auto
// (ocl::choose_precision_auto, noted). `note` gets one line per remark.
ChosenBackend choose_backend(const std::string& device, Precision precision,
                             const std::function<void(const std::string&)>& note);

// `--device auto` simulates on the host reference below this many nodes: there a whole run on the
// host ends before an OpenCL device is set up and its first lists are built (measured where host
// and PoCL whole runs cross, docs/devices.md "auto and small meshes"). Outputs do not change: the
// device run in double precision is the host's bit for bit.
inline constexpr double kAutoHostBelowNodes = 1000;

// Whether `device` ("auto" only) should take the host reference for a run of about `nodes` nodes:
// below kAutoHostBelowNodes, or below PDMESH_TEST_AUTO_HOST_BELOW when that is set (a test hook,
// docs/robustness.md: 0 lets the tests of auto's OpenCL path run on small cases).
bool auto_prefers_host(const std::string& device, double nodes);

// choose_backend for a run of about `nodes` nodes: "auto" below kAutoHostBelowNodes is the host
// reference (noted), otherwise as choose_backend.
ChosenBackend choose_backend_for(const std::string& device, Precision precision, double nodes,
                                 const std::function<void(const std::string&)>& note);

// The backend of a run with a metric field (SimOptions::metric), which the device-resident run refuses:
// "host" and "auto" the host reference (auto noted); an explicit opencl spec the host driver over that
// device's OpenCL StepBackend (metric mode with the host's neighbour rows), in the precision chosen as
// choose_backend chooses it. InputError when the device is not there, DeviceError when the program
// does not build on it.
ChosenBackend choose_metric_backend(const std::string& device, Precision precision,
                                    const std::function<void(const std::string&)>& note);

// How many backends choose_backend and choose_backend_for have set up in this process (a test hook:
// a caller that keeps its backend, like the Python Mesher's steps, sets up one).
std::size_t backend_setups();

// The first of `candidates` (tried in order; each failure noted) on which the program builds, else
// the host reference. `fall_back` false: the first candidate's DeviceError propagates.
ChosenBackend choose_among(const std::vector<ocl::DeviceInfo>& candidates, bool fall_back, Precision precision,
                           const std::function<void(const std::string&)>& note);

}  // namespace pdmesh
