// Mesh writers and readers: every format written and read back (same points bit for bit, same
// triangles, boundary edges and curve names), plus the readers' errors and skipped elements.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "core/errors.hpp"
#include "io/fort14_writer.hpp"
#include "io/mesh_formats.hpp"
#include "io/msh_reader.hpp"
#include "io/msh_writer.hpp"
#include "io/su2_reader.hpp"
#include "io/sms2dm_writer.hpp"
#include "io/su2_writer.hpp"
#include "io/text_file.hpp"
#include "io/triangle_reader.hpp"
#include "io/vtu_data.hpp"
#include "io/vtu_reader.hpp"
#include "io/vtu_writer.hpp"
#include "mesh_fixtures.hpp"
#include "nodes/node_file.hpp"
#include "temp_files.hpp"
#include "seeded_random.hpp"

using namespace pdmesh;

namespace {

using pdmesh_test::unit;

// A 5 x 4 grid of the rectangle [0, 1.7] x [0, 0.9] with jittered interior points (coordinates
// that need all 17 digits), two triangles per cell, counter-clockwise, and the four sides as
// curves. One edge of "bottom" is listed last so that writers must group edges by curve.
Mesh grid_mesh() {
  const int nx = 5, ny = 4;
  std::mt19937_64 rng(2024);
  Mesh m;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      Vec2 p{1.7 * i / (nx - 1), 0.9 * j / (ny - 1)};
      const bool interior = i > 0 && i < nx - 1 && j > 0 && j < ny - 1;
      if (interior) p = p + Vec2{0.1 * (unit(rng) - 0.5), 0.05 * (unit(rng) - 0.5)};
      m.points.push_back(p);
      const bool corner = (i == 0 || i == nx - 1) && (j == 0 || j == ny - 1);
      m.kind.push_back(corner ? NodeKind::Fixed : interior ? NodeKind::Interior : NodeKind::Boundary);
    }
  }
  const auto id = [&](int i, int j) { return j * nx + i; };
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  m.curve_names = {"bottom", "right", "top", "left"};
  for (int i = 1; i + 1 < nx; ++i) m.boundary_edges.push_back({id(i, 0), id(i + 1, 0), 0});
  for (int j = 0; j + 1 < ny; ++j) m.boundary_edges.push_back({id(nx - 1, j), id(nx - 1, j + 1), 1});
  for (int i = nx - 1; i > 0; --i) m.boundary_edges.push_back({id(i, ny - 1), id(i - 1, ny - 1), 2});
  for (int j = ny - 1; j > 0; --j) m.boundary_edges.push_back({id(0, j), id(0, j - 1), 3});
  m.boundary_edges.push_back({id(0, 0), id(1, 0), 0});
  return m;
}

using pdmesh_test::fresh_dir;

// An n x n grid of the unit square with q at every point: large enough that each format's text is
// several of core/text_sink.hpp's 8 MB pieces.
Mesh big_grid_mesh(int n) {
  return fixtures::grid_mesh_of(n, [n](int i, int j, bool) { return Vec2{i / (n - 1.0) + 1e-9 * j, j / (n - 1.0)}; });
}

// Edges grouped by curve as the writers store them (stable within a curve).
std::vector<std::array<int, 3>> grouped_edges(const Mesh& m) {
  std::vector<std::array<int, 3>> e;
  for (const auto& b : m.boundary_edges) e.push_back({b.curve, b.a, b.b});
  std::stable_sort(e.begin(), e.end(), [](const auto& x, const auto& y) { return x[0] < y[0]; });
  return e;
}

void check_round_trip(const Mesh& in, const Mesh& out, bool keeps_kind) {
  REQUIRE(out.points.size() == in.points.size());
  for (std::size_t i = 0; i < in.points.size(); ++i) {
    INFO("point " << i);
    CHECK(out.points[i].x == in.points[i].x);  // bit for bit
    CHECK(out.points[i].y == in.points[i].y);
  }
  CHECK(out.triangles == in.triangles);
  CHECK(out.curve_names == in.curve_names);
  CHECK(grouped_edges(out) == grouped_edges(in));
  if (keeps_kind) {
    CHECK(out.kind == in.kind);
  } else {
    CHECK(out.kind.empty());
  }
}

