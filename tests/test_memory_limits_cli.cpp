// `pdmesh mesh` refuses, with exit status 2, the numbers and nothing written, what its budgets
// (--max-nodes, --max-memory) do not allow, before the stage that would allocate it; and values
// that the node estimate or a reader could not represent get a message that says what they are.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "run_pdmesh.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;

namespace {

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// The unit square as one closed curve.
fs::path write_square(const fs::path& dir, const std::string& x1 = "1") {
  const fs::path file = dir / "square.crv";
  std::ofstream(file) << "5\n0 0\n" << x1 << " 0\n1 1\n0 1\n0 0\n";
  return file;
}

pdmesh_test::Result mesh(const fs::path& input, const fs::path& out, const std::string& options) {
  return pdmesh_test::run_pdmesh("mesh '" + input.string() + "' --out '" + out.string() + "' --device host " + options);
}

}  // namespace

TEST_CASE("the node limit (--max-nodes) must be a count >= 1", "[memory]") {
  const fs::path dir = pdmesh_test::fresh_dir("max_nodes_negative");
  const auto r = mesh(write_square(dir), dir / "out", "--max-nodes -1");
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK(contains(r.output, "--max-nodes -1: expected a node count >= 1"));
  CHECK_FALSE(fs::exists(dir / "out"));
  CHECK(mesh(write_square(dir), dir / "out", "--max-nodes 0").status == 2);
  fs::remove_all(dir);
}

TEST_CASE("the memory limit (--max-memory) takes a size with a suffix and refuses anything else", "[memory]") {
  const fs::path dir = pdmesh_test::fresh_dir("max_memory_bad");
  const auto r = mesh(write_square(dir), dir / "out", "--max-memory 4X");
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK(contains(r.output, "--max-memory 4X: expected a size in bytes"));
  CHECK_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

TEST_CASE("the memory limit (--max-memory) refuses a run whose later stages would not fit, before they allocate", "[memory]") {
  const fs::path dir = pdmesh_test::fresh_dir("max_memory_run");
  const auto r = mesh(write_square(dir), dir / "out", "--iterations 5 --max-memory 32M");
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK(contains(r.output, "meshing about"));
  CHECK(contains(r.output, "of memory, more than --max-memory 32.0 MiB"));
  CHECK_FALSE(fs::exists(dir / "out"));
  // The geometry's tree is checked before it is built.
  const auto tiny = mesh(write_square(dir), dir / "out", "--max-memory 1K");
  INFO(tiny.output);
  CHECK(tiny.status == 2);
  CHECK(contains(tiny.output, "the geometry's quadtree over 4 segments needs about 2.00 KiB of memory"));
  CHECK_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

TEST_CASE("a field that asks for 1e9 nodes is refused on the quadtree's first level", "[memory]") {
  const fs::path dir = pdmesh_test::fresh_dir("uniform_1e9");
  // 3.4e-5 on the unit square: about 1e9 nodes, a quadtree of ~3e8 leaves at that resolution.
  const auto r = mesh(write_square(dir), dir / "out", "--set spacing.expression=3.4e-5");
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK(contains(r.output, "asks for about 9.9"));
  CHECK(contains(r.output, "already on level 0 of its quadtree"));
  CHECK(contains(r.output, "more than --max-nodes 20000000"));
  CHECK_FALSE(fs::exists(dir / "out"));
  // The thesis preset (the exact field's quadtree, built lazily) is refused the same way.
  const auto thesis = mesh(write_square(dir), dir / "out", "--set spacing.expression=3.4e-5 --set preset=thesis");
  INFO(thesis.output);
  CHECK(thesis.status == 2);
  CHECK(contains(thesis.output, "already on level 0 of its quadtree"));
  CHECK_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

TEST_CASE("a spacing beyond 1e154 is not counted as NaN nodes", "[memory]") {
  const fs::path dir = pdmesh_test::fresh_dir("huge_spacing");
  // q^2 overflows: the estimate was inf - inf, "asks for about -nan nodes".
  const auto r = mesh(write_square(dir), dir / "out", "--set spacing.expression=1e200 --iterations 0 --max-nodes 10");
  INFO(r.output);
  CHECK_FALSE(contains(r.output, "nan"));
  CHECK(r.status == 0);
  fs::remove_all(dir);
}

TEST_CASE("a coordinate that underflows is called too small, not too large", "[memory]") {
  const fs::path dir = pdmesh_test::fresh_dir("underflow");
  const auto r = mesh(write_square(dir, "1e-400"), dir / "out", "");
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK(contains(r.output, "square.crv:3: x coordinate '1e-400' is too small for a double"));
  CHECK_FALSE(contains(r.output, "too large"));
  CHECK_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

TEST_CASE("a denormal spacing is called an underflow, not coordinates too large", "[memory]") {
  const fs::path dir = pdmesh_test::fresh_dir("denormal_spacing");
  const auto r = mesh(write_square(dir), dir / "out", "--set spacing.expression=1e-310");
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK(contains(r.output, "is 1e-310, below the smallest normal double (2.22507e-308)"));
  CHECK_FALSE(contains(r.output, "move the geometry nearer the origin"));
  CHECK_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}
