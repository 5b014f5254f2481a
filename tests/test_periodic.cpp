// [[periodic]] (docs/geometry-input.md, "Periodic curves"): a unit cell periodic in x and y and a
// 60-degree annulus sector periodic by rotation mesh with the image curves' nodes the exact
// transforms of the source curves' (read back from mesh.msh's $Periodic section), quality.json
// reports the pairs, and every malformed table exits 2 with a message and writes nothing.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.hpp"
#include "geometry/periodic.hpp"
#include "io/mesh_formats.hpp"
#include "io/msh_reader.hpp"
#include "io/msh_writer.hpp"
#include "mesh/periodic_links.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using pdmesh::Vec2;

namespace {

const fs::path kData = fs::path(PDMESH_SOURCE_DIR) / "tests/data/periodic";

struct Link {
  int dim = 0, curve = 0, source = 0;
  std::array<double, 16> affine{};
  std::vector<std::array<int, 2>> nodes;  // (image tag, source tag)
};

// The $Periodic section of an MSH 4.1 or 2.2 file.
std::vector<Link> periodic_section(const std::string& text) {
  std::vector<Link> links;
  const auto at = text.find("$Periodic\n");
  if (at == std::string::npos) return links;
  std::istringstream in(text.substr(at + 10));
  std::size_t n = 0;
  in >> n;
  for (std::size_t k = 0; k < n; ++k) {
    Link l;
    std::size_t pairs = 0;
    std::string values;  // MSH 4.1: the count 16; MSH 2.2: "Affine"
    in >> l.dim >> l.curve >> l.source >> values;
    REQUIRE((values == "16" || values == "Affine"));
    for (double& v : l.affine) in >> v;
    in >> pairs;
    l.nodes.resize(pairs);
    for (auto& p : l.nodes) in >> p[0] >> p[1];
    links.push_back(l);
  }
  std::string end;
  in >> end;
  CHECK(end == "$EndPeriodic");
  return links;
}

Vec2 apply(const std::array<double, 16>& a, Vec2 p) {
  return {a[0] * p.x + a[1] * p.y + a[3], a[4] * p.x + a[5] * p.y + a[7]};
}

struct Run {
  pdmesh::Mesh mesh;
  std::vector<Link> links;
  std::string quality;
  std::string output;
};

Run mesh_case(const fs::path& case_file, const std::string& tag, const std::string& format) {
  const fs::path out = pdmesh_test::fresh_path(tag);
  Run run;
  const auto r = pdmesh_test::run_pdmesh("mesh '" + case_file.string() + "' --out '" + out.string() +
                                         "' --device host --formats " + format);
  run.output = r.output;
  INFO(r.output);
  REQUIRE(r.status == 0);
  run.mesh = pdmesh::read_mesh(out / "mesh.msh");
  run.links = periodic_section(pdmesh_test::slurp(out / "mesh.msh"));
  run.quality = pdmesh_test::slurp(out / "quality.json");
  return run;
}

int curve_of(const pdmesh::Mesh& mesh, const std::string& name) {
  for (std::size_t c = 0; c < mesh.curve_names.size(); ++c)
    if (mesh.curve_names[c] == name) return static_cast<int>(c);
  FAIL("no curve " << name);
  return -1;
}

// The mesh nodes on a curve (ends included), from its boundary edges.
std::set<int> nodes_on(const pdmesh::Mesh& mesh, int curve) {
  std::set<int> out;
  for (const auto& e : mesh.boundary_edges)
    if (e.curve == curve) out.insert({e.a, e.b});
  return out;
}

// Every link pairs each node of its image curve with a node of its source curve, once, and the
// image node is the source node's transform to 1e-12 of the geometry's size.
void check_links(const Run& run, const std::vector<std::array<std::string, 2>>& pairs, double size) {
  REQUIRE(run.links.size() == pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const Link& l = run.links[k];
    const int source = curve_of(run.mesh, pairs[k][0]), image = curve_of(run.mesh, pairs[k][1]);
    INFO(pairs[k][0] << " -> " << pairs[k][1]);
    CHECK(l.dim == 1);
    CHECK(l.curve == image + 1);
    CHECK(l.source == source + 1);
    std::set<int> image_nodes, source_nodes;
    double worst = 0.0;
    for (const auto& [i, s] : l.nodes) {
      image_nodes.insert(i - 1);
      source_nodes.insert(s - 1);
      const Vec2 mapped = apply(l.affine, run.mesh.points[static_cast<std::size_t>(s - 1)]);
      worst = std::max(worst, pdmesh::dist(mapped, run.mesh.points[static_cast<std::size_t>(i - 1)]));
    }
    CHECK(worst <= 1e-12 * size);
    CHECK(l.nodes.size() >= 3);
    CHECK(image_nodes == nodes_on(run.mesh, image));
    CHECK(source_nodes == nodes_on(run.mesh, source));
  }
}

double max_mismatch(const std::string& quality, std::size_t tables) {
  const std::regex re("\"max_mismatch\": ([-+0-9.eE]+)");
  double worst = -1.0;
  std::size_t found = 0;
  for (auto it = std::sregex_iterator(quality.begin(), quality.end(), re); it != std::sregex_iterator(); ++it, ++found)
    worst = std::max(worst, std::stod((*it)[1]));
  CHECK(found == tables);
  return worst;
}

// The unit square in two triangles, its right side linked to its left by the translation (1, 0).
std::pair<pdmesh::Mesh, std::vector<pdmesh::PeriodicLink>> unit_square_with_link() {
  pdmesh::Mesh mesh;
  mesh.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  mesh.boundary_edges = {{0, 1, 0}, {1, 2, 1}, {2, 3, 2}, {3, 0, 3}};
  mesh.curve_names = {"bottom", "right", "top", "left"};
  pdmesh::PeriodicLink link;
  link.curve = 1;
  link.source_curve = 3;
  link.affine = pdmesh::PeriodicTransform::translation({1.0, 0.0}).affine();
  link.nodes = {{1, 0}, {2, 3}};
  const std::vector<pdmesh::PeriodicLink> links{link};
  return {mesh, links};
}

}  // namespace

