// Tests of the warm start (case key init.file): the points reader (init/warm_points), the fill that
// keeps a file's interior points (init/metric_fill warm_fill) in a metric and by q, and the key.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "core/errors.hpp"
#include "geometry/geometry_tree.hpp"
#include "geometry_fixtures.hpp"
#include "init/boundary_placement.hpp"
#include "init/metric_fill.hpp"
#include "init/warm_points.hpp"
#include "spacing/metric.hpp"
#include "spacing/metric_field.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
namespace fs = std::filesystem;

namespace {

class ConstantSpacing final : public SpacingField {
 public:
  explicit ConstantSpacing(double q) : q_(q) {}
  double at(Vec2) const override { return q_; }

 private:
  double q_;
};

NodeSet square_boundary(const GeometryTree& tree, const SpacingField& along) {
  return assemble_boundary_nodes(tree.geometry(), along, spacing_stations(tree.geometry(), along));
}

// This process's directory for the files the tests write.
const fs::path& scratch_dir() {
  static const fs::path dir = pdmesh_test::fresh_dir("warm_start");
  return dir;
}

fs::path write_file(const std::string& name, const std::string& text) {
  const fs::path path = scratch_dir() / name;
  std::ofstream(path) << text;
  return path;
}

}  // namespace

TEST_CASE("warm_fill keeps the interior points that clear the curves and each other, by q") {
  const Geometry g = fixtures::square(1.0, 4);
  const GeometryTree tree(g);
  const ConstantSpacing q(0.1);
  NodeSet nodes = square_boundary(tree, q);
  const std::size_t boundary = nodes.size();
  const std::vector<Vec2> points{
      {0.5, 0.5},    // kept
      {0.52, 0.5},   // 0.2 q from the first: dropped
      {0.3, 0.3},    // kept
      {1.5, 0.5},    // outside: dropped
      {0.5, 0.03},   // 0.3 q from the bottom side: dropped
      {0.45, 0.08},  // 0.8 q from it, 0.94 q from its nodes at x = 0.4 and 0.5: kept
      {0.0, 0.5},    // on the boundary: dropped
  };
  const std::size_t added = warm_fill(tree, nullptr, q, nodes, points);
  CHECK(added == 3);
  REQUIRE(nodes.size() == boundary + 3);
  CHECK(nodes.x[boundary].x == 0.5);
  CHECK(nodes.x[boundary + 1].x == 0.3);
  CHECK(nodes.x[boundary + 2].y == 0.08);
  for (std::size_t i = boundary; i < nodes.size(); ++i) {
    CHECK(nodes.kind[i] == NodeKind::Interior);
    CHECK(nodes.q[i] == 0.1);
  }
}

TEST_CASE("warm_fill measures the spacing in the run's metric") {
  const Geometry g = fixtures::square(1.0, 4);
  const GeometryTree tree(g);
  // Sizes 0.1 along x, 0.01 along y.
  const ConstantMetricField metric(metric_from_sizes(0.1, 0.01, 0.0));
  const ConstantSpacing q(std::sqrt(0.1 * 0.01));
  const CurveMetricSpacing along(tree, metric);
  NodeSet nodes = square_boundary(tree, along);
  const std::size_t boundary = nodes.size();
  const std::vector<Vec2> points{
      {0.5, 0.5},   {0.5, 0.51},  // one metric unit across: kept
      {0.52, 0.5},                // 0.2 metric units along: dropped
      {0.5, 0.004},               // 0.4 metric units from the bottom: dropped
      {0.04, 0.3},                // 0.4 metric units from the left side: dropped
      {0.08, 0.3},                // 0.8: kept
  };
  CHECK(warm_fill(tree, &metric, q, nodes, points) == 3);
  REQUIRE(nodes.size() == boundary + 3);
  CHECK(nodes.x[boundary + 1].y == 0.51);
  CHECK(nodes.x[boundary + 2].x == 0.08);
  MetricFillOptions limited;
  limited.max_nodes = 1;
  NodeSet again = square_boundary(tree, along);
  CHECK_THROWS_AS(warm_fill(tree, &metric, q, again, points, limited), LimitError);
}

TEST_CASE("metric_fill grown from the kept points fills the gaps a warm start leaves") {
  const Geometry g = fixtures::square(1.0, 4);
  const GeometryTree tree(g);
  const ConstantMetricField metric(metric_from_sizes(0.05, 0.01, 0.0));
  const ConstantSpacing q(std::sqrt(0.05 * 0.01));
  const CurveMetricSpacing along(tree, metric);
  NodeSet nodes = square_boundary(tree, along);
  const std::size_t boundary = nodes.size();
  REQUIRE(warm_fill(tree, &metric, q, nodes, {{0.5, 0.5}, {0.51, 0.5}}) == 1);
  MetricFillOptions fill;
  fill.grow_from_interior = true;
  metric_fill(tree, metric, q, nodes, fill);
  // Within 10 % of the unit mesh's (4C/sqrt(3) + B + 2) / 2 nodes, C = 1 / (0.05 * 0.01); the kept
  // points stay first.
  const double ideal = (4.0 / (0.05 * 0.01) / std::sqrt(3.0) + static_cast<double>(boundary) + 2.0) / 2.0;
  INFO(nodes.size() << " nodes, ideal " << ideal);
  CHECK(static_cast<double>(nodes.size()) > 0.9 * ideal);
  CHECK(static_cast<double>(nodes.size()) < 1.1 * ideal);
  CHECK(nodes.x[boundary].x == 0.5);
  CHECK(nodes.kind[boundary] == NodeKind::Interior);
}

TEST_CASE("read_warm_points reads a node file's points and refuses bad files by name") {
  const fs::path good =
      write_file("good.nodes", "# pdmesh nodes v1\n2\n0.25 0.5 interior -1 1\n0.75 0.5 interior -1 1\ncurves 0\n");
  const std::vector<Vec2> points = read_warm_points(good);
  REQUIRE(points.size() == 2);
  CHECK(points[0].x == 0.25);
  CHECK(points[1].x == 0.75);
  const fs::path missing = scratch_dir() / "missing.nodes";
  CHECK_THROWS_WITH(read_warm_points(missing), Catch::Contains("missing.nodes") && Catch::Contains("no such file"));
  const fs::path nan = write_file("nan.nodes", "# pdmesh nodes v1\n1\nnan 0.5 interior -1 1\ncurves 0\n");
  CHECK_THROWS_AS(read_warm_points(nan), InputError);
  CHECK_THROWS_WITH(read_warm_points(nan), Catch::Contains("nan.nodes"));
  const fs::path text = write_file("points.txt", "0 0\n");
  CHECK_THROWS_WITH(read_warm_points(text), Catch::Contains("points.txt"));
}

TEST_CASE("init.file is read relative to the case file and must name a node or mesh file") {
  const fs::path source = "/cases/demo/case.toml";
  const CaseConfig c = parse_case_text("[geometry]\nfiles = [\"a.crv\"]\n[init]\nfile = \"prev/mesh.nodes\"\n", source);
  CHECK(c.init.file == fs::path("/cases/demo/prev/mesh.nodes"));
  CHECK(parse_case_text("[geometry]\nfiles = [\"a.crv\"]\n", source).init.file.empty());
  CHECK_THROWS_WITH(parse_case_text("[geometry]\nfiles = [\"a.crv\"]\n[init]\nfile = \"prev.csv\"\n", source),
                    Catch::Contains("init.file") && Catch::Contains("prev.csv"));
}
