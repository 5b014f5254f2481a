// `pdmesh devices`: lists every OpenCL platform and device with the --device spec that selects it.
#pragma once

namespace pdmesh {

// Prints the device list (and which one `--device auto` picks). With `check`, checks each device
// (check_device: program build, a short run against the host reference, the fp64 rate) and prints
// what it found. Returns the exit status (1 if a device failed its check).
int run_devices(bool check);

}  // namespace pdmesh