TEST_CASE("a unit cell periodic in x and y: the opposite sides carry the same nodes", "[periodic][cli]") {
  const Run run = mesh_case(kData / "cell.toml", "periodic_cell", "msh");
  INFO(run.output);
  check_links(run, {{"left", "right"}, {"bottom", "top"}}, 1.0);
  // x: translation (1, 0), inferred and said so; y: (0, 1) as given.
  CHECK(run.links[0].affine[3] == 1.0);
  CHECK(run.links[0].affine[7] == 0.0);
  CHECK(run.links[1].affine[3] == 0.0);
  CHECK(run.links[1].affine[7] == 1.0);
  CHECK(run.output.find("inferred from the curves' ends") != std::string::npos);
  // The corners are shared: (0, 0) is a source node of both tables, (1, 1) an image of both.
  std::map<std::pair<double, double>, int> corner;
  for (std::size_t i = 0; i < run.mesh.points.size(); ++i)
    corner[{run.mesh.points[i].x, run.mesh.points[i].y}] = int(i);
  const int origin = corner.at({0.0, 0.0}) + 1, far = corner.at({1.0, 1.0}) + 1;
  for (const Link& l : run.links) {
    bool has_origin = false, has_far = false;
    for (const auto& [i, s] : l.nodes) {
      has_origin = has_origin || s == origin;
      has_far = has_far || i == far;
    }
    CHECK(has_origin);
    CHECK(has_far);
  }
  CHECK(run.quality.find("\"periodic\": [") != std::string::npos);
  CHECK(max_mismatch(run.quality, 2) <= 1e-12);
}

