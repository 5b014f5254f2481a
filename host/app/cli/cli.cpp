// Command-line definition: `pdmesh mesh INPUT --out DIR [options]`, translating the direct options
// into case-file overrides so that one validator checks every value.
#include "app/cli/cli.hpp"

#include <memory>
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <optional>
#include <sstream>
#include <toml++/toml.h>

#include "app/config/case_file.hpp"
#include "app/config/environment.hpp"
#include "app/pipeline/exit_codes.hpp"
#include "app/bench/bench_command.hpp"
#include "app/bench/whole_run_bench.hpp"
#include "app/cli/adapt_command.hpp"
#include "app/cli/devices_command.hpp"
#include "app/config/option_overrides.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "app/pipeline/smooth_pipeline.hpp"
#include "app/cli/quality_command.hpp"
#include "app/cli/transfer_command.hpp"
#include "app/pipeline/motion_pipeline.hpp"
#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "core/interrupt.hpp"
#include "core/memory_budget.hpp"
#include "io/mesh_geometry.hpp"
#include "mesh/quality.hpp"

namespace pdmesh {

namespace fs = std::filesystem;

struct QualityArguments {
  std::string mesh;
  std::optional<std::string> geometry, json, picture, view, color_by, color_range;
};

struct MeshArguments {
  std::vector<std::string> inputs;
  std::string out;
  std::vector<std::string> sets;
  std::optional<std::string> iterations, dt, cutoff, method, seed, total, device, precision, formats, r0_rule, color_by,
      stability, momentum, stop, timings, farfield, size;
  std::vector<std::string> views;
  bool tree = false;
  bool plot_spacing = false;
  bool quiet = false;
  bool check = false;
  std::int64_t max_nodes = 20'000'000;
  std::optional<std::string> max_memory;
  std::optional<std::string> resume;
  std::int64_t stop_after = 0;
  std::optional<std::string> start;       // --start: init.file
  std::vector<CaseOverride> defaults;     // keys a command sets before the user's --set (pdmesh smooth)
  std::vector<std::string> command_line;  // argv as given
};

// pdmesh smooth MESH --geometry G: the run's options are pdmesh mesh's (inputs = {G}).
struct SmoothArguments {
  MeshArguments run;
  std::string mesh;
  std::string geometry;
  std::string field = "mesh";
};

// pdmesh adapt DOMAIN --solution SOL ...: the run's options are pdmesh mesh's (inputs = {DOMAIN}).
struct AdaptArguments {
  MeshArguments run;
  std::string domain;
  AdaptOptions options;
  bool no_transfer = false;
};

namespace {

// "--formats png,svg" as the TOML array ["png", "svg"].
std::string formats_value(const std::string& list) {
  toml::array a;
  std::stringstream in(list);
  for (std::string f; std::getline(in, f, ',');) a.push_back(f);
  return toml_text(a);
}

// "--view [NAME=]x0,y0,x1,y1" as an inline table { name = ..., window = [...] }.
std::string view_value(const std::string& text) {
  std::string name, numbers = text;
  if (const auto eq = text.find('='); eq != std::string::npos) {
    name = text.substr(0, eq);
    numbers = text.substr(eq + 1);
  }
  toml::array window;
  std::stringstream in(numbers);
  for (std::string f; std::getline(in, f, ',');) {
    char* end = nullptr;
    const double v = std::strtod(f.c_str(), &end);
    if (f.empty() || end != f.c_str() + f.size()) {
      throw InputError(fmt::format("--view {}: '{}' is not a number (expected [NAME=]x0,y0,x1,y1)", text, f));
    }
    window.push_back(v);
  }
  toml::table t;
  if (!name.empty()) t.insert("name", name);
  t.insert("window", std::move(window));
  t.is_inline(true);
  return toml_text(t);
}

// "a,b,c" as exactly `count` finite numbers; errors name the option and the text.
std::vector<double> number_list(const std::string& option, const std::string& text, std::size_t count,
                                const char* expected) {
  std::vector<double> out;
  std::stringstream in(text);
  for (std::string f; std::getline(in, f, ',');) {
    char* end = nullptr;
    const double v = std::strtod(f.c_str(), &end);
    if (f.empty() || end != f.c_str() + f.size() || !std::isfinite(v)) {
      throw InputError(fmt::format("{} {}: '{}' is not a finite number (expected {})", option, text, f, expected));
    }
    out.push_back(v);
  }
  if (out.size() != count) {
    throw InputError(fmt::format("{} {}: expected {} numbers ({}), got {}", option, text, count, expected, out.size()));
  }
  return out;
}

// The `pdmesh quality --picture` options, checked before anything is read or written.
std::optional<QualityPicture> quality_picture(const QualityArguments& a) {
  if (!a.picture) {
    for (const auto* o : {&a.view, &a.color_by, &a.color_range}) {
      if (*o) throw InputError("--view, --color-by and --color-range draw a picture: give --picture FILE too");
    }
    return std::nullopt;
  }
  QualityPicture p;
  p.path = *a.picture;
  const std::string ext = fs::path(p.path).extension().string();
  if (ext != ".png" && ext != ".svg") {
    throw InputError(fmt::format("--picture {}: the file name must end in .png or .svg", p.path));
  }
  if (a.view) {
    const auto w = number_list("--view", *a.view, 4, "x0,y0,x1,y1");
    if (!(w[0] < w[2] && w[1] < w[3])) throw InputError(fmt::format("--view {}: needs x0 < x1 and y0 < y1", *a.view));
    p.window = std::array<double, 4>{w[0], w[1], w[2], w[3]};
  }
  if (a.color_by) {
    // Throws for unknown names; "region" fills by the mesh's regions.
    if (*a.color_by != "region") metric_values({}, *a.color_by == "none" ? "min_angle" : *a.color_by);
    p.color_by = *a.color_by;
  }
  if (a.color_range) {
    const auto r = number_list("--color-range", *a.color_range, 2, "LO,HI");
    if (!(r[0] < r[1])) throw InputError(fmt::format("--color-range {}: needs LO < HI", *a.color_range));
    if (p.color_by == "none" || p.color_by == "region") throw InputError("--color-range needs --color-by METRIC");
    p.color_range = std::pair<double, double>(r[0], r[1]);
  }
  return p;
}

std::vector<CaseOverride> overrides_from(const MeshArguments& a) {
  std::vector<CaseOverride> out = a.defaults;
  for (const std::string& s : a.sets) out.push_back(parse_set_option(s));
  const auto direct = [&](const std::optional<std::string>& v, const char* option, const char* key) {
    add_option_override(out, v, option, key);
  };
  direct(a.iterations, "--iterations", "simulation.iterations");
  direct(a.stop, "--stop", "simulation.stop");
  direct(a.dt, "--dt", "simulation.dt_initial");
  direct(a.cutoff, "--cutoff", "simulation.cutoff");
  direct(a.method, "--method", "init.method");
  direct(a.seed, "--seed", "init.seed");
  direct(a.total, "--total", "init.total");
  direct(a.device, "--device", "simulation.device");
  direct(a.precision, "--precision", "simulation.precision");
  direct(a.r0_rule, "--r0-rule", "simulation.r0_rule");
  direct(a.stability, "--stability", "simulation.stability_factor");
  direct(a.momentum, "--momentum", "simulation.momentum");
  direct(a.color_by, "--color-by", "output.color_by");
  if (a.start) out.push_back({"init.file", toml_string(*a.start), "--start " + *a.start});
  direct(a.size, "--size", "spacing.size");
  if (a.farfield) {
    // SHAPE:SIZE as farfield.shape and farfield.size; the validator checks both values.
    const std::string label = "--farfield " + *a.farfield;
    const auto colon = a.farfield->find(':');
    if (colon == std::string::npos)
      throw InputError(fmt::format("{}: expected SHAPE:SIZE, e.g. circle:20 or box:10", label));
    out.push_back({"farfield.shape", a.farfield->substr(0, colon), label});
    out.push_back({"farfield.size", a.farfield->substr(colon + 1), label});
  }
  if (a.formats) out.push_back({"output.formats", formats_value(*a.formats), "--formats " + *a.formats});
  if (a.tree) out.push_back({"output.tree_overlay", "true", "--tree"});
  if (a.plot_spacing) out.push_back({"output.spacing_picture", "true", "--plot-spacing"});
  for (const std::string& v : a.views) out.push_back({"output.views", view_value(v), "--view " + v, true});
  return out;
}

// Curve files, and mesh files whose cells are the domain (io/mesh_geometry.hpp).
bool is_geometry_extension(const std::string& ext) {
  return ext == ".crv" || ext == ".dat" || ext == ".poly" || ext == ".geojson" || ext == ".json" || ext == ".shp" ||
         is_mesh_geometry_extension(ext);
}

CaseConfig config_from(const MeshArguments& a) {
  std::error_code ec;
  for (const std::string& name : a.inputs) {
    if (!fs::exists(fs::path(name), ec))
      throw InputError(fmt::format("cannot read '{}': {}", name, std::strerror(ENOENT)));
  }
  fs::path input(a.inputs.front());
  // A case directory stands for the case.toml inside it.
  if (fs::is_directory(input, ec)) {
    if (!fs::is_regular_file(input / "case.toml", ec)) {
      throw InputError(fmt::format("'{}' is a directory without a case.toml", a.inputs.front()));
    }
    input /= "case.toml";
  }
  const std::vector<CaseOverride> overrides = overrides_from(a);
  const std::string ext = lower_extension(input);
  CaseConfig config;
  if (ext == ".toml") {
    if (a.inputs.size() > 1) {
      throw InputError(
          fmt::format("{}: a case file is meshed alone; '{}' would be a second input (name geometry "
                      "files in the case file's geometry.files)",
                      a.inputs.front(), a.inputs[1]));
    }
    config = load_case_file(input, overrides);
  } else if (is_geometry_extension(ext)) {
    // Several geometry files make one geometry, as geometry.files does in a case file.
    std::vector<fs::path> files;
    for (const std::string& name : a.inputs) {
      const std::string e = lower_extension(fs::path(name));
      if (!is_geometry_extension(e) || fs::is_directory(fs::path(name), ec)) {
        throw InputError(
            fmt::format("{}: expected a .crv, .dat, .poly, .geojson, .json or .shp geometry file or a .msh, .vtu, "
                        ".su2, .mesh or .ele mesh after '{}', got '{}'",
                        name, a.inputs.front(), e.empty() ? name : e));
      }
      files.emplace_back(name);
    }
    config = case_for_geometry_files(files, overrides);
  } else {
    throw InputError(
        fmt::format("{}: unknown input type '{}' (expected a case .toml, a case directory or a .crv, "
                    ".dat, .poly, .geojson, .json or .shp geometry file, or a .msh, .vtu, .su2, .mesh or .ele mesh "
                    "as the geometry)",
                    a.inputs.front(), ext));
  }
  config.out_dir = a.out;
  config.quiet = a.quiet;
  config.check = a.check;
  if (a.max_nodes < 1) throw InputError(fmt::format("--max-nodes {}: expected a node count >= 1", a.max_nodes));
  config.max_nodes = static_cast<std::uint64_t>(a.max_nodes);
  if (a.max_memory) config.max_memory = parse_memory_limit(*a.max_memory);
  if (a.resume) config.resume = fs::path(*a.resume);
  if (a.stop_after < 0)
    throw InputError(fmt::format("--stop-after {}: expected an iteration number >= 1", a.stop_after));
  config.stop_after = a.stop_after;
  config.command_line = a.command_line;
  if (a.timings) config.timings_file = fs::path(*a.timings);
  return config;
}

// The options of a run shared by pdmesh mesh and pdmesh smooth.
void add_run_options(CLI::App& mesh, MeshArguments& a) {
  mesh.add_option("--out,-o", a.out, "Output directory (created if missing)")->required()->type_name("DIR");
  mesh.add_option("--set", a.sets,
                  "Override a case-file key: section.key=VALUE (TOML value; a bare word is a string). Repeatable")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
  mesh.add_option("--iterations", a.iterations, "simulation.iterations: number of time steps (>= 0)")->type_name("N");
  mesh.add_option("--stop", a.stop,
                  "simulation.stop: converged (stop once the nodes have settled, at most --iterations) | iterations "
                  "(exactly --iterations)")
      ->type_name("RULE");
  mesh.add_option("--dt", a.dt, "simulation.dt_initial: initial global maximum time step (> 0)")->type_name("DT");
  mesh.add_option("--cutoff", a.cutoff, "simulation.cutoff: cut-off distance factor times q_i (> 0)")->type_name("F");
  mesh.add_option("--method", a.method, "init.method: structured | random | hexagonal | hybrid")->type_name("METHOD");
  mesh.add_option("--seed", a.seed, "init.seed: seed of the random fill and overloading (>= 0)")->type_name("N");
  mesh.add_option("--total", a.total, "init.total: total node count to reach by overloading (0 = off)")->type_name("N");
  mesh.add_option("--device", a.device, "simulation.device: auto | host | opencl | opencl:P:D")->type_name("DEV");
  mesh.add_option("--precision", a.precision, "simulation.precision: double | float")->type_name("P");
  mesh.add_option(
          "--r0-rule", a.r0_rule,
          "simulation.r0_rule: force_direction (thesis eq. 5.3) | any_direction (nearest neighbour limits the step)")
      ->type_name("RULE");
  mesh.add_option("--stability", a.stability,
                  "simulation.stability_factor in [0, 1]: bound each step by the local stiffness (default 1; "
                  "0 = the thesis' time step exactly, which can oscillate late in a run)")
      ->type_name("C");
  mesh.add_option("--momentum", a.momentum,
                  "simulation.momentum in [0, 1): heavy-ball beta, each move carries beta times the node's previous "
                  "one (default 0: plain gradient descent)")
      ->type_name("B");
  mesh.add_option("--farfield", a.farfield,
                  "farfield.shape and farfield.size: a closed curve named farfield around the geometry, a circle "
                  "or box of radius or half-width SIZE times its largest extent (the body becomes a hole)")
      ->type_name("SHAPE:SIZE");
  mesh.add_option("--size", a.size,
                  "spacing.size: the base field is H everywhere instead of eq. 3.6 (feature size, curvature and "
                  "gradation still refine it)")
      ->type_name("H");
  mesh.add_option("--color-by", a.color_by,
                  "output.color_by: fill mesh.png by a quality metric (none | min_angle | max_angle | aspect_ratio | "
                  "skewness | condition_number | min_jacobian) or by region, with a legend of the region names")
      ->type_name("METRIC");
  mesh.add_option("--formats", a.formats,
                  fmt::format("output.formats, comma-separated: {} (no png and no svg: no pictures at all)",
                              fmt::join(CaseConfig::Output::format_names(), ",")))
      ->type_name("LIST");
  mesh.add_option("--view", a.views,
                  "Extra zoomed picture initial_NAME.png of the window x0,y0,x1,y1 (NAME defaults to viewK). "
                  "Repeatable")
      ->type_name("[NAME=]x0,y0,x1,y1")
      ->allow_extra_args(false);
  mesh.add_flag("--tree", a.tree, "output.tree_overlay: draw the initialization tree on the initial pictures");
  mesh.add_flag(
      "--plot-spacing", a.plot_spacing,
      "output.spacing_picture: draw the final spacing field as DIR/spacing.png (log colour scale, boundary drawn)");
  mesh.add_flag("--quiet,-q", a.quiet, "No progress messages on stderr and no quality table on stdout");
  mesh.add_flag("--check", a.check,
                "Check the mesh invariants (topology, orientation, constrained Delaunay, boundary edges, area); "
                "exit 1 listing the problems if any fails");
  mesh.add_option("--max-nodes", a.max_nodes, "Refuse cases whose estimated node count exceeds this (default 20000000)")
      ->type_name("N");
  mesh.add_option("--max-memory", a.max_memory,
                  "Refuse, before allocating, a run whose stages would need more memory than this: bytes, or with "
                  "a suffix K, M, G, T (powers of 1024), e.g. 4G (default: 3/4 of the least of the RAM, ulimit -v "
                  "and the cgroup's memory.max)")
      ->type_name("SIZE");
  mesh.add_option("--timings", a.timings, "Write the wall and CPU time of every phase of the run as JSON to FILE")
      ->type_name("FILE");
}

void add_mesh_options(CLI::App& mesh, MeshArguments& a) {
  mesh.add_option("INPUT", a.inputs,
                  "Case file (.toml), case directory (holding case.toml), or one or more geometry files (.crv, .dat, "
                  ".poly, .geojson, .json, .shp, or a .msh, .vtu, .su2, .mesh or .ele mesh whose cells are the domain) "
                  "that together make one geometry, meshed with the best settings (preset = \"best\")")
      ->required()
      ->type_name("FILE...");
  add_run_options(mesh, a);
  mesh.add_option(
          "--start", a.start,
          "init.file: start warm from this node file or mesh (.nodes, .msh, .vtu, .su2, .mesh, .ele); its interior "
          "points are the initial interior nodes (pdmesh smooth: docs/smoothing.md)")
      ->type_name("FILE");
  mesh.add_option("--resume", a.resume,
                  "Continue an interrupted run from its checkpoint: DIR/checkpoint.pdmesh (or that file); the case "
                  "must be the same (--iterations may differ)")
      ->type_name("DIR");
  // Testing aid (docs/cli.md): behave as if interrupted after iteration N. Hidden from --help.
  mesh.add_option("--stop-after", a.stop_after, "")->group("")->type_name("N");
  mesh.footer(
      "Options other than --out, --quiet, --max-nodes and --max-memory override keys of the case file;\n"
      "every key can be set with --set (see docs/cli.md). Direct options are applied after --set.");
}

void add_smooth_options(CLI::App& smooth, SmoothArguments& a) {
  smooth
      .add_option(
          "MESH", a.mesh,
          "The triangle mesh to smooth: .msh (Gmsh 2.2 or 4.1), .vtu, .su2, Medit .mesh, or Triangle .ele/.node")
      ->required()
      ->type_name("FILE");
  smooth
      .add_option("--geometry,-g", a.geometry,
                  "Case file (.toml), case directory or geometry file (.crv, .dat, .poly) of the mesh's domain; "
                  "without it the mesh's own cells are the domain (docs/geometry-input.md)")
      ->type_name("FILE");
  smooth
      .add_option("--field", a.field,
                  "mesh: the spacing is the mesh's own local edge lengths (default) | case: the case's spacing field")
      ->type_name("FIELD");
  add_run_options(smooth, a.run);
  smooth.footer(
      "The run is pdmesh mesh's from the mesh's nodes (docs/smoothing.md); its options and --set keys are\n"
      "those of pdmesh mesh.");
}

void add_adapt_options(CLI::App& adapt, AdaptArguments& a) {
  adapt
      .add_option("DOMAIN", a.domain,
                  "Case file (.toml), case directory, or geometry or mesh file of the domain (SOL's own mesh too); the "
                  "case's settings are kept but for its [spacing]")
      ->required()
      ->type_name("FILE");
  adapt.add_option("--solution", a.options.solution, "spacing.file: the solution, a .vtu or .msh with point data")
      ->required()
      ->type_name("SOL");
  adapt
      .add_option("--array", a.options.arrays,
                  "spacing.array: the point array(s) of SOL to adapt to; several: their metrics intersected")
      ->required()
      ->delimiter(',')
      ->type_name("NAME[,NAME...]");
  adapt
      .add_option("--complexity", a.options.complexity,
                  "spacing.complexity: the metric's complexity C (> 0; about 1.15 C vertices)")
      ->required()
      ->type_name("C");
  adapt.add_option("--hmin", a.options.hmin, "spacing.hmin: smallest size (default 0: none)")->type_name("H");
  adapt.add_option("--hmax", a.options.hmax, "spacing.hmax: largest size (default: none)")->type_name("H");
  adapt
      .add_option("--gradation", a.options.gradation,
                  "spacing.metric_gradation: size ratio per unit metric length, in (1, 100] (default 0: off)")
      ->type_name("B");
  adapt
      .add_option("--max-anisotropy", a.options.max_anisotropy,
                  "spacing.max_anisotropy: largest ratio of a metric's two sizes (>= 1; default: none)")
      ->type_name("A");
  adapt
      .add_option("--norm", a.options.norm,
                  "spacing.norm: p of the L^p norm of the interpolation error the metric minimises (>= 1; default 2)")
      ->type_name("P");
  adapt.add_flag("--no-transfer", a.no_transfer, "Do not write DIR/solution.vtu (SOL's point data on the new mesh)");
  add_run_options(adapt, a.run);
  adapt
      .add_option("--start", a.run.start,
                  "init.file: start warm from this node file or mesh (e.g. SOL's mesh); docs/smoothing.md")
      ->type_name("FILE");
  adapt.footer(
      "The run is pdmesh mesh's on DOMAIN with spacing.field = \"hessian\" on SOL (docs/metric-fields.md);\n"
      "its options and --set keys are those of pdmesh mesh. DIR/solution.vtu holds SOL's point arrays\n"
      "interpolated onto the new mesh's points.");
}

void add_quality_options(CLI::App& quality, QualityArguments& a) {
  quality
      .add_option("MESH", a.mesh, "Mesh file: .msh (Gmsh 2.2 or 4.1), .vtu, .su2, Medit .mesh, or Triangle .ele/.node")
      ->required()
      ->type_name("FILE");
  quality
      .add_option("--geometry,-g", a.geometry,
                  "Case file or geometry file giving the desired spacing q (for spacing conformance)")
      ->type_name("FILE");
  quality.add_option("--json", a.json, "Also write the JSON summary: a file, a directory, or - for stdout")
      ->type_name("PATH");
  quality.add_option("--picture", a.picture, "Also draw the mesh: a .png or .svg file")->type_name("FILE");
  quality.add_option("--view", a.view, "Window of the picture (default: the whole mesh)")->type_name("x0,y0,x1,y1");
  quality
      .add_option("--color-by", a.color_by,
                  "Fill the picture's triangles by a metric (none | min_angle | max_angle | aspect_ratio | "
                  "skewness | condition_number | min_jacobian) or by the file's regions (region)")
      ->type_name("METRIC");
  quality
      .add_option("--color-range", a.color_range,
                  "Values at the two ends of the colour scale (default: the mesh's range), so that pictures "
                  "of different meshes compare")
      ->type_name("LO,HI");
}

void add_bench_options(CLI::App& bench, BenchArguments& a) {
  bench.add_option("--cases", a.cases, "Cases to run (graded_1m is generated in code)")->type_name("NAME...");
  bench.add_option("--cases-dir", a.cases_dir, "Directory holding the named cases")->type_name("DIR");
  bench.add_option("--iterations", a.iterations, "Iterations per case and backend")->type_name("N");
  bench.add_option("--large-iterations", a.large_iterations, "Iterations for graded_1m")->type_name("N");
  bench.add_option("--large-nodes", a.large_nodes, "Target node count of graded_1m")->type_name("N");
  bench.add_option("--precision", a.precision, "double | float (devices without fp64 run float)")->type_name("P");
  bench.add_option("--warmup", a.warmup, "Untimed iterations before timing, every backend from that state")
      ->type_name("N");
  bench.add_option("--large-warmup", a.large_warmup, "The same for graded_1m")->type_name("N");
  bench
      .add_option("--skin", a.verlet_skin,
                  "Verlet skin of the device runs (list radius cutoff q (1 + skin)); default as pdmesh mesh picks it "
                  "(the case file's simulation.verlet_skin, else by the case's node count)")
      ->type_name("S");
  bench
      .add_option("--population", a.population_every,
                  "Population control during the timed iterations: an event every K iterations (0 = off)")
      ->type_name("K");
  bench
      .add_option("--floor-repeat", a.floor_repeat,
                  "Repetitions of the pair-force floor measured at each case's node count (the table's ratio to "
                  "it; 0 = none)")
      ->type_name("N");
  bench.add_flag("--skip-host", a.skip_host, "Do not run the host reference");
  bench.add_flag("--skip-host-large", a.skip_host_large, "Do not run the host reference on graded_1m");
  bench.add_option("--force-loop", a.force_loop, "Force loop of the device runs: auto | vector | scalar")
      ->type_name("L");
  bench.add_option("--out", a.out, "Also write the table (Markdown) to this file")->type_name("FILE");
  bench
      .add_flag("--whole-run", a.whole_run,
                "Time the mesh command end to end instead: every phase, --repeat runs per case and backend, each "
                "a separate process")
      ->group("Whole runs");
  bench.add_option("--repeat", a.repeat, "Runs per case and backend (--whole-run)")
      ->type_name("N")
      ->group("Whole runs");
  bench.add_option("--backends", a.backends, "--device of the runs, e.g. host auto (--whole-run)")
      ->type_name("DEV...")
      ->group("Whole runs");
  bench.add_option("--set", a.sets, "Case key passed to every run as --set (--whole-run)")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false)
      ->group("Whole runs");
  bench.add_option("--work-dir", a.work_dir, "Where the runs write (and annulus_N cases are generated)")
      ->type_name("DIR")
      ->group("Whole runs");
  bench.add_flag("--no-pictures{false}", a.keep_pictures, "Runs write no pictures (--formats msh)")
      ->group("Whole runs");
}

SmoothField smooth_field(const std::string& name) {
  if (name == "mesh") return SmoothField::Mesh;
  if (name == "case") return SmoothField::Case;
  throw InputError(fmt::format("--field {}: expected mesh or case", name));
}

int run_smooth_command(SmoothArguments& a) {
  const SmoothField field = smooth_field(a.field);
  // Without --geometry the mesh is its own geometry, as `pdmesh mesh MESH` reads it.
  a.run.inputs = {a.geometry.empty() ? a.mesh : a.geometry};
  a.run.defaults = smooth_overrides(field);
  std::error_code ec;
  if (!fs::exists(fs::path(a.mesh), ec))
    throw InputError(fmt::format("cannot read '{}': {}", a.mesh, std::strerror(ENOENT)));
  return run_smooth(config_from(a.run), fs::path(a.mesh), field);
}

int run_adapt_command(AdaptArguments& a) {
  a.options.transfer = !a.no_transfer;
  a.run.inputs = {a.domain};
  a.run.defaults = adapt_overrides(a.options);
  const CaseConfig config = config_from(a.run);
  if (config.motion.enabled)
    throw InputError(fmt::format("{}: pdmesh adapt meshes one domain; the case has [motion]", a.domain));
  return run_adapt(config, a.options);
}

}  // namespace