bool message_has(const std::function<void()>& f, const std::string& text) {
  try {
    f();
  } catch (const InputError& e) {
    INFO(e.what());
    CHECK(std::string(e.what()).find(text) != std::string::npos);
    return std::string(e.what()).find(text) != std::string::npos;
  }
  FAIL("no InputError thrown, expected one mentioning " << text);
  return false;
}

const char* kMsh22 =
    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
    "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n"
    "$Elements\n5\n"
    "1 15 2 0 1 1\n"       // a point element: skipped
    "2 1 2 7 3 1 2\n"      // a line in physical group 7
    "3 3 2 0 1 1 2 3 4\n"  // a quadrangle: skipped
    "4 2 2 0 1 1 3 2\n"    // a clockwise triangle: reoriented
    "5 2 2 0 1 1 3 4\n"
    "$EndElements\n";

}  // namespace

TEST_CASE("every format reads back what it wrote", "[mesh_io]") {
  const Mesh mesh = grid_mesh();
  const auto dir = fresh_dir("round_trip");
  for (const std::string format : {"msh", "msh22", "vtu", "su2", "triangle"}) {
    INFO(format);
    const auto written = write_mesh(mesh, dir, "grid_" + format, {format});
    REQUIRE_FALSE(written.empty());
    MeshReadReport report;
    const Mesh back = read_mesh(format == "triangle" ? dir / ("grid_" + format + ".ele") : written.front(), report);
    CHECK(report.skipped_elements == 0);
    CHECK(report.reoriented_triangles == 0);
    check_round_trip(mesh, back, format == "vtu" || format == "triangle");
  }
  CHECK(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()) == 7);
  std::filesystem::remove_all(dir);
}

TEST_CASE("empty curves keep their names, and odd names are made writable", "[mesh_io]") {
  Mesh mesh = grid_mesh();
  mesh.curve_names.push_back("unused curve");
  mesh.curve_names.push_back("");
  MeshReadReport r;
  CHECK(parse_msh("a.msh", msh41_string(mesh), r).curve_names.back() == "curve5");
  CHECK(parse_msh("a.msh", msh22_string(mesh), r).curve_names[4] == "unused curve");
  CHECK(parse_vtu("a.vtu", vtu_string(mesh), r).curve_names[4] == "unused curve");
  CHECK(parse_su2("a.su2", su2_string(mesh), r).curve_names[4] == "unused_curve");
  mesh.curve_names[4] = "say \"hi\"";
  CHECK(parse_msh("a.msh", msh41_string(mesh), r).curve_names[4] == "say _hi_");
}

TEST_CASE("MSH 4.1 layout: format line, physical groups, entity blocks and counts", "[mesh_io]") {
  const Mesh mesh = grid_mesh();
  const std::string s = msh41_string(mesh);
  CHECK(s.rfind("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n", 0) == 0);
  CHECK(s.find("$PhysicalNames\n5\n1 1 \"bottom\"\n1 2 \"right\"\n1 3 \"top\"\n1 4 \"left\"\n2 5 \"domain\"\n") !=
        std::string::npos);
  CHECK(s.find("$Entities\n0 4 1 0\n") != std::string::npos);
  CHECK(s.find("$Nodes\n1 20 1 20\n2 1 0 20\n") != std::string::npos);
  // 4 curve blocks + 1 surface block; 14 lines + 24 triangles.
  CHECK(s.find("$Elements\n5 38 1 38\n1 1 1 4\n") != std::string::npos);
  CHECK(s.find("2 1 2 24\n") != std::string::npos);
  const std::string s22 = msh22_string(mesh);
  CHECK(s22.find("$Elements\n38\n1 1 2 1 1 ") != std::string::npos);
}

