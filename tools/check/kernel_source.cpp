// Prints the simulation program exactly as StepProgram hands it to the OpenCL compiler (the defines
// the program builder prepends, common.cl and the kernel files in build order), for a precision and a
// force-loop shape, so tools/check/kernel_registers.sh compiles the host's program for GPU targets. Needs no
// OpenCL device. Exit status 2 on a bad argument.
// Usage: kernel_source double|float vector|scalar
#include <fmt/format.h>

#include <string>

#include "core/errors.hpp"
#include "opencl/context.hpp"
#include "opencl/step_program.hpp"

int main(int argc, char** argv) {
  using namespace pdmesh;
  const std::string usage = "usage: kernel_source double|float vector|scalar\n";
  if (argc != 3) {
    fmt::print(stderr, "{}", usage);
    return 2;
  }
  const std::string precision = argv[1];
  if (precision != "double" && precision != "float") {
    fmt::print(stderr, "kernel_source: the precision must be double or float, got '{}'\n{}", precision, usage);
    return 2;
  }
  try {
    const ocl::ForceLoop loop = ocl::parse_force_loop(argv[2], "kernel_source: the force loop");
    if (loop == ocl::ForceLoop::Auto) throw InputError("kernel_source: name the force loop: vector or scalar");
    const ocl::Precision p = precision == "double" ? ocl::Precision::Double : ocl::Precision::Float;
    fmt::print("{}",
               ocl::program_source(ocl::step_program_files(), ocl::step_program_defines(p, ocl::kStepWorkGroup, loop)));
  } catch (const InputError& e) {
    fmt::print(stderr, "{}\n{}", e.what(), usage);
    return 2;
  }
  return 0;
}
