// --precision auto: whether a device should simulate in double or float. Consumer GPUs run fp64 at
// 1/16 to 1/64 of their float rate and some have none; data-centre GPUs and CPUs at 1/2 or better.
// Float costs little once a run is on another device anyway (docs/opencl.md, "Precision").
#pragma once
#include <functional>
#include <string>

#include "opencl/context.hpp"

namespace pdmesh::ocl {

// Float is chosen when double runs more than this many times slower than float.
inline constexpr double kFp64SlowdownLimit = 8.0;

// How many times longer the selftest_rate kernel (kernels/selftest.cl: multiply-add chains) takes
// in double than in float on ctx's device, the same work in both: the work grows until a float run
// takes a few milliseconds (launch overhead then negligible), best of three timed runs after a
// warm-up. Needs fp64 (DeviceError otherwise); builds two small programs.
double measure_fp64_slowdown(Context& ctx);

struct PrecisionChoice {
  Precision precision = Precision::Double;
  std::string reason;  // one line for the progress output
};

// --precision auto on `device`: float without fp64; double on CPU devices (fp64 at half the float
// rate or better: measuring is not worth the two program builds); otherwise float when
// measure() > kFp64SlowdownLimit. measure is called only for such devices.
PrecisionChoice choose_precision_auto(const DeviceInfo& device, const std::function<double()>& measure);

}  // namespace pdmesh::ocl
