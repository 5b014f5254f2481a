// Metric data on a background mesh (io/metric_mesh_file, io/medit_reader): a .vtu and a .msh with a
// 3-component point array, and mmg's Medit .mesh + .sol pair, read to the metrics written, and every
// class of bad input refused with a message naming the file, the line or point, and the value.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "error_message.hpp"
#include "io/medit_reader.hpp"
#include "io/metric_mesh_file.hpp"
#include "spacing/metric.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
namespace fs = std::filesystem;
using pdmesh_test::error_message;

namespace {

fs::path write(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

// A 3 x 3 grid on [0, 1]², two counter-clockwise triangles per cell, and a stretched rotated metric
// at each point (exact in 17 digits).
struct Grid {
  std::vector<Vec2> points;
  std::vector<std::array<int, 3>> triangles;  // 0-based
  std::vector<Metric> metrics;
};
Grid grid() {
  Grid g;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      g.points.push_back({0.5 * i, 0.5 * j});
      g.metrics.push_back(metric_from_sizes(0.1, 0.01 + 0.02 * i + 0.005 * j, 0.3 * j));
    }
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int a = 3 * j + i, b = a + 1, c = a + 4, d = a + 3;
      g.triangles.push_back({a, b, c});
      g.triangles.push_back({a, c, d});
    }
  return g;
}

std::string g17(double v) { return fmt::format("{:.17g}", v); }

// `bad` replaces the metric of point 4 in the text when not empty.
std::string vtu_text(const Grid& g, const std::string& array, int components, const std::string& bad = "") {
  std::string s =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "<UnstructuredGrid>\n<Piece NumberOfPoints=\"9\" NumberOfCells=\"8\">\n<PointData>\n";
  s += fmt::format("<DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">\n", array,
                   components);
  for (std::size_t i = 0; i < g.points.size(); ++i) {
    const Metric& m = g.metrics[i];
    if (i == 4 && !bad.empty()) {
      s += bad + "\n";
    } else if (components == 3) {
      s += g17(m.m11) + " " + g17(m.m12) + " " + g17(m.m22) + "\n";
    } else {
      for (int c = 0; c < components; ++c) s += "1 ";
      s += "\n";
    }
  }
  s += "</DataArray>\n</PointData>\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (Vec2 p : g.points) s += g17(p.x) + " " + g17(p.y) + " 0\n";
  s += "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& t : g.triangles) s += fmt::format("{} {} {}\n", t[0], t[1], t[2]);
  s += "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n";
  for (int k = 1; k <= 8; ++k) s += fmt::format("{} ", 3 * k);
  s += "\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n5 5 5 5 5 5 5 5\n</DataArray>\n"
       "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  return s;
}

// MSH 2.2 with a $NodeData view "metric" of 3 components; `skip` leaves that node out of it.
std::string msh_text(const Grid& g, int skip = -1) {
  std::string s = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n9\n";
  for (std::size_t i = 0; i < g.points.size(); ++i)
    s += fmt::format("{} {} {} 0\n", i + 1, g17(g.points[i].x), g17(g.points[i].y));
  s += "$EndNodes\n$Elements\n8\n";
  for (std::size_t k = 0; k < g.triangles.size(); ++k)
    s += fmt::format("{} 2 2 1 1 {} {} {}\n", k + 1, g.triangles[k][0] + 1, g.triangles[k][1] + 1,
                     g.triangles[k][2] + 1);
  s += fmt::format("$EndElements\n$NodeData\n1\n\"metric\"\n1\n0.0\n3\n0\n3\n{}\n", skip >= 0 ? 8 : 9);
  for (std::size_t i = 0; i < g.points.size(); ++i) {
    if (static_cast<int>(i) == skip) continue;
    const Metric& m = g.metrics[i];
    s += fmt::format("{} {} {} {}\n", i + 1, g17(m.m11), g17(m.m12), g17(m.m22));
  }
  return s + "$EndNodeData\n";
}