TEST_CASE("a file written by gmsh 4.8 is read (nodes in point, curve and surface blocks)", "[mesh_io]") {
  // gmsh 4.8.4: `gmsh sq.geo -2 -format msh41 -save_all -parametric` for the unit square with
  // Physical Curve("wall") = {1} and Physical Surface("fluid") = {1}, verbatim.
  const std::string gmsh_file =
      "$MeshFormat\n"
      "4.1 0 8\n"
      "$EndMeshFormat\n"
      "$PhysicalNames\n"
      "2\n"
      "1 1 \"wall\"\n"
      "2 2 \"fluid\"\n"
      "$EndPhysicalNames\n"
      "$Entities\n"
      "4 4 1 0\n"
      "1 0 0 0 0 \n"
      "2 1 0 0 0 \n"
      "3 1 1 0 0 \n"
      "4 0 1 0 0 \n"
      "1 0 0 0 1 0 0 1 1 2 1 -2 \n"
      "2 1 0 0 1 1 0 0 2 2 -3 \n"
      "3 0 1 0 1 1 0 0 2 3 -4 \n"
      "4 0 0 0 0 1 0 0 2 4 -1 \n"
      "1 0 0 0 1 1 0 1 2 4 1 2 3 4 \n"
      "$EndEntities\n"
      "$Nodes\n"
      "9 5 1 5\n"
      "0 1 0 1\n"
      "1\n"
      "0 0 0\n"
      "0 2 0 1\n"
      "2\n"
      "1 0 0\n"
      "0 3 0 1\n"
      "3\n"
      "1 1 0\n"
      "0 4 0 1\n"
      "4\n"
      "0 1 0\n"
      "1 1 1 0\n"
      "1 2 1 0\n"
      "1 3 1 0\n"
      "1 4 1 0\n"
      "2 1 1 1\n"
      "5\n"
      "0.5 0.5 0 0.5 0.5\n"
      "$EndNodes\n"
      "$Elements\n"
      "9 12 1 12\n"
      "0 1 15 1\n"
      "1 1 \n"
      "0 2 15 1\n"
      "2 2 \n"
      "0 3 15 1\n"
      "3 3 \n"
      "0 4 15 1\n"
      "4 4 \n"
      "1 1 1 1\n"
      "5 1 2 \n"
      "1 2 1 1\n"
      "6 2 3 \n"
      "1 3 1 1\n"
      "7 3 4 \n"
      "1 4 1 1\n"
      "8 4 1 \n"
      "2 1 2 4\n"
      "9 1 2 5 \n"
      "10 4 1 5 \n"
      "11 2 3 5 \n"
      "12 3 4 5 \n"
      "$EndElements\n";
  MeshReadReport r;
  const Mesh m = parse_msh("gmsh.msh", gmsh_file, r);
  REQUIRE(m.points.size() == 5);
  CHECK(m.points[1].x == 1.0);
  CHECK(m.points[1].y == 0.0);
  CHECK(m.points[4].x == 0.5);
  CHECK(m.triangles.size() == 4);
  CHECK(r.reoriented_triangles == 0);
  CHECK(m.curve_names == std::vector<std::string>{"wall", "entity2", "entity3", "entity4"});
  REQUIRE(m.boundary_edges.size() == 4);
  CHECK(m.boundary_edges[0].a == 0);
  CHECK(m.boundary_edges[0].b == 1);
  CHECK(m.boundary_edges[0].curve == 0);
  CHECK(m.boundary_edges[3].curve == 3);
  CHECK(r.skipped_elements == 4);  // the four point elements
}

TEST_CASE("MSH 2.2 reader skips unsupported elements with a count and reorients triangles", "[mesh_io]") {
  MeshReadReport r;
  const Mesh m = parse_msh("legacy.msh", kMsh22, r);
  CHECK(m.points.size() == 4);
  CHECK(m.triangles.size() == 2);
  CHECK(r.skipped_elements == 2);
  CHECK(r.reoriented_triangles == 1);
  CHECK(m.triangles[0] == std::array<int, 3>{0, 1, 2});
  CHECK(m.curve_names == std::vector<std::string>{"physical7"});
  REQUIRE(m.boundary_edges.size() == 1);
  CHECK(m.boundary_edges[0].curve == 0);
}