TEST_CASE("a 60-degree sector of an annulus periodic by rotation (written as MSH 2.2)", "[periodic][cli]") {
  const Run run = mesh_case(kData / "sector.toml", "periodic_sector", "msh22");
  check_links(run, {{"r0", "r60"}}, 2.0);
  const auto& a = run.links[0].affine;
  CHECK(a[0] == Approx(0.5).margin(1e-15));
  CHECK(a[4] == Approx(std::sqrt(3.0) / 2).margin(1e-15));
  CHECK(max_mismatch(run.quality, 1) <= 2e-12);
}

TEST_CASE("the MSH 2.2 writer's $Periodic section gives the transform on an Affine line", "[periodic][io]") {
  const auto [mesh, links] = unit_square_with_link();
  const std::string v22 = pdmesh::msh22_string(mesh, &links);
  CHECK(v22.find("$Periodic\n1\n1 2 4\nAffine 1 0 0 1 0 1 0 0 0 0 1 0 0 0 0 1\n2\n2 1\n3 4\n$EndPeriodic\n") !=
        std::string::npos);
  const std::string v41 = pdmesh::msh41_string(mesh, &links);
  CHECK(v41.find("$Periodic\n1\n1 2 4\n16 1 0 0 1 0 1 0 0 0 0 1 0 0 0 0 1\n2\n2 1\n3 4\n$EndPeriodic\n") !=
        std::string::npos);
  // Without links: no section (every other run's files stay as they were).
  CHECK(pdmesh::msh41_string(mesh).find("$Periodic") == std::string::npos);
}

