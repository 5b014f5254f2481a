// Benchmark and inspection tool for the final cleanup (docs/cleanup.md): triangulates a node file
// (e.g. a run's final.nodes) over its geometry, cleans the mesh, checks it and prints the quality
// before and after and the time of each stage.
// Usage: bench_cleanup NODES GEOMETRY... [--min-angle D] [--iterations N] [--smooth-below D]
//                      [--step-cap F] [--no-topology] [--no-compound] [--trials-per-triangle F] [--min-trials N]
//                      [--repeats N] [--png PREFIX] [--window x0,y0,x1,y1]
//                      [--spacing EXPRESSION] (default: the boundary spacing, eq. 3.6)
//                      [--settled-aspect-drop D] (CleanupOptions::settled_aspect_drop)
//                      [--threads N] [--strip-vertices N] [--small-strip-vertices N]
//                      (CleanupOptions::threads, ::strip_vertices, ::small_strip_vertices)
//                      [--per-iteration] (a table of every outer iteration) [--write MESH.msh] (the cleaned mesh)
//        bench_cleanup --write-graded N FILE.crv   (the graded_N geometry of `pdmesh bench` as a curve file)
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <cmath>
#include <ctime>
#include <string>
#include <vector>

#include "app/bench/graded_case.hpp"
#include "cleanup/cleanup.hpp"
#include "io/msh_writer.hpp"
#include "io/text_file.hpp"
#include "geometry/geometry_files.hpp"
#include "geometry/geometry_tree.hpp"
#include "mesh/mesh_check.hpp"
#include "mesh/quality.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "nodes/node_domain.hpp"
#include "nodes/node_file.hpp"
#include "render/mesh_picture.hpp"
#include "spacing/spacing_field.hpp"

using namespace pdmesh;

