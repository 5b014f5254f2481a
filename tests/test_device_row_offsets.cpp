// Neighbour-row offsets past 2^31 entries (kernels/common.cl, row_base). Every row is `stride`
// entries, the largest row count of the run (856 on shock), so at 2.5M nodes i * stride no longer fits
// an int: a kernel computing it in int reads or writes 8 GiB before its buffer. A test that reads such
// a row needs an index buffer of 8 GiB, which PoCL refuses (it enforces CL_DEVICE_MAX_MEM_ALLOC_SIZE,
// 2 GiB here) and Oclgrind backs with real memory; so the offsets are tested on the device directly:
// row_base at strides and node indices whose products pass 2^31 (kernels/selftest.cl,
// selftest_row_base), and no kernel source multiplies by the stride anywhere else. With row_base in
// int arithmetic, as every kernel had it before, the first test fails (its products wrap negative).
#include <catch2/catch.hpp>

#include <cstdint>
#include <limits>
#include <regex>
#include <string>
#include <vector>

#include "core/embedded_kernels.hpp"
#include "opencl/buffer.hpp"
#include "opencl/step_program.hpp"
#include "step_backend_inputs.hpp"

using namespace pdmesh;

TEST_CASE("row offsets are computed in 64 bits on the device", "[opencl][row_offsets]") {
  ocl::Context& ctx = test::test_context();
  const std::size_t wg = ocl::kStepWorkGroup;
  cl::Program program = ctx.build({"selftest.cl"}, ocl::precision_defines(ocl::Precision::Double, wg));
  cl_int err = CL_SUCCESS;
  cl::Kernel kernel(program, "selftest_row_base", &err);
  ocl::check(err, "clCreateKernel(selftest_row_base)");
  constexpr std::int32_t kMax = std::numeric_limits<std::int32_t>::max();
  struct Probe {
    std::int32_t stride;
    std::vector<std::int32_t> nodes;
  };
  // Shock's stride at 2.5M nodes and more; few rows of a huge stride; the largest int operands.
  const std::vector<Probe> probes = {{856, {0, 1, 2'508'000, 2'508'740, 3'000'000, 20'000'000}},
                                     {(1 << 30) + 8, {0, 1, 2, 3}},
                                     {kMax, {kMax - 1, kMax}}};
  int past = 0;
  for (const Probe& p : probes) {
    INFO("stride " << p.stride);
    const auto n = p.nodes.size();
    ocl::Buffer<std::int32_t> nodes(ctx, "nodes", n);
    ocl::Buffer<std::int64_t> out(ctx, "row_base", n);
    nodes.upload(ctx.queue(), p.nodes);
    ocl::ArgSetter(kernel, "selftest_row_base")(static_cast<cl_int>(n))(static_cast<cl_int>(p.stride))(nodes)(out);
    ocl::launch(ctx.queue(), kernel, "selftest_row_base", n, wg);
    std::vector<std::int64_t> got;
    out.download(ctx.queue(), got);
    for (std::size_t k = 0; k < n; ++k) {
      const std::int64_t expected = static_cast<std::int64_t>(p.nodes[k]) * p.stride;
      INFO("node " << p.nodes[k]);
      CHECK(got[k] == expected);
      past += expected > kMax ? 1 : 0;
    }
  }
  CHECK(past >= 6);
}

TEST_CASE("no kernel computes a row offset outside row_base", "[opencl][row_offsets]") {
  // A product with the stride (`i * stride`, `stride * j`) is a row offset; row_base is its one place.
  const std::regex product(R"((\w|\))\s*\*\s*\(?\s*(\(long\)\s*)?stride\b|\bstride\s*\)?\s*\*\s*\w)");
  int files = 0;
  for (const auto& k : embedded_kernels()) {
    ++files;
    std::size_t line_number = 0;
    std::string::size_type start = 0;
    while (start < k.source.size()) {
      const auto end = k.source.find('\n', start);
      const std::string line = k.source.substr(start, end == std::string::npos ? std::string::npos : end - start);
      start = end == std::string::npos ? k.source.size() : end + 1;
      ++line_number;
      const std::string code = line.substr(0, line.find("//"));
      if (code.find("long row_base(") != std::string::npos) continue;  // the definition itself
      INFO(k.file << ":" << line_number << ": " << line);
      CHECK_FALSE(std::regex_search(code, product));
    }
  }
  CHECK(files >= 8);
}
