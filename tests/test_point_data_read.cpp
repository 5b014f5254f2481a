// Point arrays read with a mesh (MeshPointData::decode, decode_all): every array asked for in the one
// pass that reads a .vtu (its encodings) or .msh (2.2 and 4.1, the last block of a view), bit for bit;
// malformed arrays named with file, line and value; solution transfer from one read; the .msh writer's
// point-data views (MeshWriteOptions::msh_point_data) read back.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/pipeline/solution_transfer.hpp"
#include "core/errors.hpp"
#include "core/g17.hpp"
#include "io/mesh_formats.hpp"
#include "io/msh_reader.hpp"
#include "io/msh_writer.hpp"
#include "io/vtu_reader.hpp"
#include "io/vtu_writer.hpp"
#include "mesh/transfer.hpp"
#include "mesh_fixtures.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
using Catch::Matchers::Contains;

namespace {

// A 6 x 6 grid of the unit square, interior points moved off the lattice, with q and two point
// arrays whose values need all 17 digits: "u" (one component) and "w" (two).
Mesh mesh_with_data() {
  Mesh m = fixtures::grid_mesh_of(6, [](int i, int j, bool side) {
    const double jitter = side ? 0.0 : 0.03 * std::sin(7.0 * i + 3.0 * j);
    return Vec2{i / 5.0 + jitter, j / 5.0 - jitter};
  });
  PointValues u{"u", 1, {}, false}, w{"w", 2, {}, false};
  for (const Vec2& p : m.points) {
    u.values.push_back(std::sin(3.0 * p.x) * std::exp(p.y) / 3.0);
    w.values.push_back(p.x / 7.0);
    w.values.push_back(-p.y * M_PI);
  }
  m.point_data = {u, w};
  return m;
}

// A $NodeData view (node tag = point index + 1) of `values` with `components` per point.
std::string node_data(const std::string& name, double time, int components, const std::vector<double>& values) {
  std::string s = fmt::format("$NodeData\n1\n\"{}\"\n1\n{}\n3\n0\n{}\n{}\n", name, time, components,
                              values.size() / static_cast<std::size_t>(components));
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i % static_cast<std::size_t>(components) == 0) s += fmt::format("{}", i / components + 1);
    s += ' ';
    append_g17(s, values[i]);
    if ((i + 1) % static_cast<std::size_t>(components) == 0) s += '\n';
  }
  return s + "$EndNodeData\n";
}

const PointDataArray& array_named(const MeshPointData& d, const std::string& name) {
  for (const PointDataArray& a : d.arrays)
    if (a.name == name) return a;
  FAIL("no array " << name);
  return d.arrays.front();
}

std::vector<std::string> names_of(const MeshPointData& d) {
  std::vector<std::string> out;
  for (const PointDataArray& a : d.arrays) out.push_back(a.name);
  return out;
}

}  // namespace

TEST_CASE("a .vtu's point arrays, every one or those named, bit for bit in both forms", "[point_data]") {
  const Mesh mesh = mesh_with_data();
  for (const VtuFormat format : {VtuFormat::Binary, VtuFormat::Ascii}) {
    const std::string text = vtu_string(mesh, format);
    MeshReadReport report;
    MeshPointData all;
    all.decode_all = true;
    (void)parse_vtu("m.vtu", text, report, &all);
    CHECK(names_of(all) == std::vector<std::string>{"kind", "q", "u", "w"});
    CHECK(array_named(all, "q").values == mesh.spacing);
    CHECK(array_named(all, "u").components == 1);
    CHECK(array_named(all, "u").values == mesh.point_data[0].values);
    CHECK(array_named(all, "w").components == 2);
    CHECK(array_named(all, "w").values == mesh.point_data[1].values);
    CHECK_THAT(array_named(all, "w").where, Contains("m.vtu:"));

    MeshPointData some;
    some.decode = {"w", "missing"};
    (void)parse_vtu("m.vtu", text, report, &some);
    CHECK(names_of(some) == std::vector<std::string>{"w"});
    CHECK(some.point_arrays == std::vector<std::string>{"kind", "q", "u", "w"});
    CHECK_FALSE(some.array);
  }
}

