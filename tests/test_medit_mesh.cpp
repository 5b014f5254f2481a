// Medit .mesh as a mesh file (io/medit_reader.hpp, io/medit_writer.hpp): what pdmesh writes reads back
// to the same points, cells, curves and boundary edges, a layered mesh with its quads and its layer;
// the sections mmg2d writes are read; bad files exit 2 naming the file and the line, writing nothing.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <string>

#include "core/errors.hpp"
#include "error_message.hpp"
#include "init/warm_points.hpp"
#include "io/medit_reader.hpp"
#include "io/medit_writer.hpp"
#include "io/mesh_formats.hpp"
#include "io/mixed_mesh.hpp"
#include "io/text_file.hpp"
#include "mesh_fixtures.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;
using pdmesh_test::error_message;

namespace {

// A 5 x 5 grid on irrational coordinates (17 digits must carry them), its outline cut into three
// curves, one of them named with a blank, and a fourth curve without edges; the four corners fixed.
Mesh small_mesh() {
  Mesh m = fixtures::grid_mesh_of(5, [](int i, int j, bool) {
    return Vec2{std::sqrt(2.0) * i / 4.0, std::acos(-1.0) * j / 4.0};
  });
  m.curve_names = {"bottom wall", "right", "rest", "unused"};
  for (std::size_t e = 0; e < m.boundary_edges.size(); ++e) m.boundary_edges[e].curve = e < 4 ? 0 : e < 8 ? 1 : 2;
  for (const int corner : {0, 4, 20, 24}) m.kind[static_cast<std::size_t>(corner)] = NodeKind::Fixed;
  return m;
}

bool same_edges(const std::vector<BoundaryEdge>& a, const std::vector<BoundaryEdge>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k].a != b[k].a || a[k].b != b[k].b || a[k].curve != b[k].curve) return false;
  return true;
}

bool same_points(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k].x != b[k].x || a[k].y != b[k].y) return false;
  return true;
}

}  // namespace

TEST_CASE("a mesh written as Medit .mesh reads back to the same points, triangles, curves and edges", "[io][medit]") {
  const fs::path dir = pdmesh_test::fresh_dir("medit_round_trip");
  const Mesh m = small_mesh();
  const auto written = write_mesh(m, dir, "m", {"mesh"});
  REQUIRE(written == std::vector<fs::path>{dir / "m.mesh"});
  const std::string text = pdmesh_test::slurp(dir / "m.mesh");
  CHECK(text.rfind("MeshVersionFormatted 2\n", 0) == 0);
  CHECK(text.find("Dimension 2\n") != std::string::npos);
  CHECK(text.find("# ref 1: curve bottom wall\n# ref 2: curve right\n# ref 3: curve rest\n# ref 4: curve unused\n") !=
        std::string::npos);
  CHECK(text.find("Corners\n4\n1\n5\n21\n25\nEnd\n") != std::string::npos);
  CHECK(text.find("Edges\n16\n1 2 1\n") != std::string::npos);

  MeshReadReport report;
  const Mesh back = read_mesh(dir / "m.mesh", report);
  CHECK(same_points(back.points, m.points));
  CHECK(back.triangles == m.triangles);
  CHECK(back.curve_names == m.curve_names);
  CHECK(same_edges(back.boundary_edges, m.boundary_edges));
  CHECK(report.reoriented_triangles == 0);
  CHECK(report.skipped_elements == 0);
  // The Corners are the fixed nodes again, the edges' other vertices boundary nodes: written again,
  // the file has the same Corners.
  CHECK(back.kind == m.kind);
  CHECK(medit_string(back) == text);
  // The warm start (pdmesh mesh --start, init.file) takes its points.
  CHECK(same_points(read_warm_points(dir / "m.mesh"), m.points));
}

