// PDMESH_KERNEL_PROFILE (opencl/kernel_profile.hpp): with the variable set before the first Context,
// the queue profiles, each launch's device time is added to its kernel's totals at the next finish,
// and a run writes the totals to the named file at exit. One test executable of its own: the
// variable is read once per process, before any other test could create a Context.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "opencl/buffer.hpp"
#include "opencl/context.hpp"
#include "opencl/kernel_profile.hpp"
#include "run_pdmesh.hpp"
#include "selftest_axpy.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
using namespace pdmesh::ocl;

TEST_CASE("profiled launches are timed by kernel at the next finish", "[opencl]") {
  const auto file = pdmesh_test::fresh_path("kernel_profile_unit");
  ::setenv("PDMESH_KERNEL_PROFILE", file.c_str(), 1);
  REQUIRE(kernel_profiling());
  auto info = select_device("auto");
  REQUIRE(info.has_value());
  Context ctx(*info);
  const std::size_t wg = 8;
  const int n = 13;
  const std::vector<float> x(n, 1.5f);
  Buffer<float> bx(ctx, "x", n), by(ctx, "y", n);
  bx.upload(ctx.queue(), x);
  by.upload(ctx.queue(), x);
  cl::Kernel k = pdmesh::test::selftest_axpy(ctx, wg, n, bx, by);
  launch(ctx.queue(), k, "selftest_axpy", n, wg);
  launch(ctx.queue(), k, "selftest_axpy", n, wg);
  CHECK(kernel_times().count("selftest_axpy") == 0);  // not collected before the finish
  finish(ctx.queue(), "profiled launches");
  const auto times = kernel_times();
  REQUIRE(times.count("selftest_axpy") == 1);
  CHECK(times.at("selftest_axpy").launches == 2);
  CHECK(times.at("selftest_axpy").seconds >= 0.0);
  launch(ctx.queue(), k, "selftest_axpy", n, wg);
  finish(ctx.queue(), "one more");
  CHECK(kernel_times().at("selftest_axpy").launches == 3);
}

TEST_CASE("a profiled run writes each kernel's launches and seconds at exit", "[opencl][device_sim]") {
  const auto dir = pdmesh_test::fresh_dir("kernel_profile_run");
  const auto file = dir / "kernels.tsv";
  const pdmesh_test::Result r =
      pdmesh_test::run_pdmesh("mesh '" + std::string(PDMESH_SOURCE_DIR) + "/cases/circle_circle/case.toml' --out '" +
                                  (dir / "out").string() + "' -q --device auto --iterations 3 --formats msh",
                              "PDMESH_KERNEL_PROFILE='" + file.string() + "'");
  INFO(r.output);
  REQUIRE(r.status == 0);
  const std::string text = pdmesh_test::slurp(file);
  CHECK(text.rfind("kernel\tlaunches\tseconds\n", 0) == 0);
  CHECK(text.find("\ndevice_step\t3\t") != std::string::npos);  // one launch per iteration
  std::filesystem::remove_all(dir);
}
