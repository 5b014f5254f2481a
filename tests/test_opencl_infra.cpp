// The OpenCL infrastructure on the first available device (PoCL's CPU device in CI): device listing,
// the program builder with shared defines, typed buffers with a canary tail, and error reporting.
#include <catch2/catch.hpp>

#include "core/errors.hpp"
#include "opencl/buffer.hpp"
#include "opencl/cl_errors.hpp"
#include "opencl/context.hpp"
#include "opencl/devices.hpp"
#include "opencl/step_program.hpp"

using namespace pdmesh;
using namespace pdmesh::ocl;

namespace {
// CI always has PoCL: a missing device must fail loudly, not skip.
DeviceInfo require_device() {
  auto d = select_device("auto");
  REQUIRE(d.has_value());
  return *d;
}
}  // namespace

TEST_CASE("error names cover the common codes", "[opencl]") {
  CHECK(std::string(error_name(CL_OUT_OF_RESOURCES)) == "CL_OUT_OF_RESOURCES");
  CHECK(std::string(error_name(CL_BUILD_PROGRAM_FAILURE)) == "CL_BUILD_PROGRAM_FAILURE");
  CHECK(std::string(error_name(12345)) == "CL_UNKNOWN_ERROR");
  REQUIRE_THROWS_WITH(check(CL_INVALID_KERNEL_ARGS, "enqueue 'sum_forces'"),
                      "enqueue 'sum_forces' failed: CL_INVALID_KERNEL_ARGS (-52)");
  REQUIRE_NOTHROW(check(CL_SUCCESS, "anything"));
}

TEST_CASE("devices are listed and selected", "[opencl]") {
  auto devices = list_devices();
  REQUIRE_FALSE(devices.empty());
  for (const auto& d : devices) {
    CHECK(!d.name.empty());
    CHECK(d.compute_units > 0);
    CHECK(d.max_work_group > 0);
    CHECK(describe(d).find(d.name) != std::string::npos);
  }
  auto chosen = require_device();
  auto explicit_spec = fmt::format("opencl:{}:{}", chosen.platform, chosen.device);
  CHECK(select_device(explicit_spec)->name == chosen.name);
  REQUIRE_THROWS_AS(select_device("opencl:99:0"), InputError);
  REQUIRE_THROWS_WITH(select_device("opencl:99:0"), Catch::Contains("Available"));
  REQUIRE_THROWS_AS(select_device("gpu please"), InputError);
}

TEST_CASE("program builder runs an embedded kernel in both precisions", "[opencl]") {
  auto info = require_device();
  Context ctx(info);
  const std::size_t wg = 8;
  for (auto precision : {Precision::Double, Precision::Float}) {
    if (precision == Precision::Double && !info.fp64) continue;
    auto program = ctx.build({"selftest.cl"}, precision_defines(precision, wg));
    cl_int err = CL_SUCCESS;
    cl::Kernel k(program, "selftest_axpy", &err);
    check(err, "clCreateKernel(selftest_axpy)");
    for (int n : {0, 1, 7, 9, 13}) {  // 0, 1, WG-1, WG+1, a prime
      std::vector<double> x(n);
      for (int i = 0; i < n; ++i) x[i] = 0.5 * i - 3;
      const double canary = -12345.0;
      if (precision == Precision::Double) {
        Buffer<double> bx(ctx, "x", n), by(ctx, "y", n + 4);
        bx.upload(ctx.queue(), x);
        std::vector<double> init(n + 4, canary);
        by.upload(ctx.queue(), init);
        k.setArg(0, n);
        k.setArg(1, 2.0);
        k.setArg(2, bx.get());
        k.setArg(3, by.get());
        launch(ctx.queue(), k, "selftest_axpy", n, wg);
        std::vector<double> y;
        by.download(ctx.queue(), y);
        for (int i = 0; i < n; ++i) CHECK(y[i] == 2.0 * x[i] + i);
        for (int i = n; i < n + 4; ++i) CHECK(y[i] == canary);  // nothing written past the end
      } else {
        std::vector<float> xf(x.begin(), x.end());
        Buffer<float> bx(ctx, "x", n), by(ctx, "y", n + 4);
        bx.upload(ctx.queue(), xf);
        std::vector<float> init(n + 4, static_cast<float>(canary));
        by.upload(ctx.queue(), init);
        k.setArg(0, n);
        k.setArg(1, 2.0f);
        k.setArg(2, bx.get());
        k.setArg(3, by.get());
        launch(ctx.queue(), k, "selftest_axpy", n, wg);
        std::vector<float> y;
        by.download(ctx.queue(), y);
        for (int i = 0; i < n; ++i) CHECK(y[i] == 2.0f * xf[i] + static_cast<float>(i));
        for (int i = n; i < n + 4; ++i) CHECK(y[i] == static_cast<float>(canary));
      }
    }
  }
}

