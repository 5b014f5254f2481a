// The fp64 rate measurement and the --precision auto rule; see precision_probe.hpp.
#include "opencl/precision_probe.hpp"

#include <algorithm>
#include <chrono>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "opencl/buffer.hpp"
#include "opencl/cl_errors.hpp"
#include "opencl/step_program.hpp"

namespace pdmesh::ocl {
namespace {

constexpr std::size_t kGroup = 64;
constexpr int kRounds = 256;
constexpr double kTargetSeconds = 0.004;     // a float run at least this long
constexpr std::size_t kMaxItems = 1u << 24;  // 16M work-items x 256 rounds x 8 flops: 34 GFLOP

template <typename Real>
class RateProbe {
 public:
  explicit RateProbe(Context& ctx) : ctx_(ctx) {
    program_ =
        ctx.build({"selftest.cl"},
                  precision_defines(std::is_same_v<Real, double> ? Precision::Double : Precision::Float, kGroup));
    cl_int err = CL_SUCCESS;
    kernel_ = cl::Kernel(program_, "selftest_rate", &err);
    check(err, "clCreateKernel(selftest_rate)");
  }
  // Best of three runs over `items` work-items (after one untimed run), in seconds.
  double seconds(std::size_t items) {
    if (out_.size() < items) out_ = Buffer<Real>(ctx_, "rate_out", items);
    ArgSetter(kernel_,
              "selftest_rate")(static_cast<cl_int>(kRounds))(static_cast<Real>(0.999))(static_cast<Real>(0.001))(out_);
    double best = 0.0;
    for (int run = 0; run < 4; ++run) {
      const auto t0 = std::chrono::steady_clock::now();
      launch(ctx_.queue(), kernel_, "selftest_rate", items, kGroup);
      finish(ctx_.queue(), "selftest_rate");
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (run == 1 || (run > 1 && s < best)) best = s;
    }
    return best;
  }

 private:
  Context& ctx_;
  cl::Program program_;
  cl::Kernel kernel_;
  Buffer<Real> out_;
};

}  // namespace

double measure_fp64_slowdown(Context& ctx) {
  if (!ctx.device().fp64) throw DeviceError(fmt::format("{} has no fp64 to measure", ctx.device().name));
  RateProbe<float> f(ctx);
  RateProbe<double> d(ctx);
  std::size_t items = 1u << 14;
  double float_seconds = f.seconds(items);
  while (float_seconds < kTargetSeconds && items < kMaxItems) {
    items *= 4;
    float_seconds = f.seconds(items);
  }
  const double double_seconds = d.seconds(items);
  return double_seconds / std::max(float_seconds, 1e-9);
}

PrecisionChoice choose_precision_auto(const DeviceInfo& device, const std::function<double()>& measure) {
  if (!device.fp64) return {Precision::Float, fmt::format("float ({} has no fp64)", device.name)};
  if (device.type == "CPU") return {Precision::Double, "double (a CPU device: fp64 at half the float rate or better)"};
  const double slowdown = measure();
  const bool slow = slowdown > kFp64SlowdownLimit;
  return {slow ? Precision::Float : Precision::Double,
          fmt::format("{} (double took {:.1f}x as long as float on {}, measured; float past {:g}x)",
                      slow ? "float" : "double", slowdown, device.name, kFp64SlowdownLimit)};
}

}  // namespace pdmesh::ocl
