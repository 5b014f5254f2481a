// `pdmesh devices`: lists every OpenCL platform and device with the --device spec that selects it.
#pragma once

namespace pdmesh {

// Prints the device list (and which one `--device auto` picks). With `check`, builds and runs the
// selftest kernel on each device and prints ok or the error. Returns the exit status (1 if a check failed).
int run_devices(bool check);

}  // namespace pdmesh