Cli::Cli()
    : app_(std::make_unique<CLI::App>("pdmesh: physics-based point placement and triangle meshing", "pdmesh")),
      mesh_(std::make_unique<MeshArguments>()),
      quality_(std::make_unique<QualityArguments>()),
      bench_(std::make_unique<BenchArguments>()),
      smooth_(std::make_unique<SmoothArguments>()),
      adapt_(std::make_unique<AdaptArguments>()) {
  app_->set_version_flag("--version", std::string("pdmesh ") + PDMESH_VERSION);
  // Parse errors start like every other input error (docs/cli.md, "Exit status"), so that a script
  // or a user finds them by the same prefix.
  app_->failure_message([](const CLI::App*, const CLI::Error& e) {
    return fmt::format("pdmesh: error: {}\nRun with --help for more information.\n", e.what());
  });
  app_->require_subcommand(1);
  CLI::App* mesh = app_->add_subcommand("mesh", "Distribute nodes for a case and write them and their pictures");
  add_mesh_options(*mesh, *mesh_);
  commands_.emplace_back(mesh, [this] {
    const CaseConfig config = config_from(*mesh_);
    return config.motion.enabled ? run_motion(config) : run_mesh(config);
  });

  CLI::App* smooth =
      app_->add_subcommand("smooth", "Improve a triangle mesh made elsewhere: its nodes relaxed, its sizing kept");
  add_smooth_options(*smooth, *smooth_);
  commands_.emplace_back(smooth, [this] { return run_smooth_command(*smooth_); });

  CLI::App* adapt = app_->add_subcommand(
      "adapt", "Re-mesh a domain to a solution: the Hessian metric of its point arrays, the solution carried over");
  add_adapt_options(*adapt, *adapt_);
  commands_.emplace_back(adapt, [this] { return run_adapt_command(*adapt_); });

  CLI::App* quality = app_->add_subcommand("quality", "Print the quality table of an existing mesh file");
  add_quality_options(*quality, *quality_);
  commands_.emplace_back(quality, [this] {
    const auto picture = quality_picture(*quality_);
    return run_quality(quality_->mesh, quality_->geometry, quality_->json, picture);
  });

  CLI::App* bench =
      app_->add_subcommand("bench", "Time the simulation on the host reference and on each OpenCL device");
  add_bench_options(*bench, *bench_);
  commands_.emplace_back(bench,
                         [this] { return bench_->whole_run ? run_whole_run_bench(*bench_) : run_bench(*bench_); });

  CLI::App* transfer = app_->add_subcommand(
      "transfer", "Interpolate the point data of one mesh onto the points of another (a motion run's steps)");
  struct TransferArguments {
    std::string from, to, out;
    std::vector<std::string> arrays;
    bool quiet = false;
  };
  auto targs = std::make_shared<TransferArguments>();
  transfer->add_option("FROM", targs->from, "Mesh with the point data: .vtu or .msh")->required()->type_name("FILE");
  transfer->add_option("TO", targs->to, "Mesh whose points receive the data (any format pdmesh reads)")
      ->required()
      ->type_name("FILE");
  transfer->add_option("--out,-o", targs->out, "Output .vtu: TO with the interpolated point data")
      ->required()
      ->type_name("FILE");
  transfer->add_option("--arrays", targs->arrays, "Point arrays to transfer (default: all but kind, q and node_id)")
      ->delimiter(',')
      ->type_name("NAME,...");
  transfer->add_flag("--quiet,-q", targs->quiet, "No summary line on stderr");
  commands_.emplace_back(
      transfer, [targs] { return run_transfer(targs->from, targs->to, targs->out, targs->arrays, targs->quiet); });

  CLI::App* devices = app_->add_subcommand("devices", "List the OpenCL platforms and devices (--device opencl:P:D)");
  devices->add_flag("--check", devices_check_, "Also build and run a small kernel on each device");
  commands_.emplace_back(devices, [this] { return run_devices(devices_check_); });
}