TEST_CASE("a layered mesh written as Medit .mesh reads back with its quads and its boundary layer",
          "[io][medit][layers]") {
  const fs::path dir = pdmesh_test::fresh_dir("medit_layers");
  // Two layer quads on a wall (curve 0) under a core of two triangles and one layer triangle.
  MixedMesh m;
  m.points = {{0, 0}, {1, 0}, {2, 0}, {0, 0.5}, {1, 0.5}, {2, 0.5}, {1, 1}, {3, 0}};
  m.cells = {{3, 4, 6, -1}, {4, 5, 6, -1}, {0, 1, 4, 3}, {1, 2, 5, 4}, {2, 7, 5, -1}};
  m.layer = {0, 0, 1, 1, 1};
  m.boundary_edges = {{0, 1, 0}, {1, 2, 0}, {2, 7, 0}, {7, 5, 1}, {5, 6, 1}, {6, 3, 1}, {3, 0, 1}};
  m.curve_names = {"wall", "far"};
  write_mixed_mesh(m, dir, "m", {"mesh"});
  const std::string text = pdmesh_test::slurp(dir / "m.mesh");
  CHECK(text.find("# ref 1: region boundary_layer\n") != std::string::npos);
  CHECK(text.find("Triangles\n3\n4 5 7 0\n5 6 7 0\n3 8 6 1\nQuadrilaterals\n2\n1 2 5 4 1\n2 3 6 5 1\n") !=
        std::string::npos);

  MeshReadReport report;
  SurfaceCells cells;
  cells.region = kLayerRegion;
  const Mesh back = read_mesh(dir / "m.mesh", report, &cells);
  CHECK(cells.region_found);
  const MixedMesh mixed = mixed_mesh_of(back, cells);
  CHECK(same_points(mixed.points, m.points));
  CHECK(mixed.cells ==
        std::vector<std::array<int, 4>>{{3, 4, 6, -1}, {4, 5, 6, -1}, {2, 7, 5, -1}, {0, 1, 4, 3}, {1, 2, 5, 4}});
  CHECK(mixed.layer == std::vector<std::uint8_t>{0, 0, 1, 1, 1});
  CHECK(mixed.curve_names == m.curve_names);
  CHECK(same_edges(mixed.boundary_edges, m.boundary_edges));
  // Without SurfaceCells (every caller but quality and Mesh.read) the quads are skipped with a note.
  MeshReadReport plain;
  CHECK(read_mesh(dir / "m.mesh", plain).triangles.size() == 3);
  CHECK(plain.skipped_elements == 2);
  REQUIRE(plain.notes.size() == 1);
  CHECK(plain.notes[0].find("skipped 2 quadrilaterals") != std::string::npos);
}

TEST_CASE("a Medit .mesh as mmg2d writes it: sections in its order, references without names, clockwise cells",
          "[io][medit]") {
  // mmg2d writes Corners and RequiredVertices before Edges, Ridges and RequiredEdges after them.
  const std::string text =
      "MeshVersionFormatted 2\n\n\nDimension 2\n \nVertices\n5\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n2 0 7\n"
      "Corners\n2\n1\n2\nRequiredVertices\n1\n5\nEdges\n4\n1 2 7\n2 5 3\n3 4 7\n4 1 7\nRidges\n1\n2\n"
      "RequiredEdges\n1\n1\nTriangles\n2\n1 3 2 0\n1 3 4 0\nQuadrilaterals\n1\n2 5 3 4 4\nEnd\n";
  MeshReadReport report;
  SurfaceCells cells;
  cells.region = kLayerRegion;
  const Mesh m = parse_medit_mesh("mmg.mesh", text, report, &cells);
  CHECK(m.points.size() == 5);
  CHECK(m.curve_names == std::vector<std::string>{"ref3", "ref7"});
  REQUIRE(m.boundary_edges.size() == 4);
  CHECK(m.boundary_edges[0].curve == 1);
  CHECK(m.boundary_edges[1].curve == 0);
  CHECK(m.boundary_edges[1].a == 1);
  CHECK(m.boundary_edges[1].b == 4);
  // The first triangle is clockwise in the file.
  CHECK(report.reoriented_triangles == 1);
  CHECK(m.triangles[0] == std::array<int, 3>{0, 1, 2});
  CHECK(m.triangles[1] == std::array<int, 3>{0, 2, 3});
  REQUIRE(cells.quads.size() == 1);
  CHECK_FALSE(cells.region_found);
  // Corners and RequiredVertices are fixed nodes, the edges' other vertices boundary nodes.
  using K = NodeKind;
  CHECK(m.kind == std::vector<NodeKind>{K::Fixed, K::Fixed, K::Boundary, K::Boundary, K::Fixed});
  // Without either section the kinds stay unknown.
  const std::string plain =
      "MeshVersionFormatted 2\nDimension 2\nVertices\n3\n0 0 0\n1 0 0\n0 1 0\n"
      "Edges\n1\n1 2 1\nTriangles\n1\n1 2 3 0\nEnd\n";
  CHECK(parse_medit_mesh("plain.mesh", plain, report).kind.empty());
}

