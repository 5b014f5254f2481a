// The smallest real launch the OpenCL wrapper tests count and time: kernels/selftest.cl's
// selftest_axpy (y[i] = a x[i] + i) in float, built on a test's context.
#pragma once
#include <cstddef>

#include "opencl/buffer.hpp"
#include "opencl/context.hpp"

namespace pdmesh::test {

// The kernel with its arguments set: n elements, y = 2 x + i.
inline cl::Kernel selftest_axpy(ocl::Context& ctx, std::size_t wg, int n, ocl::Buffer<float>& x,
                                ocl::Buffer<float>& y) {
  cl::Program program = ctx.build({"selftest.cl"}, ocl::precision_defines(ocl::Precision::Float, wg));
  cl_int err = CL_SUCCESS;
  cl::Kernel k(program, "selftest_axpy", &err);  // the kernel keeps its program alive
  ocl::check(err, "clCreateKernel(selftest_axpy)");
  k.setArg(0, n);
  k.setArg(1, 2.0f);
  k.setArg(2, x.get());
  k.setArg(3, y.get());
  return k;
}

}  // namespace pdmesh::test