Cli::~Cli() = default;

void Cli::parse(int argc, const char* const* argv) {
  mesh_->command_line.assign(argv, argv + argc);
  smooth_->run.command_line.assign(argv, argv + argc);
  adapt_->run.command_line.assign(argv, argv + argc);
  app_->parse(argc, argv);
}

int Cli::run() {
  for (const auto& [command, runner] : commands_) {
    if (command->parsed()) return runner();
  }
  throw Error("no command was selected");
}

int run_command_line(int argc, const char* const* argv) {
  try {
    Cli cli;
    try {
      cli.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      // --help and --version arrive here too, with exit code 0.
      return cli.app().exit(e) == 0 ? kExitOk : kExitInput;
    }
    check_environment();
    return cli.run();
  } catch (const Interrupted&) {  // a stop request outside run_mesh's own handling
    fmt::print(stderr, "pdmesh: stopped\n");
    return kExitInterrupted;
  } catch (const InputError& e) {
    fmt::print(stderr, "pdmesh: error: {}\n", e.what());
    return kExitInput;
  } catch (const Error& e) {
    fmt::print(stderr, "pdmesh: error: {}\n", e.what());
    return kExitFailure;
  } catch (const std::exception& e) {
    fmt::print(stderr, "pdmesh: internal error: {}\n", e.what());
    return kExitFailure;
  }
}

}  // namespace pdmesh
