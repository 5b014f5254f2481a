// `pdmesh mesh` refuses, with exit status 2, the numbers and nothing written, what its budgets
// (--max-nodes, --max-memory) do not allow, before the stage that would allocate it; and values
// that the node estimate or a reader could not represent get a message that says what they are.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <initializer_list>
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

// A refusal as the budgets give it: exit status 2, a message holding each of `parts`, and no output
// folder.
void check_refused(const pdmesh_test::Result& r, const fs::path& out, std::initializer_list<const char*> parts) {
  INFO(r.output);
  CHECK(r.status == 2);
  for (const char* part : parts) CHECK(contains(r.output, part));
  CHECK_FALSE(fs::exists(out));
}

}  // namespace

TEST_CASE("the node limit (--max-nodes) must be a count >= 1", "[memory]") {
  const fs::path dir = pdmesh_test::fresh_dir("max_nodes_negative");
  const auto r = mesh(write_square(dir), dir / "out", "--max-nodes -1");
  check_refused(r, dir / "out", {"--max-nodes -1: expected a node count >= 1"});
  CHECK(mesh(write_square(dir), dir / "out", "--max-nodes 0").status == 2);
  fs::remove_all(dir);
}

TEST_CASE("the memory limit (--max-memory) takes a size with a suffix and refuses anything else", "[memory]") {
  const fs::path dir = pdmesh_test::fresh_dir("max_memory_bad");
  const auto r = mesh(write_square(dir), dir / "out", "--max-memory 4X");
  check_refused(r, dir / "out", {"--max-memory 4X: expected a size in bytes"});
  fs::remove_all(dir);
}

TEST_CASE("the memory limit (--max-memory) refuses a run whose later stages would not fit, before they allocate",
          "[memory]") {
  const fs::path dir = pdmesh_test::fresh_dir("max_memory_run");
  const auto r = mesh(write_square(dir), dir / "out", "--iterations 5 --max-memory 32M");
  check_refused(r, dir / "out", {"meshing about", "of memory, more than --max-memory 32.0 MiB"});
  // The geometry's tree is checked before it is built.
  const auto tiny = mesh(write_square(dir), dir / "out", "--max-memory 1K");
  check_refused(tiny, dir / "out", {"the geometry's quadtree over 4 segments needs about 2.00 KiB of memory"});
  fs::remove_all(dir);
}

TEST_CASE("a field that asks for 1e9 nodes is refused on the quadtree's first level", "[memory]") {
  const fs::path dir = pdmesh_test::fresh_dir("uniform_1e9");
  // 3.4e-5 on the unit square: about 1e9 nodes, a quadtree of ~3e8 leaves at that resolution.
  const auto r = mesh(write_square(dir), dir / "out", "--set spacing.expression=3.4e-5");
  // The best preset places the nodes at spacing.relax_scale x q (1.09): 1/1.09^2 of them.
  check_refused(r, dir / "out",
                {"asks for about 8.4", "already on level 0 of its quadtree", "more than --max-nodes 20000000"});
  // The thesis preset (the exact field's quadtree, built lazily, relax_scale 1) is refused the same way.
  const auto thesis = mesh(write_square(dir), dir / "out", "--set spacing.expression=3.4e-5 --set preset=thesis");
  check_refused(thesis, dir / "out", {"asks for about 9.9", "already on level 0 of its quadtree"});
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
  check_refused(r, dir / "out", {"square.crv:3: x coordinate '1e-400' is too small for a double"});
  CHECK_FALSE(contains(r.output, "too large"));
  fs::remove_all(dir);
}

TEST_CASE("a denormal spacing is called an underflow, not coordinates too large", "[memory]") {
  const fs::path dir = pdmesh_test::fresh_dir("denormal_spacing");
  const auto r = mesh(write_square(dir), dir / "out", "--set spacing.expression=1e-310");
  check_refused(r, dir / "out", {"is 1e-310, below the smallest normal double (2.22507e-308)"});
  CHECK_FALSE(contains(r.output, "move the geometry nearer the origin"));
  fs::remove_all(dir);
}