TEST_CASE("a .vtu's integer point arrays are read as integers, its float arrays as floats", "[point_data]") {
  Mesh mesh = mesh_with_data();
  PointValues marker{"marker", 1, {}, true};
  for (std::size_t i = 0; i < mesh.points.size(); ++i) marker.values.push_back(static_cast<double>(i % 5) - 2.0);
  mesh.point_data.push_back(marker);
  for (const VtuFormat format : {VtuFormat::Binary, VtuFormat::Ascii}) {
    MeshReadReport report;
    MeshPointData all;
    all.decode_all = true;
    (void)parse_vtu("m.vtu", vtu_string(mesh, format), report, &all);
    CHECK(array_named(all, "marker").integer);
    CHECK(array_named(all, "marker").values == marker.values);
    CHECK(array_named(all, "kind").integer);
    CHECK_FALSE(array_named(all, "u").integer);
    CHECK_FALSE(array_named(all, "q").integer);
  }
}

TEST_CASE("an .msh's $NodeData views: several components, the last time step of a name", "[point_data]") {
  const Mesh mesh = mesh_with_data();
  std::vector<double> old_u = mesh.point_data[0].values;
  for (double& v : old_u) v += 5.0;
  const std::string views = node_data("u", 0.0, 1, old_u) + node_data("w", 0.0, 2, mesh.point_data[1].values) +
                            node_data("u", 1.0, 1, mesh.point_data[0].values);
  for (const bool v41 : {true, false}) {
    const std::string text = (v41 ? msh41_string(mesh) : msh22_string(mesh)) + views;
    MeshReadReport report;
    MeshPointData all;
    all.decode_all = true;
    const Mesh read = parse_msh("m.msh", text, report, &all);
    REQUIRE(read.points.size() == mesh.points.size());
    CHECK(names_of(all) == std::vector<std::string>{"q", "u", "w"});
    CHECK(array_named(all, "q").values == mesh.spacing);
    CHECK(array_named(all, "u").values == mesh.point_data[0].values);  // the second block of "u"
    CHECK(array_named(all, "u").given.empty());
    CHECK(array_named(all, "w").components == 2);
    CHECK(array_named(all, "w").values == mesh.point_data[1].values);
    // The single wanted array and a named list read the same values in the same pass.
    MeshPointData both;
    both.wanted = "u";
    both.decode = {"w"};
    (void)parse_msh("m.msh", text, report, &both);
    REQUIRE(both.array);
    CHECK(both.array->values == mesh.point_data[0].values);
    CHECK(names_of(both) == std::vector<std::string>{"w"});
  }
}

TEST_CASE("read_mesh hands point data on from .msh and .vtu files, none from the others", "[point_data]") {
  const Mesh mesh = mesh_with_data();
  const auto dir = pdmesh_test::fresh_path("point_data_read");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_mesh(mesh, dir, "m", {"vtu", "su2"});
  for (const char* name : {"m.vtu", "m.su2"}) {
    MeshReadReport report;
    MeshPointData data;
    data.decode_all = true;
    const Mesh read = read_mesh(dir / name, report, nullptr, &data);
    CHECK(read.points == mesh.points);
    if (std::string(name) == "m.vtu") {
      CHECK(names_of(data) == std::vector<std::string>{"kind", "q", "u", "w"});
    } else {
      CHECK(data.arrays.empty());
    }
  }
}

TEST_CASE("a malformed point array names the file, the line or array, and the value", "[point_data]") {
  const Mesh mesh = mesh_with_data();
  const std::string msh = msh41_string(mesh);
  const int lines = static_cast<int>(std::count(msh.begin(), msh.end(), '\n'));
  MeshReadReport report;
  MeshPointData all;
  all.decode_all = true;
  // A bad number: the view, the line and the token.
  const std::string bad = msh + "$NodeData\n1\n\"u\"\n1\n0\n3\n0\n1\n2\n1 0.5\n2 0.5x\n$EndNodeData\n";
  CHECK_THROWS_WITH(parse_msh("m.msh", bad, report, &all),
                    Contains(fmt::format("m.msh:{}:", lines + 11)) && Contains("$NodeData 'u'") && Contains("'0.5x'"));
  // Fewer values than the view says: the end marker where a node tag should be.
  const std::string short_view = msh + "$NodeData\n1\n\"u\"\n1\n0\n3\n0\n1\n3\n1 0.5\n2 0.5\n$EndNodeData\n";
  CHECK_THROWS_WITH(parse_msh("m.msh", short_view, report, &all),
                    Contains(fmt::format("m.msh:{}:", lines + 12)) && Contains("'$EndNodeData'"));
  // Without point data asked for, the views are skipped unread, as before.
  CHECK_NOTHROW(parse_msh("m.msh", bad, report));

  // A .vtu array one value short: its name, its line and the counts.
  std::string vtu = vtu_string(mesh, VtuFormat::Ascii);
  const auto at = vtu.find("Name=\"w\"");
  REQUIRE(at != std::string::npos);
  const auto first = vtu.find('\n', at) + 1;
  vtu.erase(vtu.find_first_not_of(' ', first),
            vtu.find(' ', vtu.find_first_not_of(' ', first)) - vtu.find_first_not_of(' ', first) + 1);
  CHECK_THROWS_WITH(parse_vtu("m.vtu", vtu, report, &all),
                    Contains("m.vtu:") && Contains("'w' holds 71 values, expected 2 components x 36 points"));
}