// The Medit pair: a .mesh with a comment, Edges, Corners, one clockwise triangle and End; a .sol
// with the metrics. `sol_values` replaces the SolAtVertices records when not empty.
std::string medit_mesh(const Grid& g) {
  std::string s = "MeshVersionFormatted 2\n# written by the test\nDimension\n2\nVertices\n9\n";
  for (Vec2 p : g.points) s += g17(p.x) + " " + g17(p.y) + " 0\n";
  s += "Edges\n2\n1 2 1\n2 3 1\nCorners\n1\n1\nTriangles\n8\n";
  for (std::size_t k = 0; k < g.triangles.size(); ++k) {
    const auto& t = g.triangles[k];
    if (k == 3)
      s += fmt::format("{} {} {} 0\n", t[0] + 1, t[2] + 1, t[1] + 1);  // clockwise
    else
      s += fmt::format("{} {} {} 0\n", t[0] + 1, t[1] + 1, t[2] + 1);
  }
  return s + "End\n";
}
std::string medit_sol(const Grid& g, const std::string& header = "SolAtVertices\n9\n1 3\n", int bad_line = -1,
                      const std::string& bad = "") {
  std::string s = "MeshVersionFormatted 2\n\nDimension 2\n\n" + header;
  for (std::size_t i = 0; i < g.points.size(); ++i) {
    const Metric& m = g.metrics[i];
    s += static_cast<int>(i) == bad_line ? bad + "\n" : g17(m.m11) + " " + g17(m.m12) + " " + g17(m.m22) + "\n";
  }
  return s + "\nEnd\n";
}

void check_read(const MetricMeshData& d, const Grid& g) {
  REQUIRE(d.points.size() == 9);
  REQUIRE(d.metrics.size() == 9);
  REQUIRE(d.triangles.size() == 8);
  for (std::size_t i = 0; i < 9; ++i) {
    CHECK(d.points[i].x == g.points[i].x);
    CHECK(d.points[i].y == g.points[i].y);
    CHECK(d.metrics[i].m11 == g.metrics[i].m11);
    CHECK(d.metrics[i].m12 == g.metrics[i].m12);
    CHECK(d.metrics[i].m22 == g.metrics[i].m22);
  }
  // As a field: the corner metrics exactly at the corners, and between them the log-Euclidean mean.
  const auto field = make_mesh_metric_field(d);
  const Metric at4 = field->at(g.points[4]);
  CHECK(at4.m11 == Approx(g.metrics[4].m11).epsilon(1e-12));
  CHECK(at4.m22 == Approx(g.metrics[4].m22).epsilon(1e-12));
  const Metric mid = field->at({0.25, 0.0});
  const Metric want = interpolate(g.metrics[0], g.metrics[1], 0.5);
  CHECK(mid.m11 == Approx(want.m11).epsilon(1e-12));
  CHECK(mid.m12 == Approx(want.m12).margin(1e-9));
  CHECK(mid.m22 == Approx(want.m22).epsilon(1e-12));
}

}  // namespace

TEST_CASE("a .vtu and a .msh with a 3-component point array read to the metrics written", "[metric_readers]") {
  const fs::path dir = pdmesh_test::fresh_dir("metric_readers_ok");
  const Grid g = grid();
  check_read(load_metric_mesh(write(dir / "m.vtu", vtu_text(g, "metric", 3)), "metric"), g);
  check_read(load_metric_mesh(write(dir / "m.msh", msh_text(g)), "metric"), g);
}

