// End-to-end simulation tests: a 300-iteration circle-in-circle run (thesis ch. 6 geometry) that
// settles, stays inside, keeps the boundary consistent and repeats bit for bit; and the outputs.
#include <catch2/catch.hpp>

#include <cairo.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "render/history_plot.hpp"
#include "sim/boundary_handling.hpp"
#include "sim/simulation.hpp"
#include "spacing/spacing_field.hpp"
#include "sim_fixtures.hpp"

using namespace pdmesh;

namespace {

using pdmesh_test::circle_circle;

struct Run {
  NodeSet initial;
  NodeSet nodes;
  SimResult result;
  int callbacks = 0;
  bool interior_inside = true;         // every interior node inside the domain (exact test)
  bool arcs_ordered = true;            // boundary nodes strictly ordered along every curve
  double worst_boundary_offset = 0.0;  // boundary nodes are on their curve up to rounding
};

Run run_circle_circle(int iterations) {
  const Geometry geometry = circle_circle();
  const GeometryTree tree(geometry);
  const BoundarySpacing spacing(tree);
  Run run;
  run.nodes = make_initial_distribution(tree, spacing, {InitMethod::Structured, 1, {}}).nodes;
  run.initial = run.nodes;
  SimOptions options;
  options.iterations = iterations;
  options.dt_initial = 0.01;
  options.quiet = true;
  SimCallbacks callbacks;
  callbacks.on_iteration = [&](const HistoryRow&) { ++run.callbacks; };
  run.result = run_simulation(run.nodes, tree, spacing, options, callbacks);
  for (std::size_t i = 0; i < run.nodes.size(); ++i) {
    // Boundary nodes lie on their curve only up to rounding, so the exact inside test is for
    // interior nodes; boundary nodes are checked by their distance to the curve.
    if (run.nodes.kind[i] == NodeKind::Interior)
      run.interior_inside = run.interior_inside && tree.inside(run.nodes.x[i]);
    else
      run.worst_boundary_offset =
          std::max(run.worst_boundary_offset, tree.closest_on_curve(run.nodes.x[i], run.nodes.curve[i]).distance);
  }
  // The handler recomputes arc positions from scratch: they must still be strictly ordered.
  const BoundaryHandler check(tree, run.nodes);
  for (const auto& arcs : check.arcs())
    for (std::size_t k = 1; k < arcs.size(); ++k)
      if (!(arcs[k - 1] < arcs[k])) run.arcs_ordered = false;
  return run;
}

bool same_rows(const HistoryRow& a, const HistoryRow& b) {
  return a.iteration == b.iteration && a.average_force == b.average_force && a.average_kinetic == b.average_kinetic &&
         a.max_force == b.max_force && a.dt_gm == b.dt_gm && a.snapped == b.snapped && a.clamped == b.clamped &&
         a.fixed == b.fixed && a.boundary == b.boundary && a.interior == b.interior;
}

std::filesystem::path scratch_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("pdmesh_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace

TEST_CASE("circle in circle: 300 iterations settle, stay inside and repeat bit for bit", "[sim]") {
  const Run run = run_circle_circle(300);
  const auto& h = run.result.history;
  REQUIRE(h.size() == 300);
  CHECK(run.callbacks == 300);
  CHECK(h.front().iteration == 1);
  CHECK(h.back().iteration == 300);
  INFO("average |F| first " << h.front().average_force << ", last " << h.back().average_force);
  CHECK(h.back().average_force * 10.0 <= h.front().average_force);
  CHECK(run.interior_inside);
  CHECK(run.arcs_ordered);
  CHECK(run.worst_boundary_offset < 1e-12);
  CHECK(run.result.stats.pairs_within > 0);
  CHECK(run.result.stats.coincident_pairs == 0);
  // Fixed nodes never move; node counts by kind add up.
  for (std::size_t i = 0; i < run.initial.size(); ++i)
    if (run.initial.kind[i] == NodeKind::Fixed) CHECK(run.nodes.x[i] == run.initial.x[i]);
  CHECK(h.back().fixed + h.back().boundary + h.back().interior == run.nodes.size());
  CHECK(h.back().fixed == 4);

  const Run again = run_circle_circle(300);
  REQUIRE(again.nodes.size() == run.nodes.size());
  bool identical = again.nodes.curve_nodes == run.nodes.curve_nodes && again.nodes.kind == run.nodes.kind;
  for (std::size_t i = 0; i < run.nodes.size(); ++i)
    identical = identical && again.nodes.x[i] == run.nodes.x[i] && again.nodes.q[i] == run.nodes.q[i];
  for (std::size_t k = 0; k < h.size(); ++k) identical = identical && same_rows(again.result.history[k], h[k]);
  CHECK(identical);
}

TEST_CASE("default initial dt_GM rule", "[sim]") {
  NodeSet nodes;
  nodes.add({0, 0}, 0.5, NodeKind::Interior, -1);
  nodes.add({1, 0}, 2.0, NodeKind::Interior, -1);
  nodes.add({2, 0}, 1.0, NodeKind::Interior, -1);
  // dt^2 = 2 (q/200) / (4 a q (0.9^-12 - 0.9^-6)): q cancels.
  const double g = std::pow(0.9, -12) - std::pow(0.9, -6);
  CHECK(default_dt_initial(nodes, 15.0) == Approx(std::sqrt(2.0 / 200.0 / (60.0 * g))).epsilon(1e-14));
  CHECK(default_dt_initial(nodes, 15.0) == Approx(0.01002).epsilon(1e-3));
  CHECK(default_dt_initial(nodes, 60.0) == Approx(0.5 * default_dt_initial(nodes, 15.0)).epsilon(1e-14));
}

TEST_CASE("history CSV and plot files", "[sim]") {
  std::vector<HistoryRow> rows;
  for (int k = 1; k <= 137; ++k) {
    HistoryRow r;
    r.iteration = k;
    r.average_force = 50.0 * std::exp(-0.03 * k);
    r.average_kinetic = k == 60 ? 0.0 : 1e-3 * std::exp(-0.05 * k);  // a zero breaks the log-scale line
    r.max_force = 2.0 * r.average_force;
    r.dt_gm = 0.01;
    r.fixed = 4;
    r.boundary = 116;
    r.interior = 1000 + k;
    rows.push_back(r);
  }
  const auto dir = scratch_dir("history");
  write_history_csv(dir / "history.csv", rows);
  std::ifstream in(dir / "history.csv");
  std::string line;
  std::getline(in, line);
  CHECK(line ==
        "iteration,average_force,average_kinetic_energy,max_force,dt_gm,snapped,clamped,fixed,boundary,interior,"
        "inserted,removed");
  int lines = 0;
  std::string last;
  while (std::getline(in, line)) ++lines, last = line;
  CHECK(lines == 137);
  std::istringstream fields(last);
  std::string field;
  std::getline(fields, field, ',');
  CHECK(field == "137");
  std::getline(fields, field, ',');
  CHECK(std::stod(field) == rows.back().average_force);  // 17 significant digits round-trip

  write_history_plot(dir / "history.png", rows, "test run");
  cairo_surface_t* png = cairo_image_surface_create_from_png((dir / "history.png").c_str());
  REQUIRE(cairo_surface_status(png) == CAIRO_STATUS_SUCCESS);
  const int w = cairo_image_surface_get_width(png), h = cairo_image_surface_get_height(png);
  CHECK(w == 900);
  CHECK(h == 560);
  // Both series are drawn: count strongly red and strongly blue pixels.
  const unsigned char* data = cairo_image_surface_get_data(png);
  const int stride = cairo_image_surface_get_stride(png);
  int red = 0, blue = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const unsigned char* px = data + y * stride + 4 * x;  // BGRA in native-endian ARGB32
      red += px[2] > 180 && px[1] < 80 && px[0] < 80;
      blue += px[0] > 180 && px[1] < 100 && px[2] < 80;
    }
  }
  cairo_surface_destroy(png);
  CHECK(red > 300);
  CHECK(blue > 300);
  std::filesystem::remove_all(dir);
}