TEST_CASE("a periodic node lost or a node without a partner is an error naming the curve", "[periodic]") {
  pdmesh::PeriodicNodes pair;
  pair.source_curve = 3;
  pair.image_curve = 1;
  pair.transform = pdmesh::PeriodicTransform::translation({1.0, 0.0});
  pair.source = {{0.0, 0.0}, {0.0, 1.0}};
  pair.image = {{1.0, 0.0}, {1.0, 1.0}};
  pdmesh::Mesh mesh;
  mesh.points = {{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  mesh.boundary_edges = {{0, 1, 0}, {1, 2, 1}, {2, 3, 2}, {3, 0, 3}};
  mesh.curve_names = {"bottom", "right", "top", "left"};
  const auto links = pdmesh::link_periodic_nodes(mesh, {pair});
  REQUIRE(links.size() == 1);
  CHECK(links[0].curve == 1);
  CHECK(links[0].source_curve == 3);
  CHECK(links[0].nodes == std::vector<std::array<int, 2>>{{1, 0}, {2, 3}});
  CHECK(links[0].max_mismatch == 0.0);
  // An image node off by an ulp is not the transform's.
  pdmesh::Mesh moved = mesh;
  moved.points[2].y = std::nextafter(1.0, 2.0);
  CHECK_THROWS_WITH(pdmesh::link_periodic_nodes(moved, {pair}),
                    Catch::Contains("periodic curve 'right': its node (1, 1) is not a point of the mesh"));
  // A node the cleanup would have put on the image curve, with no partner on the source.
  pdmesh::Mesh split = mesh;
  split.points.push_back({1.0, 0.5});
  split.boundary_edges = {{0, 1, 0}, {1, 4, 1}, {4, 2, 1}, {2, 3, 2}, {3, 0, 3}};
  split.triangles = {{0, 1, 4}, {0, 4, 2}, {0, 2, 3}};
  CHECK_THROWS_WITH(pdmesh::link_periodic_nodes(split, {pair}),
                    Catch::Contains("periodic curve 'right': its mesh node (1, 0.5) has no partner on 'left'"));
}

TEST_CASE("malformed [[periodic]] tables exit 2 naming the table and write nothing", "[periodic][cli][bad]") {
  const fs::path dir = pdmesh_test::fresh_dir("periodic_bad");
  const std::string head = "preset = \"best\"\n[geometry]\nfiles = [\"" + (kData / "cell.crv").string() +
                           "\"]\ncurve_names = [\"bottom\", \"right\", \"top\", \"left\", \"hole\"]\n"
                           "[spacing]\nsize = 0.1\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[[periodic]]\ncurves = [\"left\", \"nowhere\"]\n", "unknown curve 'nowhere'"},
      {"[[periodic]]\ncurves = [\"left\", \"left\"]\n", "cannot be periodic with itself"},
      {"[[periodic]]\ncurves = [\"left\", \"right\"]\ntranslate = [0.9, 0]\n",
       "the translation (0.9, 0) does not map 'left' onto 'right': they are 0.1 apart at"},
      {"[[periodic]]\ncurves = [\"left\", \"right\"]\nrotate = { center = [0.5, 0.5], angle_deg = 90 }\n",
       "does not map 'left' onto 'right'"},
      {"[[periodic]]\ncurves = [\"left\", \"right\"]\n[[periodic]]\ncurves = [\"right\", \"top\"]\n",
       "curve 'right' is in two tables"},
      {"[[periodic]]\ncurves = [\"left\", \"right\"]\n[[boundary_layer]]\ncurves = [\"left\"]\nfirst_height = "
       "0.001\nlayers = 3\n",
       "curve 'left' is also a boundary-layer wall"},
      {"[[periodic]]\ncurves = [\"left\", \"right\"]\n[motion]\ncurves = [\"hole\"]\nrotate = \"10 * t\"\nsteps = 2\n",
       "[[periodic]] is not supported with [motion]"},
      {"[[periodic]]\ncurves = [\"left\", \"right\"]\nrotate = { centre = [0, 0], angle_deg = 90 }\n",
       "unknown key 'periodic.rotate.centre'"},
      {"[[periodic]]\ncurves = [\"left\", \"right\", \"top\"]\n", "must name 2 curves"},
      {"[[periodic]]\ncurves = [\"left\", \"hole\"]\n", "does not map 'left' onto 'hole'"},
  };
  int k = 0;
  for (const auto& [table, expected] : cases) {
    const fs::path file = dir / ("case" + std::to_string(k++) + ".toml");
    std::ofstream(file) << head << table;
    const fs::path out = dir / ("out" + std::to_string(k));
    const auto r = pdmesh_test::run_pdmesh("mesh '" + file.string() + "' --out '" + out.string() + "'");
    INFO(table);
    INFO(r.output);
    CHECK(r.status == 2);
    CHECK(r.output.rfind("pdmesh: error: ", 0) == 0);
    CHECK(r.output.find(expected) != std::string::npos);
    CHECK(r.output.find(file.string()) != std::string::npos);  // names the case file
    CHECK_FALSE(fs::exists(out));
  }
}

TEST_CASE("a periodic channel with layers on both walls: the layers' end columns are paired too",
          "[periodic][layers][cli]") {
  const Run run = mesh_case(kData / "channel.toml", "periodic_channel", "msh");
  INFO(run.output);
  check_links(run, {{"inlet", "outlet"}}, 2.0);
  CHECK(run.links[0].affine[3] == 2.0);
  CHECK(run.links[0].affine[7] == 0.0);
  CHECK(max_mismatch(run.quality, 1) == 0.0);
  CHECK(run.quality.find("\"boundary_layer\"") != std::string::npos);
  // Both walls' layers (thickness 0.08 from h1 = 0.002) end on the inlet and the outlet: their
  // column nodes are pairs, the first at h1 over each wall, and the outlet carries the inlet's
  // heights exactly.
  std::vector<double> inlet, outlet;
  for (const auto& [i, s] : run.links[0].nodes) {
    const Vec2 si = run.mesh.points[static_cast<std::size_t>(s - 1)];
    const Vec2 im = run.mesh.points[static_cast<std::size_t>(i - 1)];
    CHECK(si.x == 0.0);
    CHECK(im.x == 2.0);
    CHECK(im.y == si.y);
    inlet.push_back(si.y);
    outlet.push_back(im.y);
  }
  std::sort(inlet.begin(), inlet.end());
  const auto count_in = [&](double lo, double hi) {
    return std::count_if(inlet.begin(), inlet.end(), [&](double y) { return y >= lo && y <= hi; });
  };
  CHECK(count_in(0.0, 0.08) >= 10);  // the bottom layer's column, wall node included
  CHECK(count_in(0.92, 1.0) >= 10);  // the top's
  REQUIRE(inlet.size() >= 3);
  CHECK(inlet[0] == 0.0);
  CHECK(inlet[1] == Approx(0.002).epsilon(1e-9));
  CHECK(inlet.back() == 1.0);
}

