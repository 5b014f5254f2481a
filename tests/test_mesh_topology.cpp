// `pdmesh quality` refuses a folded or non-manifold mesh, naming the triangles and the edge
// (mesh/mesh_topology.hpp); a mesh whose triangles are merely clockwise is turned and measured.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "mesh/mesh_topology.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;

namespace {

// MSH 2.2 with the given node and element lines.
std::string msh(const std::string& nodes, int node_count, const std::string& elements, int element_count) {
  return "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" + std::to_string(node_count) + "\n" + nodes +
         "$EndNodes\n$Elements\n" + std::to_string(element_count) + "\n" + elements + "$EndElements\n";
}

const std::string kFourNodes = "1 0 0 0\n2 1 0 0\n3 0 1 0\n4 1 1 0\n";

pdmesh::Mesh square(std::vector<std::array<int, 3>> triangles) {
  pdmesh::Mesh m;
  m.points = {{0, 0}, {1, 0}, {0, 1}, {1, 1}, {0.2, 0.2}};
  m.triangles = std::move(triangles);
  return m;
}

}  // namespace

TEST_CASE("find_fold_or_nonmanifold_edge names the folded pair and the shared edge", "[quality][topology]") {
  CHECK_FALSE(pdmesh::find_fold_or_nonmanifold_edge(square({{0, 1, 3}, {0, 3, 2}})).has_value());
  // Triangle 1 lies on triangle 0's side of the edge 1-2 (point 4 at (0.2, 0.2)).
  const auto fold = pdmesh::find_fold_or_nonmanifold_edge(square({{0, 1, 2}, {2, 4, 1}}));
  REQUIRE(fold.has_value());
  CHECK(*fold ==
        "triangle 0 (points 0, 1, 2) and triangle 1 (points 2, 4, 1) lie on the same side of the edge between "
        "points 1 (1, 0) and 2 (0, 1): one is folded over the other (a triangle inverted in the file, or "
        "overlapping triangles)");
  const auto three = pdmesh::find_fold_or_nonmanifold_edge(square({{0, 1, 2}, {1, 3, 2}, {1, 3, 2}, {0, 1, 3}}));
  REQUIRE(three.has_value());
  CHECK(three->find("belongs to more than two triangles") != std::string::npos);
}

TEST_CASE("pdmesh quality refuses a folded mesh with exit 2 naming the triangles", "[quality][topology][cli]") {
  const fs::path dir = pdmesh_test::fresh_dir("quality_fold");
  const auto folded = pdmesh_test::run_pdmesh(
      "quality '" PDMESH_SOURCE_DIR "/tests/data/bad/field_folded.msh' --json '" + (dir / "q.json").string() + "'");
  CHECK(folded.status == 2);
  CHECK(folded.output.find("pdmesh: error: ") != std::string::npos);
  CHECK(folded.output.find("field_folded.msh: triangle ") != std::string::npos);
  CHECK(folded.output.find("lie on the same side of the edge between points") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "q.json"));

  // Three triangles on the edge 2-3 (0-based 1-2).
  std::ofstream(dir / "three.msh") << msh(kFourNodes + "5 2 2 0\n", 5, "1 2 0 1 2 3\n2 2 0 2 4 3\n3 2 0 2 5 3\n", 3);
  const auto three = pdmesh_test::run_pdmesh("quality '" + (dir / "three.msh").string() + "'");
  CHECK(three.status == 2);
  CHECK(three.output.find("belongs to more than two triangles") != std::string::npos);

  // Clockwise triangles that do not fold are turned (with a note) and measured.
  std::ofstream(dir / "cw.msh") << msh(kFourNodes, 4, "1 2 0 1 3 2\n2 2 0 2 3 4\n", 2);
  const auto cw = pdmesh_test::run_pdmesh("quality '" + (dir / "cw.msh").string() + "'");
  CHECK(cw.status == 0);
  CHECK(cw.output.find("turned 2 clockwise triangles counter-clockwise") != std::string::npos);
  CHECK(cw.output.find("Number of Triangles") != std::string::npos);
}