TEST_CASE("a kernel that fails to build reports file, options and log", "[opencl]") {
  Context ctx(require_device());
  try {
    ctx.build_source("broken.cl", "__kernel void f(__global int* p) { p[0] = undeclared_name; }", "-cl-std=CL1.2");
    FAIL("build should have failed");
  } catch (const DeviceError& e) {
    std::string m = e.what();
    CHECK(m.find("broken.cl") != std::string::npos);
    CHECK(m.find("-cl-std=CL1.2") != std::string::npos);
    CHECK(m.find("CL_BUILD_PROGRAM_FAILURE") != std::string::npos);
    CHECK(m.find("undeclared_name") != std::string::npos);  // the compiler's log names the culprit
  }
}

TEST_CASE("buffers check sizes and names", "[opencl]") {
  Context ctx(require_device());
  Buffer<int> b(ctx, "counts", 4);
  CHECK(b.name() == "counts");
  CHECK(b.bytes() == 16);
  std::vector<int> big(5, 1);
  REQUIRE_THROWS_WITH(b.upload(ctx.queue(), big), Catch::Contains("'counts'"));
  std::vector<int> out;
  REQUIRE_THROWS_AS(b.download(ctx.queue(), out, 9), DeviceError);
  REQUIRE_THROWS_WITH(ocl::kernel_source("no_such.cl"), Catch::Contains("no_such.cl"));
}

TEST_CASE("the simulation program's work-group size is checked against every kernel's limit", "[opencl]") {
  Context ctx(require_device());
  const StepProgram program(ctx, ctx.device().fp64 ? Precision::Double : Precision::Float);
  // 31 kernels (the 4 of metric mode, kernels/metric.cl, the latest), and boundary_snap_rule where the device
  // has fp64 (kernels/boundary.cl).
  REQUIRE(program.limits.size() == (ctx.device().fp64 ? 32u : 31u));
  for (const KernelLimits& k : program.limits) {
    INFO(k.name);
    CHECK(k.max_work_group >= program.work_group);
    CHECK(k.preferred_multiple > 0);
  }
  CHECK(work_group_advice(program.limits, program.work_group).empty());  // PoCL prefers multiples of 8
  // A device whose kernel allows fewer work-items than pdmesh's groups: a clear error, not a launch failure.
  REQUIRE_THROWS_AS(check_work_group("device_step", "Some GPU", 64, 32), DeviceError);
  REQUIRE_THROWS_WITH(check_work_group("device_step", "Some GPU", 64, 32),
                      Catch::Contains("kernel 'device_step' runs at most 32 work-items per group on Some GPU "
                                      "(CL_KERNEL_WORK_GROUP_SIZE") &&
                          Catch::Contains("need groups of 64") && Catch::Contains("--device host"));
  REQUIRE_NOTHROW(check_work_group("device_step", "Some GPU", 64, 64));
  CHECK(work_group_advice({{"reduce", 256, 48}}, 64).find("kernel 'reduce' prefers multiples of 48") !=
        std::string::npos);
}
