// Builds the simulation program and creates its kernels; see step_program.hpp.
#include "opencl/step_program.hpp"

namespace pdmesh::ocl {
namespace {

cl::Kernel make_kernel(cl::Program& program, const char* name) {
  cl_int err = CL_SUCCESS;
  cl::Kernel k(program, name, &err);
  check(err, fmt::format("clCreateKernel({})", name));
  return k;
}

}  // namespace

StepProgram::StepProgram(Context& ctx, Precision p, std::size_t wg) : precision(p), work_group(wg) {
  if (p == Precision::Double && !ctx.device().fp64)
    throw DeviceError(fmt::format("{} has no double precision (cl_khr_fp64): use --precision float", ctx.device().name));
  program = ctx.build({"spacing_field.cl", "reduce.cl", "forces.cl", "time_step.cl", "neighbours.cl", "device_step.cl"},
                      precision_defines(p, wg));
  build_neighbours = make_kernel(program, "build_neighbours");
  finish_neighbours = make_kernel(program, "finish_neighbours");
  compute_forces = make_kernel(program, "compute_forces");
  time_step_and_move = make_kernel(program, "time_step_and_move");
  reduce = make_kernel(program, "reduce");
  device_step = make_kernel(program, "device_step");
  apply_host_moves = make_kernel(program, "apply_host_moves");
}

}  // namespace pdmesh::ocl