TEST_CASE("Medit edges of reference 0 between two cells, as mmg2d writes a layer's top, are not curves",
          "[io][medit][layers]") {
  // A square of two triangles beside a quad; the edge 2-3 between them and the boundary edge 1-2 have
  // reference 0, the quad's far side 5-6 reference 3.
  const std::string text =
      "MeshVersionFormatted 2\nDimension 2\nVertices\n6\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n2 1 0\n"
      "Edges\n3\n2 3 0\n1 2 0\n5 6 3\nTriangles\n2\n1 2 3 0\n1 3 4 0\nQuadrilaterals\n1\n2 5 6 3 1\nEnd\n";
  for (const bool with_cells : {false, true}) {
    INFO(with_cells);
    MeshReadReport report;
    SurfaceCells cells;
    const Mesh m = parse_medit_mesh("mmg.mesh", text, report, with_cells ? &cells : nullptr);
    CHECK(m.curve_names == std::vector<std::string>{"ref0", "ref3"});
    REQUIRE(m.boundary_edges.size() == 2);
    CHECK(m.boundary_edges[0].a == 0);
    CHECK(m.boundary_edges[0].b == 1);
    CHECK(m.boundary_edges[1].curve == 1);
    REQUIRE_FALSE(report.notes.empty());
    CHECK(report.notes[0] == "mmg.mesh: 1 edges of reference 0 between two cells are not curves");
  }
}

TEST_CASE("a Medit .mesh of Dimension 3 with every vertex at z = 0, as Gmsh and meshio write a 2-D mesh, is read",
          "[io][medit]") {
  // Gmsh's layout: the keyword and its value on separate lines, blanks before them, x y z ref.
  const std::string text =
      " MeshVersionFormatted 2\n Dimension\n 3\n Vertices\n 4\n 0 0 0 1\n 1 0 0 2\n 1 1 0 3\n 0 1 0 4\n"
      " Edges\n 2\n 1 2 5\n 2 3 6\n Triangles\n 2\n 1 2 3 7\n 1 3 4 7\n End\n";
  MeshReadReport report;
  const Mesh m = parse_medit_mesh("gmsh.mesh", text, report);
  CHECK(m.points.size() == 4);
  CHECK(m.points[2].x == 1.0);
  CHECK(m.points[2].y == 1.0);
  CHECK(m.triangles.size() == 2);
  CHECK(m.curve_names == std::vector<std::string>{"ref5", "ref6"});
  CHECK(m.region == std::vector<double>{7, 7});
  // A metric background mesh stays 2-D: its .sol would hold 3-D tensors.
  CHECK_THAT(error_message<InputError>([&] { parse_medit_metric("m.mesh", text, "m.sol", "SolAtVertices\n"); }),
             Catch::Contains("m.mesh:3: pdmesh reads 2-D Medit files: Dimension must be 2 (got '3')"));
}

