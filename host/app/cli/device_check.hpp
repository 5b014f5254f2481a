// `pdmesh devices --check` on one device: does the simulation program build and run there, and does
// a short device-resident run repeat the host reference bit for bit (double) or stay close (float)?
// Bit-identity needs the device to honour `#pragma OPENCL FP_CONTRACT OFF` (no fused multiply-adds
// the host does not make) and to round double / and sqrt correctly (docs/opencl.md, "Bit-identity").
#pragma once
#include <string>
#include <vector>

#include "opencl/devices.hpp"

namespace pdmesh {

struct DeviceCheck {
  bool ok = false;                 // false: the program does not build or run, or the run is wrong
  bool bit_identical = false;      // double run equal to the host's in every node
  std::vector<std::string> lines;  // what was checked and found, one finding per line
};

// Builds the step program in double (float without fp64), checks its work-group limits, runs 20
// iterations of a small built-in case (a square with a hole, random start: snaps, neighbour-row growth
// and scatters happen) on the device and on the host reference and compares them node by node, and
// measures the fp64 rate behind --precision auto. Never throws: failures become lines.
DeviceCheck check_device(const ocl::DeviceInfo& device);

}  // namespace pdmesh
