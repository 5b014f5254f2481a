// Counts read from a file are checked against the bytes left before anything is allocated by them;
// a checkpoint ends at `end`; a case's name is bounded (docs/robustness.md, "Input files").
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "app/config/case_file.hpp"
#include "core/errors.hpp"
#include "geometry/poly_reader.hpp"
#include "io/mesh_formats.hpp"
#include "nodes/node_file.hpp"
#include "sim/checkpoint.hpp"
#include "io/spacing_mesh_file.hpp"
#include "spacing/mesh_spacing.hpp"
#include "error_message.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using pdmesh::InputError;

namespace {

fs::path write(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
  return p;
}

const std::string kCheckpointHead =
    "pdmesh-checkpoint 2\niterations_done 0\ndt_initial 1p-7\ntime_step 1p-7 none 0 0\npopulation 0 0 0 0\n";

}  // namespace

TEST_CASE("a checkpoint's node count must fit in the file before it is allocated", "[input][counts]") {
  const std::string m = pdmesh_test::error_message<InputError>(
      [] { pdmesh::parse_checkpoint(kCheckpointHead + "nodes 400000000\n1 0 0 0 0 0 0\n", "c.pdmesh"); });
  CHECK(m ==
        "c.pdmesh:6: node count 400000000 cannot fit in the 14 bytes left in the file (each needs at least 14): "
        "the count is wrong or the file is truncated");
  // A count that fits the file still reads (the last line may lack its line break).
  const std::string one = kCheckpointHead + "nodes 1\n0 0 1p+0 0 0 0 0\ncurves 1\ncurve 0 1 0:0p+0\nhistory 0\nend";
  CHECK(pdmesh::parse_checkpoint(one, "c.pdmesh").nodes.size() == 1);
  CHECK(pdmesh_test::error_message<InputError>([] {
          pdmesh::parse_checkpoint(kCheckpointHead + "nodes 0\ncurves 999999\n", "c.pdmesh");
        }).find("c.pdmesh:7: curve count 999999 cannot fit") == 0);
}

TEST_CASE("bytes after 'end' in a checkpoint are refused, trailing blank lines are not", "[input][checkpoint]") {
  const std::string seed =
      pdmesh_test::slurp(PDMESH_SOURCE_DIR "/tests/fuzz/corpus/fuzz_checkpoint/square_3_iterations.pdmesh");
  REQUIRE(seed.size() > 100);
  CHECK_NOTHROW(pdmesh::parse_checkpoint(seed + "\n  \n", "c.pdmesh"));
  const std::string m =
      pdmesh_test::error_message<InputError>([&] { pdmesh::parse_checkpoint(seed + seed, "c.pdmesh"); });
  CHECK(m.find("unexpected content after 'end' (got 'pdmesh-checkpoint") != std::string::npos);
  CHECK(pdmesh_test::error_message<InputError>([&] {
          pdmesh::parse_checkpoint(seed + "x", "c.pdmesh");
        }).find("after 'end'") != std::string::npos);
}

TEST_CASE("a node file's node count must fit in the file", "[input][counts]") {
  const std::string m = pdmesh_test::error_message<InputError>(
      [] { pdmesh::parse_node_file("# pdmesh nodes v1\n400000000\n0 0 fixed 0 0\n", "n.nodes"); });
  CHECK(m ==
        "n.nodes:2: node count 400000000 cannot fit in the 14 bytes left in the file (each needs at least 14): the "
        "count is wrong or the file is truncated");
}