TEST_CASE("bad Medit .mesh files exit 2 naming the file and the line, and nothing is written", "[io][medit][cli]") {
  const fs::path dir = pdmesh_test::fresh_dir("medit_bad");
  const std::string head = "MeshVersionFormatted 2\nDimension 2\nVertices\n4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
  struct Bad {
    const char* name;
    std::string text;
    std::string expected;
  };
  const std::vector<Bad> bad = {
      {"binary.meshb", head, "binary.meshb: binary Medit files (.meshb) are not read; write the ASCII .mesh"},
      {"dim4.mesh", "MeshVersionFormatted 2\nDimension 4\n",
       "dim4.mesh:2: pdmesh reads 2-D Medit files: Dimension must be 2, or 3 with every vertex at z = 0 (got '4')"},
      {"dim3.mesh", "MeshVersionFormatted 2\nDimension 3\nVertices\n3\n0 0 0 0\n1 0 0.5 0\n0 1 0 0\n",
       "dim3.mesh:6: vertex 2 is off the plane z = 0: pdmesh reads planar meshes (got '0.5')"},
      {"index.mesh", head + "Triangles\n2\n1 2 3 0\n1 3 9 0\nEnd\n",
       "index.mesh:12: triangle vertex 9 is out of range [1, 4] (got '9')"},
      {"edge.mesh", head + "Edges\n1\n0 1 1\nTriangles\n1\n1 2 3 0\nEnd\n",
       "edge.mesh:11: edge vertex 0 is out of range [1, 4] (got '0')"},
      {"truncated.mesh", head + "Triangles\n2\n1 2 3 0\n1 3 4\n# the file was cut here\n",
       "truncated.mesh:13: unexpected end of file, expected a triangle reference"},
      {"cut.mesh", head + "Triangles\n2\n1 2 3 0\n",
       "cut.mesh:10: Triangles 2 cannot fit in the 8 bytes left in the file"},
      {"keyword.mesh", head + "Tetrahedra\n0\n", "keyword.mesh:9: unknown Medit keyword"},
  };
  for (const Bad& b : bad) {
    INFO(b.name);
    write_text_file(dir / b.name, b.text);
    const fs::path json = dir / "q.json";
    const auto r = pdmesh_test::run_pdmesh("quality '" + (dir / b.name).string() + "' --json '" + json.string() + "'");
    INFO(r.output);
    CHECK(r.status == 2);
    CHECK(r.output.rfind("pdmesh: error: ", 0) == 0);
    CHECK(r.output.find((dir / b.name).string()) != std::string::npos);
    CHECK(r.output.find(b.expected) != std::string::npos);
    CHECK_FALSE(fs::exists(json));
  }
  // The same refusal from Mesh.read's reader and from pdmesh smooth.
  CHECK_THAT(error_message<InputError>([&] { read_mesh(dir / "index.mesh"); }),
             Catch::Contains("index.mesh:12: triangle vertex 9 is out of range"));
  const fs::path out = dir / "smooth_out";
  const auto r = pdmesh_test::run_pdmesh("smooth '" + (dir / "dim3.mesh").string() +
                                         "' -g '" PDMESH_SOURCE_DIR "/cases/square200' --out '" + out.string() + "'");
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK(r.output.find("dim3.mesh:6: vertex 2 is off the plane z = 0") != std::string::npos);
  CHECK_FALSE(fs::exists(out));
  // A binary file gets the binary file's message from smooth and from a warm start too.
  for (const std::string& args : {"smooth '" + (dir / "binary.meshb").string() +
                                      "' -g '" PDMESH_SOURCE_DIR "/cases/square200' --out '" + out.string() + "'",
                                  std::string("mesh '" PDMESH_SOURCE_DIR "/cases/square200' --start '") +
                                      (dir / "binary.meshb").string() + "' --out '" + out.string() + "'"}) {
    const auto rb = pdmesh_test::run_pdmesh(args);
    INFO(rb.output);
    CHECK(rb.status == 2);
    CHECK(rb.output.find("binary.meshb: binary Medit files (.meshb) are not read") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
  }
}
