// Benchmark: the pictures of a `pdmesh mesh` run, drawn again from its output directory, each one
// repeated; the best and median process CPU and wall per picture, and the PNG encoder alone on the
// same pixels. Usage:
//   bench_pictures --geometry A.crv [--geometry B.crv ...] --run DIR [--repeats N=9] [--out DIR2]
// DIR holds the run's initial.nodes, final.nodes and mesh.msh; the pictures go to DIR2 (default: a
// folder "bench_pictures" in the current one), named as the run names them.
#include <cairo.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "geometry/geometry_files.hpp"
#include "io/mesh_formats.hpp"
#include "nodes/node_file.hpp"
#include "render/mesh_picture.hpp"
#include "render/node_picture.hpp"
#include "render/png_file.hpp"

namespace fs = std::filesystem;

namespace {

struct Times {
  std::vector<double> wall, cpu;
};

Times repeat(int repeats, const std::function<void()>& f) {
  Times t;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    const std::clock_t cpu_start = std::clock();
    f();
    t.cpu.push_back(static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC);
    t.wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return t;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

double best(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end()); }

void report(const std::string& name, const Times& t) {
  fmt::print("{:<28} cpu best {:7.2f} ms median {:7.2f} ms   wall best {:7.2f} ms median {:7.2f} ms\n", name,
             1e3 * best(t.cpu), 1e3 * median(t.cpu), 1e3 * best(t.wall), 1e3 * median(t.wall));
}

// The encoder alone: the written picture read back into a surface, encoded again.
void report_encoder(const fs::path& png, int repeats) {
  cairo_surface_t* surface = cairo_image_surface_create_from_png(png.c_str());
  if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
    cairo_surface_destroy(surface);
    return;
  }
  std::size_t bytes = 0;
  const Times t = repeat(repeats, [&] { bytes = pdmesh::encode_png(surface).size(); });
  report(fmt::format("  encoder ({:.0f} kB)", bytes / 1e3), t);
  cairo_surface_destroy(surface);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> geometry_files;
  fs::path run, out = "bench_pictures";
  int repeats = 9;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--geometry")
      geometry_files.push_back(value());
    else if (arg == "--run")
      run = value();
    else if (arg == "--repeats")
      repeats = std::stoi(value());
    else if (arg == "--out")
      out = value();
    else {
      fmt::print(stderr, "unknown argument {}\n", arg);
      return 2;
    }
  }
  if (geometry_files.empty() || run.empty()) {
    fmt::print(stderr,
               "usage: bench_pictures --geometry FILE [--geometry FILE ...] --run DIR [--repeats N] [--out DIR]\n");
    return 2;
  }
  fs::create_directories(out);
  const pdmesh::Geometry geometry = pdmesh::read_geometry(geometry_files, {});
  for (const char* stage : {"initial", "final"}) {
    const fs::path nodes_file = run / fmt::format("{}.nodes", stage);
    if (!fs::exists(nodes_file)) continue;
    const pdmesh::NodeFile nodes = pdmesh::read_node_file(nodes_file);
    pdmesh::NodePictureOptions options;
    options.title = stage;
    const fs::path png = out / fmt::format("{}.png", stage);
    report(fmt::format("{}.png", stage),
           repeat(repeats, [&] { pdmesh::write_node_picture(png, geometry, nodes.nodes, options); }));
    report_encoder(png, repeats);
  }
  const fs::path mesh_file = run / "mesh.msh";
  if (fs::exists(mesh_file)) {
    const pdmesh::Mesh mesh = pdmesh::read_mesh(mesh_file);
    pdmesh::MeshPictureOptions options;
    options.title = "mesh";
    const fs::path png = out / "mesh.png";
    report("mesh.png", repeat(repeats, [&] { pdmesh::write_mesh_picture(png, mesh, options); }));
    report_encoder(png, repeats);
    options.bands = 1;
    report("mesh.png (one band)", repeat(repeats, [&] { pdmesh::write_mesh_picture(png, mesh, options); }));
    if (const auto close_up = pdmesh::dense_mesh_close_up(mesh, pdmesh::default_mesh_window(mesh), options.long_side)) {
      options.bands = 4;
      options.window = close_up->window;
      const fs::path zoomed = out / "mesh_smallest_angle.png";
      report("mesh_smallest_angle.png", repeat(repeats, [&] { pdmesh::write_mesh_picture(zoomed, mesh, options); }));
      report_encoder(zoomed, repeats);
    }
  }
  return 0;
}
