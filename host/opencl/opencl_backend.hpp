// The OpenCL StepBackend: each step of host/sim/step_backend.hpp as a kernel (kernels/neighbours.cl,
// forces.cl, time_step.cl, reduce.cl), in double or float. Every call uploads its inputs and
// downloads its outputs (the contract is host arrays in, host arrays out); the device-resident run
// that avoids that traffic is host/opencl/device_simulation.hpp.
#pragma once
#include <memory>

#include "opencl/context.hpp"
#include "sim/step_backend.hpp"

namespace pdmesh::ocl {

// The backend keeps a reference to ctx (which must outlive it) and builds its program once, with the
// force loop `loop` (Auto: by the device type; step_program.hpp).
std::unique_ptr<StepBackend> make_opencl_backend(Context& ctx, Precision precision, ForceLoop loop = ForceLoop::Auto);

}  // namespace pdmesh::ocl