TEST_CASE("[[periodic]] with layers: walls that are not periodic, or layers at one end only, exit 2",
          "[periodic][layers][cli][bad]") {
  const fs::path dir = pdmesh_test::fresh_dir("periodic_layers_bad");
  const auto write_geometry = [&](const std::string& name, const std::vector<std::vector<Vec2>>& curves) {
    std::ofstream out(dir / name);
    for (const auto& c : curves) {
      out << c.size() << "\n";
      for (const Vec2 p : c) out << p.x << " " << p.y << "\n";
    }
  };
  // The bottom wall turns down 0.2 before the outlet: it meets the inlet at about 87 deg and the
  // outlet at about 63 deg, so its layer's end columns differ although the sides are periodic.
  write_geometry("bent.crv", {{{0, 0}, {1.8, 0.1}, {2, 0}}, {{2, 0}, {2, 1}}, {{2, 1}, {0, 1}}, {{0, 1}, {0, 0}}});
  // The bottom in two curves, layers on the first only: they end on the inlet, not on the outlet.
  write_geometry("split.crv",
                 {{{0, 0}, {1, 0}}, {{1, 0}, {2, 0}}, {{2, 0}, {2, 1}}, {{2, 1}, {0, 1}}, {{0, 1}, {0, 0}}});
  const std::string tail = "[[periodic]]\ncurves = [\"inlet\", \"outlet\"]\n[spacing]\nsize = 0.1\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[geometry]\nfiles = [\"bent.crv\"]\ncurve_names = [\"bottom\", \"outlet\", \"top\", \"inlet\"]\n"
       "[[boundary_layer]]\ncurves = [\"bottom\"]\nfirst_height = 0.002\nthickness = 0.05\n" +
           tail,
       "the walls are not periodic: wall 'bottom' meets 'inlet' at (0, 0) at 86.8"},
      {"[geometry]\nfiles = [\"split.crv\"]\ncurve_names = [\"bottom_a\", \"bottom_b\", \"outlet\", \"top\", "
       "\"inlet\"]\n[[boundary_layer]]\ncurves = [\"bottom_a\"]\nfirst_height = 0.002\nthickness = 0.05\n" +
           tail,
       "end on 'inlet' at (0, 0) (wall 'bottom_a') but not on 'outlet' at its periodic image (2, 0) (curve "
       "'bottom_b' meets it there)"},
  };
  int k = 0;
  for (const auto& [body, expected] : cases) {
    const fs::path file = dir / ("case" + std::to_string(k++) + ".toml");
    std::ofstream(file) << "preset = \"best\"\n" << body;
    const fs::path out = dir / ("out" + std::to_string(k));
    const auto r = pdmesh_test::run_pdmesh("mesh '" + file.string() + "' --out '" + out.string() + "'");
    INFO(body);
    INFO(r.output);
    CHECK(r.status == 2);
    CHECK(r.output.find("pdmesh: error: ") != std::string::npos);  // after the spacing's progress line
    CHECK(r.output.find(expected) != std::string::npos);
    CHECK(r.output.find(file.string()) != std::string::npos);
    CHECK_FALSE(fs::exists(out));
  }
}

