// `pdmesh devices`: the OpenCL device list, what `--device auto` would pick, and an optional self-test.
#include "app/devices_command.hpp"

#include <fmt/format.h>

#include <vector>

#include "core/errors.hpp"
#include "opencl/buffer.hpp"
#include "opencl/context.hpp"
#include "opencl/devices.hpp"

namespace pdmesh {
namespace {

// y = 2x + i on a few elements in REAL = T; returns an empty string on success, else what is wrong.
template <typename T>
std::string run_axpy(ocl::Context& ctx, cl::Kernel& k, std::size_t wg) {
  const int n = 13;
  std::vector<T> x(n, T(1.5)), y;
  ocl::Buffer<T> bx(ctx, "x", n), by(ctx, "y", n);
  bx.upload(ctx.queue(), x);
  k.setArg(0, n);
  k.setArg(1, T(2));
  k.setArg(2, bx.get());
  k.setArg(3, by.get());
  ocl::launch(ctx.queue(), k, "selftest_axpy", n, wg);
  by.download(ctx.queue(), y);
  for (int i = 0; i < n; ++i)
    if (y[i] != T(3) + static_cast<T>(i))
      return fmt::format("wrong result y[{}] = {} (expected {})", i, y[i], 3 + i);
  return "";
}

// Builds and runs the selftest kernel, in double where the device has fp64.
std::string self_test(const ocl::DeviceInfo& info) {
  try {
    ocl::Context ctx(info);
    const auto precision = info.fp64 ? ocl::Precision::Double : ocl::Precision::Float;
    const std::size_t wg = 8;
    cl::Program program = ctx.build({"selftest.cl"}, ocl::precision_defines(precision, wg));
    cl_int err = CL_SUCCESS;
    cl::Kernel k(program, "selftest_axpy", &err);
    ocl::check(err, "clCreateKernel(selftest_axpy)");
    return precision == ocl::Precision::Double ? run_axpy<double>(ctx, k, wg) : run_axpy<float>(ctx, k, wg);
  } catch (const Error& e) {
    return e.what();
  }
}

}  // namespace

int run_devices(bool check) {
  const auto devices = ocl::list_devices();
  fmt::print("OpenCL devices ({}):\n{}", devices.size(), ocl::describe_all(devices));
  const auto chosen = ocl::select_device("auto");
  fmt::print("--device auto picks: {}\n", chosen ? fmt::format("opencl:{}:{} ({})", chosen->platform, chosen->device,
                                                                chosen->name)
                                                : std::string("host (no OpenCL device)"));
  int status = 0;
  if (check) {
    for (const auto& d : devices) {
      const std::string problem = self_test(d);
      fmt::print("check opencl:{}:{}: {}\n", d.platform, d.device, problem.empty() ? "ok" : "FAILED: " + problem);
      if (!problem.empty()) status = 1;
    }
  }
  return status;
}

}  // namespace pdmesh