TEST_CASE("bad metric data on a .vtu or .msh is refused naming the file, the point and the value", "[metric_readers]") {
  const fs::path dir = pdmesh_test::fresh_dir("metric_readers_bad");
  const Grid g = grid();
  auto error = [&](const std::string& name, const std::string& text, const std::string& array = "metric") {
    return error_message<InputError>([&] { load_metric_mesh(write(dir / name, text), array); });
  };
  // Not SPD: the array's file and line, the point, its coordinates and the three values.
  const std::string not_spd = error("a.vtu", vtu_text(g, "metric", 3, "1 2 1"));
  CHECK_THAT(not_spd, Catch::Contains("a.vtu:") && Catch::Contains("'metric' at point 4 (0.5, 0.5)") &&
                          Catch::Contains("(1, 2, 1) is not positive definite"));
  CHECK_THAT(error("neg.vtu", vtu_text(g, "metric", 3, "-1 0 1")),
             Catch::Contains("(-1, 0, 1) is not positive definite"));
  // NaN.
  CHECK_THAT(error("nan.vtu", vtu_text(g, "metric", 3, "nan 0 1")), Catch::Contains("nan.vtu:"));
  // Wrong number of components, and a missing array (listing those there are).
  CHECK_THAT(error("one.vtu", vtu_text(g, "metric", 1)),
             Catch::Contains("one.vtu:") && Catch::Contains("has 1 component; a metric needs 3"));
  CHECK_THAT(error("a.vtu", vtu_text(g, "metric", 3), "M"),
             Catch::Contains("no point-data array 'M'") && Catch::Contains("arrays are: metric"));
  // A node of a triangle without a value in the MSH view.
  CHECK_THAT(error("skip.msh", msh_text(g, 4)),
             Catch::Contains("skip.msh:") && Catch::Contains("no value for node 5 (0.5, 0.5)"));
  // Another extension.
  CHECK_THAT(error("m.txt", "x"), Catch::Contains("m.txt: a metric background mesh must be a .vtu or .msh file"));
}

TEST_CASE("a Medit .mesh + .sol pair reads to the metrics written, clockwise triangles turned", "[metric_readers]") {
  const fs::path dir = pdmesh_test::fresh_dir("metric_medit_ok");
  const Grid g = grid();
  const MetricMeshData d = load_medit_metric(write(dir / "m.mesh", medit_mesh(g)), write(dir / "m.sol", medit_sol(g)));
  check_read(d, g);
  CHECK(d.triangles[3] == g.triangles[3]);  // written clockwise, read counter-clockwise
  CHECK(d.what == (dir / "m.mesh").string() + " with " + (dir / "m.sol").string());
}