TEST_CASE("the MSH reader reads $Periodic back (4.1 and 2.2) with the largest mismatch", "[periodic][io]") {
  const auto [mesh, links] = unit_square_with_link();
  for (const bool v41 : {true, false}) {
    INFO((v41 ? "MSH 4.1" : "MSH 2.2"));
    pdmesh::MeshReadReport report;
    const pdmesh::Mesh back = pdmesh::parse_msh(
        "cell.msh", v41 ? pdmesh::msh41_string(mesh, &links) : pdmesh::msh22_string(mesh, &links), report);
    REQUIRE(report.periodic.size() == 1);
    const pdmesh::PeriodicLink& l = report.periodic[0];
    CHECK(back.curve_names[static_cast<std::size_t>(l.curve)] == "right");
    CHECK(back.curve_names[static_cast<std::size_t>(l.source_curve)] == "left");
    CHECK(l.affine == links[0].affine);
    REQUIRE(l.nodes.size() == 2);
    for (const auto& [i, s] : l.nodes)
      CHECK(back.points[static_cast<std::size_t>(i)] == back.points[static_cast<std::size_t>(s)] + Vec2{1.0, 0.0});
    CHECK(l.max_mismatch == 0.0);
  }
  // A Gmsh-style 2.2 section: a link of points (skipped, with a note), a curve link without an affine
  // line, and one whose image node is 1e-3 off its transform.
  const std::string head =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 1.001 0.5 0\n$EndNodes\n"
      "$Elements\n5\n1 1 2 0 1 1 2\n2 1 2 0 2 2 5\n3 1 2 0 2 5 3\n4 1 2 0 4 4 1\n5 2 2 0 1 1 2 3\n$EndElements\n";
  pdmesh::MeshReadReport gmsh;
  const pdmesh::Mesh g =
      pdmesh::parse_msh("g.msh",
                        head +
                            "$Periodic\n3\n0 2 1\n1\n2 1\n1 2 4\nAffine 1 0 0 1 0 1 0 0 0 0 1 0 0 0 0 1\n2\n2 1\n3 4\n"
                            "1 2 4\n1\n5 4\n$EndPeriodic\n",
                        gmsh);
  REQUIRE(gmsh.periodic.size() == 2);
  CHECK(g.curve_names[static_cast<std::size_t>(gmsh.periodic[0].curve)] == "entity2");
  CHECK(gmsh.periodic[0].max_mismatch == 0.0);
  CHECK(std::isnan(gmsh.periodic[1].max_mismatch));  // no transform to measure by
  CHECK(std::find_if(gmsh.notes.begin(), gmsh.notes.end(), [](const std::string& n) {
          return n.find("skipped 1 $Periodic links of points or surfaces") != std::string::npos;
        }) != gmsh.notes.end());
  pdmesh::MeshReadReport off;
  (void)pdmesh::parse_msh(
      "off.msh", head + "$Periodic\n1\n1 2 4\nAffine 1 0 0 1 0 1 0 0 0 0 1 0 0 0 0 1\n1\n5 4\n$EndPeriodic\n", off);
  REQUIRE(off.periodic.size() == 1);
  // Node 5 (1.001, 0.5) against T(node 4) = (1, 1).
  CHECK(off.periodic[0].max_mismatch == Approx(std::hypot(0.001, 0.5)));
  pdmesh::MeshReadReport bad;
  CHECK_THROWS_WITH(pdmesh::parse_msh("bad.msh", head + "$Periodic\n1\n1 2 4\n1\n9 4\n$EndPeriodic\n", bad),
                    Catch::Contains("bad.msh:") && Catch::Contains("$Periodic refers to unknown node tag 9"));
}

