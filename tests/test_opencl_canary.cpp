// The canary tail of device buffers (Context::set_canary_tail, buffer.hpp) that the StepBackend and
// device-run tests rely on: a write past a buffer's end, by the host or by a kernel whose rounded-up
// work-items are not masked, makes the next download throw DeviceError naming the buffer.
#include <catch2/catch.hpp>

#include <cstdint>
#include <vector>

#include "core/errors.hpp"
#include "opencl/buffer.hpp"
#include "opencl/cl_errors.hpp"
#include "opencl/context.hpp"
#include "step_backend_inputs.hpp"

using namespace pdmesh;
using namespace pdmesh::ocl;

namespace {

// Writes out[i] = i for every work-item; `guarded` masks the items at or past n.
void run_fill(Context& ctx, Buffer<std::int32_t>& out, int n, bool guarded) {
  const char* source =
      "__kernel void fill_guarded(int n, __global int* out) { int i = get_global_id(0); if (i < n) out[i] = i; }\n"
      "__kernel void fill_unguarded(int n, __global int* out) { int i = get_global_id(0); out[i] = i; }\n";
  cl::Program program = ctx.build_source("canary_fill.cl", source, "-cl-std=CL1.2");
  const char* name = guarded ? "fill_guarded" : "fill_unguarded";
  cl_int err = CL_SUCCESS;
  cl::Kernel kernel(program, name, &err);
  check(err, name);
  check(kernel.setArg(0, n), "setArg 0");
  check(kernel.setArg(1, out.get()), "setArg 1");
  launch(ctx.queue(), kernel, name, static_cast<std::size_t>(n), 8);  // global size rounded up to 8
}

}  // namespace

TEST_CASE("the test context gives every buffer a canary tail", "[opencl][canary]") {
  Buffer<double> b(test::test_context(), "x", 5);
  CHECK(b.canary_tail() == test::kCanaryTail);
  CHECK(b.size() == 5);
  CHECK(b.bytes() == 5 * sizeof(double));  // the tail is not part of the buffer's size
  std::vector<double> host{1, 2, 3, 4, 5}, back;
  b.upload(test::test_context().queue(), host);
  REQUIRE_NOTHROW(b.download(test::test_context().queue(), back));
  CHECK(back == host);
}

TEST_CASE("a host write past the end is caught by the next download", "[opencl][canary]") {
  Context& ctx = test::test_context();
  for (std::size_t n : {0u, 1u, 7u, 64u}) {
    INFO(n << " elements");
    Buffer<float> b(ctx, "forces", n);
    std::vector<float> out;
    REQUIRE_NOTHROW(b.download(ctx.queue(), out));
    const float stray = 1.0f;
    check(ctx.queue().enqueueWriteBuffer(b.get(), CL_TRUE, sizeof(float) * (n + 3), sizeof(float), &stray), "stray");
    REQUIRE_THROWS_WITH(b.download(ctx.queue(), out),
                        Catch::Contains("'forces'") && Catch::Contains("element " + std::to_string(n + 3)));
    REQUIRE_THROWS_AS(b.check_canary(ctx.queue()), DeviceError);
  }
}

TEST_CASE("a kernel that lets its rounded-up work-items write is caught, and a masked one is not", "[opencl][canary]") {
  Context& ctx = test::test_context();
  for (int n : {0, 1, 7, 8, 9, 13}) {  // 0, 1, WG-1, WG, WG+1, a prime for the work-group of 8
    INFO(n << " elements");
    Buffer<std::int32_t> good(ctx, "good", static_cast<std::size_t>(n));
    run_fill(ctx, good, n, true);
    std::vector<std::int32_t> out;
    REQUIRE_NOTHROW(good.download(ctx.queue(), out));
    for (int i = 0; i < n; ++i) CHECK(out[static_cast<std::size_t>(i)] == i);
    Buffer<std::int32_t> bad(ctx, "bad", static_cast<std::size_t>(n));
    run_fill(ctx, bad, n, false);
    if (n % 8 != 0) {  // rounded-up items exist (n = 0 launches nothing)
      REQUIRE_THROWS_WITH(bad.download(ctx.queue(), out),
                          Catch::Contains("'bad'") && Catch::Contains("element " + std::to_string(n)));
    } else {
      REQUIRE_NOTHROW(bad.download(ctx.queue(), out));
    }
  }
}

TEST_CASE("without the hook buffers carry no tail", "[opencl][canary]") {
  Context ctx(test::test_context().device());
  Buffer<double> b(ctx, "plain", 3);
  CHECK(b.canary_tail() == 0);
  REQUIRE_NOTHROW(b.check_canary(ctx.queue()));
}

TEST_CASE("a buffer over a host array: kernels read the host's values, and with a canary tail it is a copy",
          "[opencl][canary]") {
  const std::vector<std::int32_t> host{3, 1, 4, 1, 5, 9, 2, 6, 5};
  Context ctx(test::test_context().device());  // no tail: the buffer is the host's array
  auto in = Buffer<std::int32_t>::over_host(ctx, "field", host);
  CHECK(in.size() == host.size());
  CHECK(in.canary_tail() == 0);
  const char* source =
      "__kernel void twice(int n, __global const int* in, __global int* out) {\n"
      "  int i = get_global_id(0); if (i < n) out[i] = 2 * in[i]; }\n";
  cl::Program program = ctx.build_source("over_host.cl", source, "-cl-std=CL1.2");
  cl_int err = CL_SUCCESS;
  cl::Kernel kernel(program, "twice", &err);
  check(err, "twice");
  Buffer<std::int32_t> out(ctx, "out", host.size());
  const int n = static_cast<int>(host.size());
  check(kernel.setArg(0, n), "setArg 0");
  check(kernel.setArg(1, in.get()), "setArg 1");
  check(kernel.setArg(2, out.get()), "setArg 2");
  launch(ctx.queue(), kernel, "twice", host.size(), 8);
  std::vector<std::int32_t> doubled, back;
  out.download(ctx.queue(), doubled);
  in.download(ctx.queue(), back);
  CHECK(back == host);
  for (std::size_t i = 0; i < host.size(); ++i) CHECK(doubled[i] == 2 * host[i]);
  // The test context's tail needs room past the array: a copy with its tail, checked on download.
  auto copy = Buffer<std::int32_t>::over_host(test::test_context(), "field", host);
  CHECK(copy.canary_tail() == test::kCanaryTail);
  REQUIRE_NOTHROW(copy.download(test::test_context().queue(), back));
  CHECK(back == host);
}
