// Whether a device run goes on while the host measures the mesh for the stopping rule
// (DeviceRun::run_ahead; docs/opencl.md, "The overlapped measurement").
#pragma once

namespace pdmesh::ocl {

// Off: the device waits for the measurement. On: it runs further windows and builds meanwhile, until
// the measurement ends. Full: it runs ahead to where the host must act, however soon the measurement
// ends (the tests: the same runs whatever the timing).
enum class MeasureOverlap { Off, On, Full };

// PDMESH_MEASURE_OVERLAP (0, 1 or full); unset: On for a GPU, Off for a CPU device, whose threads are
// the host's and would compete with the measurement's triangulation. Another value throws InputError
// naming the variable and the value.
MeasureOverlap measure_overlap(bool cpu_device);

}  // namespace pdmesh::ocl