TEST_CASE("bad Medit input is refused naming the file, the line and the value", "[metric_readers]") {
  const Grid g = grid();
  const std::string mesh = medit_mesh(g);
  auto sol_error = [&](const std::string& sol) {
    return error_message<InputError>([&] { parse_medit_metric("m.mesh", mesh, "m.sol", sol); });
  };
  auto mesh_error = [&](const std::string& text) {
    return error_message<InputError>([&] { parse_medit_metric("m.mesh", text, "m.sol", medit_sol(g)); });
  };
  // Not SPD, on line 13 (the header takes lines 1-7, so vertex k is on line 7 + k).
  CHECK_THAT(sol_error(medit_sol(g, "SolAtVertices\n9\n1 3\n", 5, "1 0 -2")),
             Catch::Contains("m.sol:13: vertex 6 (1, 0.5)") && Catch::Contains("(1, 0, -2) is not positive definite"));
  // NaN and text where a number belongs.
  CHECK_THAT(sol_error(medit_sol(g, "SolAtVertices\n9\n1 3\n", 0, "nan 0 1")),
             Catch::Contains("m.sol:8: expected a finite number for m11 (got 'nan')"));
  CHECK_THAT(sol_error(medit_sol(g, "SolAtVertices\n9\n1 3\n", 8, "1 x 1")),
             Catch::Contains("m.sol:16: expected a finite number for m12 (got 'x')"));
  // Wrong counts: more or fewer values than vertices, a count larger than the file.
  CHECK_THAT(sol_error(medit_sol(g, "SolAtVertices\n8\n1 3\n")),
             Catch::Contains("m.sol:6: SolAtVertices has 8 values for the 9 vertices of m.mesh"));
  CHECK_THAT(sol_error(medit_sol(g, "SolAtVertices\n1000000\n1 3\n")),
             Catch::Contains("m.sol:6:") && Catch::Contains("cannot fit"));
  CHECK_THAT(sol_error("SolAtVertices\n9\n1 3\n1 0 1\n"), Catch::Contains("m.sol:") && Catch::Contains("cannot fit"));
  // Wrong type, several solutions, another dimension, no SolAtVertices.
  CHECK_THAT(sol_error(medit_sol(g, "SolAtVertices\n9\n1 1\n")),
             Catch::Contains("m.sol:7: solution type 1 is not a metric") && Catch::Contains("type 1 is a scalar size"));
  CHECK_THAT(sol_error(medit_sol(g, "SolAtVertices\n9\n2 3 1\n")),
             Catch::Contains("m.sol:7: pdmesh reads one solution per vertex"));
  CHECK_THAT(sol_error("MeshVersionFormatted 2\nDimension 3\n"),
             Catch::Contains("m.sol:2: pdmesh reads 2-D Medit files: Dimension must be 2 (got '3')"));
  CHECK_THAT(sol_error("MeshVersionFormatted 2\nDimension 2\nEnd\n"),
             Catch::Contains("m.sol:3: no SolAtVertices section"));
  CHECK_THAT(sol_error("SolAtTriangles\n8\n1 3\n"), Catch::Contains("m.sol:1: expected SolAtVertices"));
  // The mesh: an index out of range, an unknown keyword, no triangles, text for a coordinate.
  std::string bad_index = mesh;
  bad_index.replace(bad_index.find("Triangles\n8\n1 2 5"), 17, "Triangles\n8\n1 2 10");
  CHECK_THAT(mesh_error(bad_index), Catch::Contains("m.mesh:25: triangle vertex 10 is out of range [1, 9] (got '10')"));
  CHECK_THAT(mesh_error("MeshVersionFormatted 2\nDimension 2\nTetrahedra\n0\n"),
             Catch::Contains("m.mesh:3: unknown Medit keyword") && Catch::Contains("(got 'Tetrahedra')"));
  CHECK_THAT(mesh_error("Dimension 2\nVertices\n3\n0 0 0\n1 0 0\n0 1 0\nEnd\n"),
             Catch::Contains("m.mesh:") && Catch::Contains("no Triangles"));
  CHECK_THAT(mesh_error("Dimension 2\nVertices\n3\n0 0 0\n1 y 0\n0 1 0\n"),
             Catch::Contains("m.mesh:5: expected a finite number for a vertex y (got 'y')"));
  // Binary files and other extensions, and a missing file.
  const fs::path dir = pdmesh_test::fresh_dir("metric_medit_bad");
  write(dir / "m.mesh", mesh);
  write(dir / "m.sol", medit_sol(g));
  CHECK_THAT(error_message<InputError>([&] { load_medit_metric(dir / "m.meshb", dir / "m.sol"); }),
             Catch::Contains("m.meshb: binary Medit files (.meshb) are not read"));
  CHECK_THAT(error_message<InputError>([&] { load_medit_metric(dir / "m.mesh", dir / "m.txt"); }),
             Catch::Contains("m.txt: a Medit metric needs a .sol file"));
  CHECK_THAT(error_message<InputError>([&] { load_medit_metric(dir / "m.mesh", dir / "none.sol"); }),
             Catch::Contains("none.sol"));
  // A degenerate triangle is MeshMetricField's refusal, naming the files.
  std::string flat = mesh;
  flat.replace(flat.find("Triangles\n8\n1 2 5"), 17, "Triangles\n8\n1 2 3");
  CHECK_THAT(error_message<InputError>(
                 [&] { make_mesh_metric_field(parse_medit_metric("m.mesh", flat, "m.sol", medit_sol(g))); }),
             Catch::Contains("m.mesh with m.sol"));
}
