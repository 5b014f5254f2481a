// The simulation kernels of one device and precision, built once: kernels/spacing_field.cl,
// neighbours.cl, forces.cl, time_step.cl, reduce.cl and device_step.cl in one program, plus the
// argument helper every launch uses (errors name the kernel and the argument).
#pragma once
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include <fmt/format.h>

#include "opencl/buffer.hpp"
#include "opencl/cl_errors.hpp"
#include "opencl/context.hpp"

namespace pdmesh::ocl {

// Work-group size of every simulation kernel (a power of two: the reductions halve it). 64 measured
// best on PoCL's CPU device among 32/64/128 (docs/opencl.md).
inline constexpr std::size_t kStepWorkGroup = 64;
// Partial sums per group written by the device_step kernel (STEP_PARTIALS in device_step.cl).
inline constexpr std::size_t kStepPartials = 7;

// What the device allows one kernel of the program (clGetKernelWorkGroupInfo).
struct KernelLimits {
  std::string name;
  std::size_t max_work_group = 0;      // CL_KERNEL_WORK_GROUP_SIZE
  std::size_t preferred_multiple = 0;  // CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE
};

// Throws DeviceError naming the kernel, the device and both sizes when work_group > kernel_limit.
void check_work_group(const std::string& kernel, const std::string& device, std::size_t work_group,
                      std::size_t kernel_limit);
// "" when work_group is a multiple of every kernel's preferred multiple, else what idles (a note, not an error).
std::string work_group_advice(const std::vector<KernelLimits>& limits, std::size_t work_group);

// Builds the program for `precision` (DeviceError when the device has no fp64 for Double, or the
// build fails, with the build log) and checks every kernel's CL_KERNEL_WORK_GROUP_SIZE against
// work_group (check_work_group).
struct StepProgram {
  StepProgram(Context& ctx, Precision precision, std::size_t work_group = kStepWorkGroup);
  Precision precision;
  std::size_t work_group;
  cl::Program program;
  cl::Kernel build_neighbours, finish_neighbours, compute_forces, time_step_and_move, reduce, device_step, apply_host_moves;
  std::vector<KernelLimits> limits;  // per kernel, in the order above
};

// Sets arguments 0.. of `kernel` in order; Buffer<T> arguments pass their cl::Buffer.
class ArgSetter {
 public:
  ArgSetter(cl::Kernel& kernel, const char* name) : kernel_(kernel), name_(name) {}
  template <typename T>
  ArgSetter& operator()(Buffer<T>& b) {
    const cl_int err = kernel_.setArg(index_, b.get());
    if (err != CL_SUCCESS) check(err, fmt::format("setting argument {} ('{}') of '{}'", index_, b.name(), name_));
    ++index_;
    return *this;
  }
  template <typename T>
  ArgSetter& operator()(const T& value) {
    static_assert(std::is_arithmetic_v<T>);
    const cl_int err = kernel_.setArg(index_, value);
    if (err != CL_SUCCESS) check(err, fmt::format("setting argument {} of '{}'", index_, name_));
    ++index_;
    return *this;
  }

 private:
  cl::Kernel& kernel_;
  const char* name_;
  cl_uint index_ = 0;
};

// Grows a buffer (new allocation, contents lost) when it holds fewer than `count` elements.
template <typename T>
void ensure_size(Context& ctx, Buffer<T>& b, const std::string& name, std::size_t count) {
  if (b.size() < count || b.name().empty()) b = Buffer<T>(ctx, name, count);
}

// Host doubles as the device's REAL.
template <typename Real>
std::vector<Real> to_real(const std::vector<double>& v) {
  return std::vector<Real>(v.begin(), v.end());
}

}  // namespace pdmesh::ocl