namespace {

void print_summary(const char* label, const QualitySummary& s) {
  fmt::print(
      "{:<7} triangles {:>8}  min {:7.3f}  max {:6.2f}  AR avg {:.6f}  edge/q mean {:.3f} std {:.4f}  <{:g}deg {}\n",
      label, s.triangles, s.min_angle, s.max_angle, s.aspect_ratio_avg, s.spacing.mean, s.spacing.stddev,
      s.small_angle_deg, s.small_angle_triangles);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    std::vector<std::string> positional;
    CleanupOptions options;
    int repeats = 1;
    int worst = 0;
    std::string expression;
    std::string png;
    std::string mesh_out;
    std::optional<Box> window;
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw std::runtime_error(arg + " needs a value");
        return argv[++i];
      };
      if (arg == "--min-angle")
        options.min_angle = std::stod(value());
      else if (arg == "--iterations")
        options.iterations = std::stoi(value());
      else if (arg == "--smooth-below")
        options.smooth_below = std::stod(value());
      else if (arg == "--topology-below")
        options.topology_below = std::stod(value());
      else if (arg == "--step-cap")
        options.step_cap = std::stod(value());
      else if (arg == "--no-topology")
        options.topology = false;
      else if (arg == "--no-compound")
        options.compound = false;
      else if (arg == "--trials-per-triangle")
        options.trials_per_triangle = std::stod(value());
      else if (arg == "--min-trials")
        options.min_trials = std::stod(value());
      else if (arg == "--repeats")
        repeats = std::stoi(value());
      else if (arg == "--png")
        png = value();
      else if (arg == "--worst")
        worst = std::stoi(value());
      else if (arg == "--move-min-rise")
        options.move_min_rise = std::stod(value());
      else if (arg == "--move-aspect-drop")
        options.move_aspect_drop = std::stod(value());
      else if (arg == "--settled-aspect-drop")
        options.settled_aspect_drop = std::stod(value());
      else if (arg == "--threads")
        options.threads = static_cast<std::size_t>(std::stoul(value()));
      else if (arg == "--strip-vertices")
        options.strip_vertices = static_cast<std::size_t>(std::stoul(value()));
      else if (arg == "--small-strip-vertices")
        options.small_strip_vertices = static_cast<std::size_t>(std::stoul(value()));
      else if (arg == "--per-iteration")
        options.measure_iterations = true;
      else if (arg == "--write")
        mesh_out = value();
      else if (arg == "--spacing")
        expression = value();
      else if (arg == "--write-graded") {
        const auto target = static_cast<std::size_t>(std::stod(value()));
        const Geometry g = graded_case_geometry(graded_case_spacing(target));
        std::string text;
        for (const Curve& c : g.curves) {
          text += fmt::format("{}\n", c.points.size());
          for (const Vec2 p : c.points) text += fmt::format("{} {}\n", p.x, p.y);
        }
        write_text_file(value(), text);
        return 0;
      } else if (arg == "--window") {
        Box b;
        double x0, y0, x1, y1;
        if (std::sscanf(value().c_str(), "%lf,%lf,%lf,%lf", &x0, &y0, &x1, &y1) != 4)
          throw std::runtime_error("bad --window");
        b.add({x0, y0});
        b.add({x1, y1});
        window = b;
      } else
        positional.push_back(arg);
    }
    if (positional.size() < 2) throw std::runtime_error("usage: bench_cleanup NODES GEOMETRY... [options]");
    const NodeFile file = read_node_file(positional[0]);
    const std::vector<std::string> geometry_files(positional.begin() + 1, positional.end());
    const Geometry geometry = read_geometry(geometry_files, file.curve_names);
    const GeometryTree tree(geometry);
    std::unique_ptr<SpacingField> field;
    if (expression.empty())
      field = std::make_unique<BoundarySpacing>(tree);
    else
      field = std::make_unique<ExpressionSpacing>(expression);
    const SpacingField& spacing = *field;
    const auto q = [&spacing](Vec2 p) { return spacing.at(p); };
    QualityOptions qo;
    qo.small_angle_deg = options.min_angle;

    auto t0 = std::chrono::steady_clock::now();
    const Mesh mesh = triangulate(file.nodes, file.curve_names);
    const double triangulate_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    print_summary("before", summarize_quality(mesh, q, qo));
    CleanupResult result;
    double best = 1e300, best_cpu = 1e300;
    for (int r = 0; r < repeats; ++r) {
      const auto start = std::chrono::steady_clock::now();
      const std::clock_t cpu_start = std::clock();
      result = clean_mesh(mesh, file.nodes, tree, spacing, options);
      best_cpu = std::min(best_cpu, static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC);
      best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    print_summary("after", summarize_quality(result.mesh, q, qo));
    const auto& st = result.stats;
    fmt::print(
        "cleanup: {} iterations{}, {} moves, {} inserted, {} collapsed, {} rejected, {} trials ({} compound, {} "
        "applied); "
        "best of {}: wall {:.3f} s, cpu {:.3f} s (smoothing {:.3f} s, topology {:.3f} s wall; triangulation {:.3f} "
        "s)\n",
        st.iterations_run, st.settled ? " (settled)" : "", st.moves, st.inserted, st.collapsed, st.rejected, st.trials,
        st.compound_trials, st.compound_applied, repeats, best, best_cpu, st.smoothing_seconds, st.topology_seconds,
        triangulate_s);
    if (st.strips > 0)
      fmt::print("strips: {}, vertices swept in strips {}, left to the serial pass {}; {:.3f} s wall in the strips\n",
                 st.strips, st.strip_taken, st.strip_left, st.strip_seconds);
    if (options.measure_iterations) {
      // Where the work goes: per outer iteration the moves (and those that lowered their star's mean
      // aspect ratio by less than 1e-4), what they gained, and the mesh after it.
      fmt::print(
          "iter  moves  small  AR-drop(all)  AR-drop(small)  topo   trials last@trial last_deg  smooth_s  topo_s  "
          "min_deg  AR_mean\n");
      for (std::size_t k = 0; k < st.per_iteration.size(); ++k) {
        const CleanupIteration& it = st.per_iteration[k];
        fmt::print(
            "{:>4} {:>6} {:>6} {:>13.6g} {:>15.6g} {:>5} {:>8} {:>10} {:>8.3f} {:>9.3f} {:>7.3f} {:>8.3f} {:>8.6f}\n",
            k + 1, it.moves, it.small_moves, it.aspect_drop, it.small_aspect_drop, it.topology, it.trials,
            it.trials_to_last_change, it.last_change_angle, it.smoothing_seconds, it.topology_seconds, it.min_angle,
            it.aspect_mean);
      }
    }
    if (!mesh_out.empty()) write_text_file(mesh_out, msh41_string(result.mesh));  // to cmp two builds' output
    // The worst triangles before and after the cleanup: angle, where, vertex kinds (F fixed,
    // B boundary, I interior) and the number of triangles around each vertex.
    for (const Mesh* which : {&mesh, static_cast<const Mesh*>(&result.mesh)}) {
      if (worst <= 0) break;
      const Mesh& out = *which;
      std::vector<int> valence(out.points.size(), 0);
      std::vector<std::pair<double, int>> order;
      const auto per = triangle_qualities(out);
      for (std::size_t t = 0; t < out.triangles.size(); ++t) {
        order.push_back({per[t].min_angle, static_cast<int>(t)});
        for (int a : out.triangles[t]) ++valence[a];
      }
      std::sort(order.begin(), order.end());
      for (int k = 0; k < worst && k < static_cast<int>(order.size()); ++k) {
        const auto& tv = out.triangles[order[k].second];
        std::string d;
        for (int a : tv) d += fmt::format(" {}{}", "FBI"[static_cast<int>(out.kind[a])], valence[a]);
        fmt::print("  {} worst {:6.2f} at ({:.4g}, {:.4g}):{}\n", which == &mesh ? "before" : "after", order[k].first,
                   out.points[tv[0]].x, out.points[tv[0]].y, d);
      }
    }
    const CheckReport check = check_mesh(result.mesh, node_domain_area(result.nodes, geometry));
    fmt::print("check: {}\n", check.ok() ? "ok" : check.summary());
    if (!png.empty()) {
      for (const Mesh* which : {&mesh, static_cast<const Mesh*>(&result.mesh)}) {
        const auto per = triangle_qualities(*which);
        std::vector<double> values;
        for (const auto& t : per) values.push_back(t.min_angle);
        MeshPictureOptions po;
        po.triangle_values = &values;
        po.value_label = "min_angle";
        po.value_range = std::make_pair(summarize_quality(mesh).min_angle, 60.0);  // one scale for both
        po.window = window;
        po.title = which == &mesh ? "before cleanup" : "after cleanup";
        write_mesh_picture(png + (which == &mesh ? "_before.png" : "_after.png"), *which, po);
      }
    }
    return check.ok() ? 0 : 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_cleanup: {}\n", e.what());
    return 2;
  }
}
