// Replays every fuzz seed (tests/fuzz/corpus/TARGET/) and every saved finding
// (tests/fuzz/regressions/TARGET/) through the fuzz entry functions: each input must either
// parse or throw pdmesh::InputError — any other exception fails the test, naming the file.
#include <catch2/catch.hpp>

#include <algorithm>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz/fuzz_entries.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path kFuzzDir = fs::path(PDMESH_SOURCE_DIR) / "tests" / "fuzz";

std::vector<fs::path> files_in(const fs::path& dir) {
  std::vector<fs::path> out;
  if (!fs::is_directory(dir)) return out;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.is_regular_file()) out.push_back(entry.path());
  }
  std::sort(out.begin(), out.end());  // a stable order makes failures reproducible
  return out;
}

std::string bytes_of(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

const pdmesh::fuzz::Target& target_named(const std::string& name) {
  for (const auto& t : pdmesh::fuzz::targets()) {
    if (t.name == name) return t;
  }
  FAIL("no fuzz target " << name);
  throw;  // unreachable: FAIL throws
}

// Returns how many files were replayed.
std::size_t replay(const std::string& name) {
  const auto& target = target_named(name);
  std::size_t count = 0;
  for (const char* kind : {"corpus", "regressions"}) {
    for (const auto& file : files_in(kFuzzDir / kind / name)) {
      const std::string bytes = bytes_of(file);
      INFO("input " << file.string());
      try {
        target.run(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
      } catch (const std::exception& e) {
        FAIL_CHECK("not an InputError: " << e.what());
      } catch (...) {
        FAIL_CHECK("an exception that is not a std::exception");
      }
      ++count;
    }
  }
  return count;
}

}  // namespace

// Every target has seeds: an empty corpus folder would make its test pass vacuously.
TEST_CASE("fuzz corpus: every target has seeds and a libFuzzer source", "[fuzz]") {
  for (const auto& t : pdmesh::fuzz::targets()) {
    INFO("target " << t.name);
    CHECK(!files_in(kFuzzDir / "corpus" / t.name).empty());
    CHECK(fs::is_regular_file(kFuzzDir / (std::string(t.name) + ".cpp")));
  }
  const auto sources = files_in(kFuzzDir);
  CHECK(std::count_if(sources.begin(), sources.end(), [](const fs::path& p) {
          return p.filename().string().rfind("fuzz_", 0) == 0 && p.extension() == ".cpp";
        }) == static_cast<std::ptrdiff_t>(pdmesh::fuzz::targets().size()));
}

// The seeds written by pdmesh's own writers must read back, so that the fuzzers start from
// inputs that reach deep into each reader (a seed rejected on line 1 teaches the fuzzer little).
TEST_CASE("fuzz corpus: the well-formed seeds parse", "[fuzz]") {
  const fs::path corpus = kFuzzDir / "corpus";
  for (const char* msh :
       {"fuzz_mesh_reader_msh/square_41.msh", "fuzz_mesh_reader_msh/square_22.msh", "fuzz_mesh_reader_vtu/square.vtu",
        "fuzz_mesh_reader_su2/square.su2", "fuzz_mesh_reader_medit/square.mesh"}) {
    INFO(msh);
    const pdmesh::Mesh m = pdmesh::read_mesh(corpus / msh);
    CHECK(m.points.size() == 5);
    CHECK(m.triangles.size() == 4);
    CHECK(m.boundary_edges.size() == 4);
    CHECK(m.curve_names.size() == 2);
  }
  const pdmesh::NodeFile nodes = pdmesh::read_node_file(corpus / "fuzz_node_file/square.nodes");
  CHECK(nodes.nodes.size() == 5);
  CHECK(nodes.curve_names == std::vector<std::string>{"bottom_right", "top_left"});
  const pdmesh::CaseConfig full = pdmesh::load_case_file(corpus / "fuzz_case_file/full.toml");
  CHECK(full.name == "naca0012");
  CHECK(full.geometry.curve_names.size() == 6);
  CHECK(full.simulation.precision == pdmesh::Precision::Float);
  CHECK(pdmesh::read_geometry({(corpus / "fuzz_poly_reader/square_with_hole.poly").string()}, {}).loops.size() == 2);
  CHECK(pdmesh::read_geometry({(corpus / "fuzz_curve_reader/unit_square.crv").string()}, {}).loops.size() == 1);
  // The checkpoint seeds fit the entry's case and continue from it (the fuzzer reaches the simulation).
  auto& world = pdmesh::fuzz::checkpoint_case();
  for (const char* seed : {"square_initial.pdmesh", "square_3_iterations.pdmesh"}) {
    INFO(seed);
    pdmesh::Checkpoint c = pdmesh::read_checkpoint(corpus / "fuzz_checkpoint" / seed);
    CHECK(c.nodes.size() > 8);
    CHECK(c.nodes.curve_nodes.size() == 2);
    CHECK_NOTHROW(pdmesh::check_checkpoint_fits(c, *world.tree, seed));
    const pdmesh::SimResult r =
        pdmesh::run_simulation(c.nodes, *world.tree, world.spacing, pdmesh::fuzz::continue_options(c));
    CHECK(r.history.size() == static_cast<std::size_t>(c.state.iterations_done) + 2);
  }
  CHECK(pdmesh::read_checkpoint(corpus / "fuzz_checkpoint/square_3_iterations.pdmesh").state.iterations_done == 3);
  // The Medit seeds: .mesh and .sol parts separated by a form feed.
  for (const char* seed : {"square", "square_edges_clockwise"}) {
    INFO(seed);
    const std::string text = bytes_of(corpus / "fuzz_metric_reader_medit" / seed);
    const std::size_t cut = text.find('\f');
    REQUIRE(cut != std::string::npos);
    const pdmesh::MetricMeshData d =
        pdmesh::parse_medit_metric("seed.mesh", text.substr(0, cut), "seed.sol", text.substr(cut + 1));
    CHECK(d.metrics.size() == d.points.size());
    CHECK_NOTHROW(pdmesh::make_mesh_metric_field(d));
  }
  CHECK_THROWS_AS(pdmesh::read_checkpoint(corpus / "fuzz_checkpoint/square_truncated.pdmesh"), pdmesh::InputError);
}

TEST_CASE("fuzz corpus: curve reader and read_geometry", "[fuzz][geometry]") {
  CHECK(replay("fuzz_curve_reader") >= 10);
}
TEST_CASE("fuzz corpus: poly reader and read_geometry", "[fuzz][geometry]") { CHECK(replay("fuzz_poly_reader") >= 5); }
TEST_CASE("fuzz corpus: case file", "[fuzz][app]") { CHECK(replay("fuzz_case_file") >= 3); }
TEST_CASE("fuzz corpus: node file", "[fuzz][nodes]") { CHECK(replay("fuzz_node_file") >= 1); }
TEST_CASE("fuzz corpus: Gmsh reader", "[fuzz][io]") { CHECK(replay("fuzz_mesh_reader_msh") >= 2); }
TEST_CASE("fuzz corpus: VTU reader", "[fuzz][io]") { CHECK(replay("fuzz_mesh_reader_vtu") >= 1); }
TEST_CASE("fuzz corpus: SU2 reader", "[fuzz][io]") { CHECK(replay("fuzz_mesh_reader_su2") >= 1); }
TEST_CASE("fuzz corpus: Medit reader", "[fuzz][io]") { CHECK(replay("fuzz_mesh_reader_medit") >= 2); }
TEST_CASE("fuzz corpus: Triangle reader", "[fuzz][io]") { CHECK(replay("fuzz_mesh_reader_triangle") >= 2); }
TEST_CASE("fuzz corpus: Medit metric reader", "[fuzz][io]") { CHECK(replay("fuzz_metric_reader_medit") >= 2); }
TEST_CASE("fuzz corpus: checkpoint reader, fit check and resumed simulation", "[fuzz][resume]") {
  CHECK(replay("fuzz_checkpoint") >= 3);
}