TEST_CASE("mesh readers check their counts against the file before allocating", "[input][counts]") {
  const fs::path dir = pdmesh_test::fresh_dir("reader_counts");
  const auto read = [&](const std::string& name, const std::string& text) {
    return pdmesh_test::error_message<InputError>([&] { pdmesh::read_mesh(write(dir / name, text)); });
  };
  // MSH 4.1: a node block of 10^12 nodes (its tags were allocated by that count).
  const std::string msh = read("a.msh",
                               "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1000000000000 1 1000000000000\n"
                               "2 1 0 1000000000000\n1\n0 0 0\n$EndNodes\n");
  CHECK(msh.find("a.msh:5: number of nodes 1000000000000 cannot fit in the") != std::string::npos);
  CHECK(read("b.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Elements\n99999999999\n")
            .find("b.msh:5: number of elements 99999999999 cannot fit") != std::string::npos);
  CHECK(read("a.su2", "NDIME= 2\nNPOIN= 99999999999\n0 0\n").find("a.su2:2: point count 99999999999 cannot fit") !=
        std::string::npos);
  CHECK(
      read("a.su2", "NDIME= 2\nNELEM= 99999999999\n5 0 1 2\n").find("a.su2:2: element count 99999999999 cannot fit") !=
      std::string::npos);
  write(dir / "a.node", "99999999999 2 0 0\n1 0 0\n");
  write(dir / "a.ele", "1 3 0\n1 1 1 1\n");
  CHECK(read("a.ele", "1 3 0\n1 1 1 1\n").find("a.node:1: point count 99999999999 cannot fit") != std::string::npos);
  CHECK(read("a.vtu",
             "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid><Piece NumberOfPoints=\"99999999999999\" "
             "NumberOfCells=\"0\">")
            .find("a.vtu:1: <Piece> with 99999999999999 points or cells: more than 2147483647") != std::string::npos);
  // A .poly's counts against the lines left.
  write(dir / "a.poly", "99999999 2 0 0\n1 0 0\n2 1 0\n");
  CHECK(pdmesh_test::error_message<InputError>([&] {
          pdmesh::read_poly_file((dir / "a.poly").string());
        }).find("a.poly:1: vertex count 99999999 is more than the 2 lines left in the file") != std::string::npos);
}

TEST_CASE("an MSH data view's component count is bounded before the values are allocated", "[input][counts]") {
  const fs::path dir = pdmesh_test::fresh_dir("reader_components");
  // 10^9 components and no values: the array for every point would have been allocated by it.
  write(dir / "q.msh",
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n"
        "$Elements\n1\n1 2 0 1 2 3\n$EndElements\n"
        "$NodeData\n1\n\"q\"\n1\n0.0\n3\n0\n1000000000\n0\n$EndNodeData\n");
  const std::string m = pdmesh_test::error_message<InputError>([&] { pdmesh::load_mesh_spacing(dir / "q.msh", "q"); });
  CHECK(m.find("q.msh:") != std::string::npos);
  CHECK(m.find("components must be 1 to 9") != std::string::npos);
}

TEST_CASE("a case's name is bounded and holds no control characters, and a large case file is refused",
          "[input][case]") {
  const fs::path dir = pdmesh_test::fresh_dir("case_name");
  write(dir / "a.crv", "5\n0 0\n1 0\n1 1\n0 1\n0 0\n");
  const auto load = [&](const std::string& name) {
    return pdmesh_test::error_message<InputError>([&] {
      pdmesh::load_case_file(write(dir / "case.toml", "name = \"" + name + "\"\n[geometry]\nfiles = [\"a.crv\"]\n"));
    });
  };
  CHECK(load(std::string(200, 'n')).empty());
  const std::string m = load(std::string(300, 'n'));
  CHECK(m.find("name has 300 bytes, more than 200 (got '" + std::string(100, 'n') + "... (300 bytes)')") !=
        std::string::npos);
  CHECK(load("a\\u0007b").find("name holds a control character (got 'a\\x07b')") != std::string::npos);
  // A 50 MB name: refused by the file's size, without echoing it.
  const std::string big = pdmesh_test::error_message<InputError>(
      [&] { pdmesh::load_case_file(write(dir / "big.toml", "name = \"" + std::string(50'000'000, 'n') + "\"\n")); });
  CHECK(big.find("it has 50000010 bytes, more than the 1 MiB a case file may have") != std::string::npos);
  CHECK(big.size() < 300);
}