TEST_CASE("MSH readers name FILE:LINE for truncated files, bad counts and bad tags", "[mesh_io]") {
  MeshReadReport r;
  const std::string good = msh41_string(grid_mesh());
  message_has([&] { parse_msh("cut.msh", good.substr(0, good.size() / 2), r); }, "cut.msh:");
  message_has([&] { parse_msh("cut.msh", good.substr(0, good.size() / 2), r); }, "unexpected end of file");
  std::string bad = kMsh22;
  bad.replace(bad.find("$Nodes\n4\n"), 9, "$Nodes\n5\n");
  message_has([&] { parse_msh("count.msh", bad, r); }, "count.msh:10:");
  std::string tag = kMsh22;
  tag.replace(tag.find("5 2 2 0 1 1 3 4"), 15, "5 2 2 0 1 1 3 9");
  message_has([&] { parse_msh("tag.msh", tag, r); }, "tag.msh:17: element refers to unknown node tag 9");
  message_has([&] { parse_msh("bin.msh", "$MeshFormat\n4.1 1 8\n$EndMeshFormat\n", r); }, "bin.msh:2: binary");
  message_has([&] { parse_msh("old.msh", "$MeshFormat\n4.0 0 8\n$EndMeshFormat\n", r); }, "unsupported MSH version");
  message_has([&] { parse_msh("x.msh", "hello\n", r); }, "x.msh:1:");
}

TEST_CASE("SU2 reader skips other element types and checks indices", "[mesh_io]") {
  const std::string su2 =
      "% comment\nNDIME= 2\nNELEM= 2\n5 0 1 2 0\n9 0 1 2 3 1\nNPOIN= 4\n0 0 0\n1 0 1\n1 1 2\n0 1 3\n"
      "NMARK= 1\nMARKER_TAG= wall\nMARKER_ELEMS= 1\n3 0 1\n";
  MeshReadReport r;
  const Mesh m = parse_su2("a.su2", su2, r);
  CHECK(m.triangles.size() == 1);
  CHECK(r.skipped_elements == 1);
  CHECK(m.curve_names == std::vector<std::string>{"wall"});
  std::string bad = su2;
  bad.replace(bad.find("5 0 1 2 0"), 9, "5 0 1 7 0");
  message_has([&] { parse_su2("b.su2", bad, r); }, "b.su2:4: point index 7 outside 0..3");
  message_has([&] { parse_su2("c.su2", "NDIME= 3\n", r); }, "c.su2:1: only 2-D");
  message_has([&] { parse_su2("d.su2", su2.substr(0, su2.find("NPOIN= 4") + 14), r); }, "d.su2:");
}

