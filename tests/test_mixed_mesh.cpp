// Tests of the mixed-mesh writers (io/mixed_mesh.hpp): the files, written in pieces with their long
// sections formatted on the worker threads, are the texts of the *_string forms, also past a block of
// items; a format the mixed mesh cannot hold is refused before anything is written.
#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "io/mixed_mesh.hpp"
#include "io/vtu_reader.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;
using pdmesh_test::lines_of;

namespace {

// Two layer quads on a wall (curve 0) under a core of two triangles; the far side is curve 1.
MixedMesh small_mixed_mesh() {
  MixedMesh m;
  m.points = {{0, 0}, {1, 0}, {2, 0}, {0, 0.5}, {1, 0.5}, {2, 0.5}, {1, 1}};
  m.cells = {{3, 4, 6, -1}, {4, 5, 6, -1}, {0, 1, 4, 3}, {1, 2, 5, 4}};
  m.layer = {0, 0, 1, 1};
  m.boundary_edges = {{0, 1, 0}, {1, 2, 0}, {2, 5, 1}, {5, 6, 1}, {6, 3, 1}, {3, 0, 1}};
  m.curve_names = {"wall", "far"};
  return m;
}

// A strip of `n` layer quads over a wall, n + 1 columns of two points; its top edge is curve 1.
MixedMesh quad_strip(int n) {
  MixedMesh m;
  for (int i = 0; i <= n; ++i) m.points.push_back({static_cast<double>(i), 0.0});
  for (int i = 0; i <= n; ++i) m.points.push_back({static_cast<double>(i), 1.0});
  for (int i = 0; i < n; ++i) {
    m.cells.push_back({i, i + 1, n + 2 + i, n + 1 + i});
    m.layer.push_back(1);
    m.boundary_edges.push_back({i, i + 1, 0});
    m.boundary_edges.push_back({n + 2 + i, n + 1 + i, 1});
  }
  m.curve_names = {"wall", "top"};
  return m;
}

}  // namespace

TEST_CASE("the mixed-mesh SU2 text: the core's cells, then the layer's, the points, a marker per curve",
          "[io][layers]") {
  CHECK(mixed_su2_string(small_mixed_mesh()) ==
        "NDIME= 2\nNELEM= 4\n5 3 4 6 0\n5 4 5 6 1\n9 0 1 4 3 2\n9 1 2 5 4 3\nNPOIN= 7\n0 0 0\n1 0 1\n2 0 2\n0 0.5 3\n"
        "1 0.5 4\n2 0.5 5\n1 1 6\nNMARK= 2\nMARKER_TAG= wall\nMARKER_ELEMS= 2\n3 0 1\n3 1 2\nMARKER_TAG= far\n"
        "MARKER_ELEMS= 4\n3 2 5\n3 5 6\n3 6 3\n3 3 0\n");
}

TEST_CASE("the mixed-mesh writers keep the items' order across the blocks formatted apart", "[io][layers]") {
  // 10,000 quads: the cells and points run over several blocks of items (core/text_blocks.hpp).
  const int n = 10000;
  const MixedMesh m = quad_strip(n);
  const std::vector<std::string> su2 = lines_of(mixed_su2_string(m));
  REQUIRE(su2.size() > static_cast<std::size_t>(3 + n + 2 * (n + 1)));
  for (int k = 0; k < n; ++k)
    REQUIRE(su2[static_cast<std::size_t>(2 + k)] == fmt::format("9 {} {} {} {} {}", k, k + 1, n + 2 + k, n + 1 + k, k));
  REQUIRE(su2[static_cast<std::size_t>(2 + n)] == fmt::format("NPOIN= {}", 2 * (n + 1)));
  for (int i = 0; i < 2 * (n + 1); ++i)
    REQUIRE(su2[static_cast<std::size_t>(3 + n + i)] == fmt::format("{} {} {}", i % (n + 1), i > n ? 1 : 0, i));
  const std::vector<std::string> msh = lines_of(mixed_msh41_string(m));
  const auto quads = std::find(msh.begin(), msh.end(), fmt::format("2 2 3 {}", n));
  REQUIRE(quads != msh.end());
  for (int k = 0; k < n; ++k)  // tags after the 2n boundary lines
    REQUIRE(*(quads + 1 + k) == fmt::format("{} {} {} {} {}", 2 * n + 1 + k, k + 1, k + 2, n + 3 + k, n + 2 + k));
  const std::vector<std::string> vtu = lines_of(mixed_vtu_string(m));
  const auto offsets =
      std::find(vtu.begin(), vtu.end(), "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">");
  REQUIRE(offsets != vtu.end());
  for (int k = 0; k < n; ++k) REQUIRE(*(offsets + 1 + k) == std::to_string(4 * (k + 1)));
}

TEST_CASE("the mixed-mesh files are each format's text", "[io][layers]") {
  const fs::path dir = pdmesh_test::fresh_dir("mixed_writers");
  const MixedMesh m = small_mixed_mesh();
  const std::vector<fs::path> written = write_mixed_mesh(m, dir, "mesh", {"su2", "msh", "vtu", "msh"});
  REQUIRE(written == std::vector<fs::path>{dir / "mesh.su2", dir / "mesh.msh", dir / "mesh.vtu", dir / "mesh.msh"});
  CHECK(pdmesh_test::slurp(dir / "mesh.msh") == mixed_msh41_string(m));
  CHECK(pdmesh_test::slurp(dir / "mesh.vtu") == mixed_vtu_string(m));
  CHECK(pdmesh_test::slurp(dir / "mesh.su2") == mixed_su2_string(m));
  CHECK(pdmesh_test::entries(dir) == 3);  // no temporaries left beside them
}

TEST_CASE("the mixed-mesh .vtu carries the curves: read back, its boundary edges and names are the mesh's",
          "[io][layers]") {
  const MixedMesh m = small_mixed_mesh();
  MeshReadReport report;
  SurfaceCells cells;
  const Mesh back = parse_vtu("mesh.vtu", mixed_vtu_string(m), report, nullptr, &cells);
  CHECK(back.curve_names == m.curve_names);
  REQUIRE(back.boundary_edges.size() == m.boundary_edges.size());
  for (std::size_t k = 0; k < m.boundary_edges.size(); ++k) {
    CHECK(back.boundary_edges[k].a == m.boundary_edges[k].a);
    CHECK(back.boundary_edges[k].b == m.boundary_edges[k].b);
    CHECK(back.boundary_edges[k].curve == m.boundary_edges[k].curve);
  }
  CHECK(back.triangles.size() == 2);
  CHECK(cells.quads.size() == 2);
}

TEST_CASE("a format the mixed mesh cannot hold is refused before any file is written", "[io][layers]") {
  const fs::path dir = pdmesh_test::fresh_dir("mixed_writers_refused");
  CHECK_THROWS_AS(write_mixed_mesh(small_mixed_mesh(), dir, "mesh", {"msh", "vtu", "msh22"}), InputError);
  CHECK(pdmesh_test::entries(dir) == 0);
}