TEST_CASE("transfer_point_arrays moves every named array from one read, as one array at a time", "[point_data]") {
  const Mesh mesh = mesh_with_data();
  const auto dir = pdmesh_test::fresh_path("point_data_transfer");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_mesh(mesh, dir, "m", {"vtu"});
  const std::string from = (dir / "m.vtu").string();
  Mesh target;
  for (double x = 0.05; x < 1.0; x += 0.13)
    for (double y = 0.02; y < 1.0; y += 0.17) target.points.push_back({x, y});
  TransferCounts counts;
  const TransferredArrays moved = transfer_point_arrays(from, {"w", "u"}, target, counts);
  CHECK(moved.names == std::vector<std::string>{"w", "u"});
  CHECK(moved.source_points == mesh.points.size());
  REQUIRE(target.point_data.size() == 2);
  // The values transfer_point_values gives from the mesh in memory.
  CHECK(target.point_data[0].values == transfer_point_values(mesh, mesh.point_data[1].values, 2, target.points));
  CHECK(target.point_data[1].values == transfer_point_values(mesh, mesh.point_data[0].values, 1, target.points));
  Mesh every;
  every.points = target.points;
  const TransferredArrays all = transfer_point_arrays(from, {}, every, counts);
  CHECK(all.names == std::vector<std::string>{"u", "w"});  // all but kind, q and node_id
  CHECK(every.point_data[0].values == target.point_data[1].values);
  CHECK_THROWS_WITH(transfer_point_arrays(from, {"v"}, every, counts), Contains("no point array 'v'"));
}

TEST_CASE("write_mesh writes point data as $NodeData views only when asked, and they read back", "[point_data]") {
  Mesh mesh = mesh_with_data();
  mesh.point_data[0].values[4] = std::nan("");
  const auto dir = pdmesh_test::fresh_path("point_data_msh");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto text_of = [](const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  for (const char* format : {"msh", "msh22"}) {
    // As the commands write it: the spacing alone, the file msh41_string/msh22_string gives.
    write_mesh(mesh, dir, "plain", {format});
    const std::string plain = text_of(dir / "plain.msh");
    CHECK(plain == (std::string(format) == "msh" ? msh41_string(mesh) : msh22_string(mesh)));
    MeshWriteOptions options;
    options.msh_point_data = true;
    write_mesh(mesh, dir, "data", {format}, options);
    const std::string data = text_of(dir / "data.msh");
    CHECK(data.substr(0, plain.size()) == plain);  // the views follow the commands' file
    MeshReadReport report;
    MeshPointData all;
    all.decode_all = true;
    (void)parse_msh("data.msh", data, report, &all);
    REQUIRE(names_of(all) == std::vector<std::string>{"q", "u", "w"});
    CHECK(std::isnan(array_named(all, "u").values[4]));
    for (std::size_t i = 0; i < mesh.points.size(); ++i)
      if (i != 4) CHECK(array_named(all, "u").values[i] == mesh.point_data[0].values[i]);
    CHECK(array_named(all, "w").components == 2);
    CHECK(array_named(all, "w").values == mesh.point_data[1].values);
  }
  MeshWriteOptions options;
  options.msh_point_data = true;
  mesh.point_data.push_back({"wide", 10, std::vector<double>(10 * mesh.points.size(), 1.0), false});
  CHECK_THROWS_WITH(write_mesh(mesh, dir, "wide", {"msh"}, options), Contains("'wide' has 10 components"));
}