TEST_CASE("Triangle reader checks indices and reads 0-based files without .poly", "[mesh_io]") {
  MeshReadReport r;
  const Mesh m =
      parse_triangle("a.node", "3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n", "a.ele", "1 3 0\n0 0 1 2\n", "a.poly", "", r);
  CHECK(m.triangles == std::vector<std::array<int, 3>>{{0, 1, 2}});
  CHECK(m.boundary_edges.empty());
  message_has(
      [&] { parse_triangle("a.node", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n", "a.ele", "1 3 0\n1 1 2 4\n", "", "", r); },
      "a.ele:2: point index 4 is out of range [1, 3]");
  message_has([&] { parse_triangle("a.node", "3 2 0 0\n1 0 0\n2 1 0\n", "a.ele", "0 3 0\n", "", "", r); },
              "a.node:1: point count 3 cannot fit in the 12 bytes left in the file");
}

TEST_CASE("VTU reader rejects damaged binary arrays and bad connectivity", "[mesh_io]") {
  MeshReadReport r;
  std::string v = vtu_string(grid_mesh(), VtuFormat::Ascii);
  // ASCII numbers declared binary: their digits decode as base64 into a nonsensical block header.
  std::string binary = v;
  binary.replace(binary.find("format=\"ascii\""), 14, "format=\"binary\"");
  message_has([&] { parse_vtu("b.vtu", binary, r); }, "b.vtu:5: DataArray 'boundary_edges': the header announces");
  std::string lz4 = v;
  lz4.replace(lz4.find("header_type="), 0, "compressor=\"vtkLZ4DataCompressor\" ");
  lz4.replace(lz4.find("format=\"ascii\""), 14, "format=\"binary\"");
  message_has([&] { parse_vtu("z.vtu", lz4, r); }, "z.vtu:5: compressor 'vtkLZ4DataCompressor' is not supported");
  std::string conn = v;
  const auto at = conn.find("Name=\"connectivity\" format=\"ascii\">\n") + 36;
  conn.replace(at, conn.find('\n', at) - at, "          0 1 99");
  message_has([&] { parse_vtu("c.vtu", conn, r); }, "connectivity holds index 99");
  CHECK(v.find("<DataArray type=\"Float64\" Name=\"condition_number\"") != std::string::npos);
  CHECK(v.find("<DataArray type=\"Int32\" Name=\"kind\"") != std::string::npos);
}

TEST_CASE("base64 encoder: RFC 4648's test vectors, and a round trip through the reader's decoder", "[mesh_io]") {
  const auto encode = [](const std::string& bytes, std::size_t chunk) {
    std::string out;
    Base64Encoder e(out);
    for (std::size_t i = 0; i < bytes.size(); i += chunk) e.put(bytes.data() + i, std::min(chunk, bytes.size() - i));
    e.finish();
    return out;
  };
  // RFC 4648, section 10.
  const std::pair<const char*, const char*> vectors[] = {{"", ""},
                                                         {"f", "Zg=="},
                                                         {"fo", "Zm8="},
                                                         {"foo", "Zm9v"},
                                                         {"foob", "Zm9vYg=="},
                                                         {"fooba", "Zm9vYmE="},
                                                         {"foobar", "Zm9vYmFy"}};
  for (const auto& [in, expected] : vectors) {
    CHECK(encode(in, 1) == expected);
    CHECK(encode(in, 7) == expected);
  }
  // Lengths about the encoder's 3072-byte buffer, put in pieces of several sizes.
  std::mt19937 rng(5);
  for (const std::size_t n : {3071u, 3072u, 3073u, 6145u, 10000u}) {
    std::string bytes(n, '\0');
    for (char& c : bytes) c = static_cast<char>(rng() & 0xff);
    for (const std::size_t chunk : {1u, 8u, 1000u, 4096u}) {
      INFO("n " << n << " chunk " << chunk);
      const std::string text = encode(bytes, chunk);
      CHECK(text.size() == (n + 2) / 3 * 4);
      VtuBytes decoder = VtuBytes::base64(text, "t");
      std::vector<unsigned char> back;
      decoder.read(n, back, "all");
      CHECK(std::string(back.begin(), back.end()) == bytes);
    }
  }
}

TEST_CASE("VTU binary and ASCII forms hold the same mesh, and binary is what write_mesh writes", "[mesh_io]") {
  Mesh mesh = grid_mesh();
  mesh.spacing.assign(mesh.points.size(), 0.0);
  for (std::size_t i = 0; i < mesh.points.size(); ++i) mesh.spacing[i] = 0.1 + std::sqrt(0.5 + mesh.points[i].x);
  const std::string binary = vtu_string(mesh);
  const std::string ascii = vtu_string(mesh, VtuFormat::Ascii);
  CHECK(binary.find("format=\"ascii\"") == std::string::npos);
  CHECK(ascii.find("format=\"binary\"") == std::string::npos);
  // 14 arrays: boundary_edges, curve_names, kind, q, 6 metrics, Points, connectivity, offsets, types.
  std::size_t arrays = 0;
  for (auto at = binary.find("format=\"binary\""); at != std::string::npos;
       at = binary.find("format=\"binary\"", at + 1))
    ++arrays;
  CHECK(arrays == 14);
  MeshReadReport r;
  MeshPointData qb, qa;
  qb.wanted = qa.wanted = "q";
  const Mesh from_binary = parse_vtu("b.vtu", binary, r, &qb);
  const Mesh from_ascii = parse_vtu("a.vtu", ascii, r, &qa);
  check_round_trip(mesh, from_binary, true);
  check_round_trip(mesh, from_ascii, true);
  REQUIRE(qb.array);
  REQUIRE(qa.array);
  CHECK(qb.array->values == mesh.spacing);  // bit for bit
  CHECK(qa.array->values == mesh.spacing);
  const auto dir = pdmesh_test::fresh_path("vtu_binary");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_mesh(mesh, dir, "m", {"vtu"});
  std::ifstream in(dir / "m.vtu", std::ios::binary);
  CHECK(std::string(std::istreambuf_iterator<char>(in), {}) == binary);
  std::filesystem::remove_all(dir);
}

TEST_CASE("each mesh format writes the files its extensions name, and no other", "[mesh_io]") {
  for (const std::string& format : mesh_format_names()) {
    INFO(format);
    const auto dir = fresh_dir("extensions_" + format);
    const auto written = write_mesh(grid_mesh(), dir, "m", {format});
    std::vector<std::filesystem::path> expected;
    for (const std::string& ext : mesh_format_extensions(format)) expected.push_back(dir / ("m" + ext));
    if (format == "openfoam") {
      // One directory, STEM_openfoam, holding the polyMesh files.
      REQUIRE(expected.size() == 1);
      const auto poly = expected.front() / "constant" / "polyMesh";
      CHECK(written == std::vector<std::filesystem::path>{poly / "points", poly / "faces", poly / "owner",
                                                          poly / "neighbour", poly / "boundary"});
      CHECK(pdmesh_test::entries(poly) == written.size());
      CHECK(written_names(dir, written) == std::vector<std::string>{"m_openfoam/"});
    } else {
      CHECK(written == expected);
      std::vector<std::string> names;
      for (const auto& p : expected) names.push_back(p.filename().string());
      CHECK(written_names(dir, written) == names);
    }
    CHECK(pdmesh_test::entries(dir) == expected.size());
    std::filesystem::remove_all(dir);
  }
  CHECK(mesh_format_extensions("fort14") == std::vector<std::string>{".14"});
  CHECK(mesh_format_files("triangle", "m") == std::vector<std::filesystem::path>{"m.node", "m.ele", "m.poly"});
  CHECK(mesh_format_files("openfoam", "m").front() == std::filesystem::path("m_openfoam/constant/polyMesh/points"));
  CHECK(mesh_format_is_read("msh"));
  CHECK_FALSE(mesh_format_is_read("openfoam"));
  CHECK_FALSE(mesh_format_is_read("fort14"));
  CHECK(mesh_format_files("cgns", "m") == std::vector<std::filesystem::path>{"m.cgns"});
  CHECK_FALSE(mesh_format_is_read("cgns"));
  CHECK_THROWS_AS(mesh_format_extensions("stl"), InputError);
}

TEST_CASE("format dispatch rejects unknown names and extensions", "[mesh_io]") {
  const auto dir = fresh_dir("dispatch");
  message_has([&] { write_mesh(grid_mesh(), dir, "g", {"stl"}); }, "unknown mesh format 'stl'");
  message_has([&] { write_mesh(grid_mesh(), dir, "g", {"msh", "msh22"}); }, "both write");
  message_has([&] { read_mesh(dir / "g.obj"); }, "unknown mesh file extension '.obj'");
  message_has([&] { read_mesh(dir / "missing.msh"); }, "missing.msh");
  CHECK(std::filesystem::is_empty(dir));
  std::filesystem::remove_all(dir);
}

TEST_CASE("mesh and node files written in pieces are their whole texts byte for byte", "[mesh_io]") {
  // 300 x 300 points: the .msh text is about 12 MB, the .vtu text about 20 MB.
  const Mesh m = big_grid_mesh(300);
  const auto dir = fresh_dir("pieces");
  const auto read = [&](const std::string& name) { return read_text_file(dir / name, InputKind::Mesh); };
  write_mesh(m, dir, "a", {"msh", "vtu", "su2", "fort14", "2dm"});
  const std::string msh = msh41_string(m);
  CHECK(msh.size() > 8u << 20);
  CHECK(read("a.msh") == msh);
  CHECK(read("a.vtu") == vtu_string(m));
  CHECK(read("a.su2") == su2_string(m));
  CHECK(read("a.14") == fort14_string(m, {}));
  CHECK(read("a.2dm") == sms2dm_string(m));
  write_mesh(m, dir, "b", {"msh22"});
  CHECK(read("b.msh") == msh22_string(m));
  NodeSet nodes;
  for (std::size_t i = 0; i < m.points.size(); ++i) nodes.add(m.points[i], m.spacing[i], NodeKind::Interior, -1);
  nodes.curve_nodes = {{0, 1, 2}};
  nodes.kind[0] = nodes.kind[1] = nodes.kind[2] = NodeKind::Boundary;
  nodes.curve[0] = nodes.curve[1] = nodes.curve[2] = 0;
  write_node_file(dir / "a.nodes", nodes, {"outline"});
  CHECK(read("a.nodes") == format_node_file(nodes, {"outline"}));
  // A failure while writing (a curve name the format cannot hold) leaves no file and no temporary.
  CHECK_THROWS_AS(write_node_file(dir / "c.nodes", nodes, {"has space"}), InputError);
  CHECK_FALSE(std::filesystem::exists(dir / "c.nodes"));
  CHECK(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator{}) == 7);
}