TEST_CASE("pdmesh quality reports a mesh file's periodic pairs as the mesh run's quality.json does",
          "[periodic][cli]") {
  const fs::path out = pdmesh_test::fresh_path("periodic_quality");
  const auto r = pdmesh_test::run_pdmesh("mesh '" + (kData / "cell.toml").string() + "' --out '" + out.string() +
                                         "' --device host --formats msh -q");
  REQUIRE(r.status == 0);
  const auto q = pdmesh_test::run_pdmesh("quality '" + (out / "mesh.msh").string() + "' --json -");
  INFO(q.output);
  REQUIRE(q.status == 0);
  CHECK(q.output.find("periodic: 'left' -> 'right': ") != std::string::npos);
  CHECK(q.output.find("periodic: 'bottom' -> 'top': ") != std::string::npos);
  CHECK(max_mismatch(q.output, 2) == 0.0);
  // The same pair counts as the run's own report.
  const std::regex pairs("\"pairs\": ([0-9]+)");
  std::vector<std::string> run_counts, read_counts;
  const std::string run_json = pdmesh_test::slurp(out / "quality.json");
  for (auto it = std::sregex_iterator(run_json.begin(), run_json.end(), pairs); it != std::sregex_iterator(); ++it)
    run_counts.push_back((*it)[1]);
  for (auto it = std::sregex_iterator(q.output.begin(), q.output.end(), pairs); it != std::sregex_iterator(); ++it)
    read_counts.push_back((*it)[1]);
  CHECK(run_counts.size() == 2);
  CHECK(read_counts == run_counts);
}

TEST_CASE("a periodic square under an anisotropic metric: the pairs in the metric run", "[periodic][metric][cli]") {
  const Run run = mesh_case(kData / "metric.toml", "periodic_metric", "msh");
  INFO(run.output);
  check_links(run, {{"left", "right"}, {"bottom", "top"}}, 1.0);
  CHECK(max_mismatch(run.quality, 2) == 0.0);
  CHECK(run.quality.find("\"metric\"") != std::string::npos);
  // The left side's nodes follow the metric's band (h_y from 0.06 at the corners to 0.01 at
  // y = 0.5): more of them near the middle than near the ends.
  const int left = curve_of(run.mesh, "left");
  int middle = 0, ends = 0;
  for (const int v : nodes_on(run.mesh, left)) {
    const double y = run.mesh.points[static_cast<std::size_t>(v)].y;
    middle += std::abs(y - 0.5) < 0.1;
    ends += y < 0.2;
  }
  CHECK(middle > 2 * ends);
}

TEST_CASE("a rotor sector with layers on hub and shroud: the columns are paired by the rotation",
          "[periodic][layers][cli]") {
  const Run run = mesh_case(kData / "sector_layers.toml", "periodic_sector_layers", "msh");
  INFO(run.output);
  check_links(run, {{"r0", "r60"}}, 2.0);
  CHECK(max_mismatch(run.quality, 1) <= 2e-12);
  // The side at 0 degrees holds both columns: nodes within the layers' 0.06 of r = 1 and of r = 2,
  // the first at h1 = 0.002 from each wall.
  std::vector<double> radii;
  for (const auto& [i, s] : run.links[0].nodes) {
    const Vec2 p = run.mesh.points[static_cast<std::size_t>(s - 1)];
    CHECK(p.y == 0.0);
    radii.push_back(p.x);
  }
  std::sort(radii.begin(), radii.end());
  const auto within = [&](double lo, double hi) {
    return std::count_if(radii.begin(), radii.end(), [&](double r) { return r >= lo && r <= hi; });
  };
  CHECK(within(1.0, 1.06 + 1e-12) >= 8);
  CHECK(within(2.0 - 0.06 - 1e-12, 2.0) >= 8);
  // Along the radius: h1 over the arc's first polygon segment, which the radial side meets a little
  // off its normal (h1 / cos of half the segment's turn).
  REQUIRE(radii.size() >= 4);
  CHECK(radii[1] - radii[0] == Approx(0.002).epsilon(1e-3));
  CHECK(radii.back() - radii[radii.size() - 2] == Approx(0.002).epsilon(1e-3));
}
