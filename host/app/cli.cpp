// Command-line definition: `pdmesh mesh INPUT --out DIR [options]`, translating the direct options
// into case-file overrides so that one validator checks every value.
#include "app/cli.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <optional>
#include <sstream>
#include <toml++/toml.h>

#include "app/case_file.hpp"
#include "app/mesh_command.hpp"
#include "core/errors.hpp"

namespace pdmesh {

namespace fs = std::filesystem;

struct MeshArguments {
  std::string input;
  std::string out;
  std::vector<std::string> sets;
  std::optional<std::string> iterations, dt, cutoff, method, seed, total, device, precision, formats;
  std::vector<std::string> views;
  bool tree = false;
  bool quiet = false;
  std::uint64_t max_nodes = 20'000'000;
};

namespace {

std::string toml_text(const toml::node& n) {
  std::ostringstream s;
  n.visit([&](const auto& v) { s << v; });
  return s.str();
}

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

std::vector<CaseOverride> overrides_from(const MeshArguments& a) {
  std::vector<CaseOverride> out;
  for (const std::string& s : a.sets) out.push_back(parse_set_option(s));
  auto direct = [&](const std::optional<std::string>& v, const char* option, const char* key) {
    if (v) out.push_back({key, *v, fmt::format("{} {}", option, *v)});
  };
  direct(a.iterations, "--iterations", "simulation.iterations");
  direct(a.dt, "--dt", "simulation.dt_initial");
  direct(a.cutoff, "--cutoff", "simulation.cutoff");
  direct(a.method, "--method", "init.method");
  direct(a.seed, "--seed", "init.seed");
  direct(a.total, "--total", "init.total");
  direct(a.device, "--device", "simulation.device");
  direct(a.precision, "--precision", "simulation.precision");
  if (a.formats) out.push_back({"output.formats", formats_value(*a.formats), "--formats " + *a.formats});
  if (a.tree) out.push_back({"output.tree_overlay", "true", "--tree"});
  for (const std::string& v : a.views) out.push_back({"output.views", view_value(v), "--view " + v, true});
  return out;
}

std::string lower_extension(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

CaseConfig config_from(const MeshArguments& a) {
  const fs::path input(a.input);
  std::error_code ec;
  if (!fs::exists(input, ec)) {
    throw InputError(fmt::format("cannot read '{}': {}", a.input, std::strerror(ENOENT)));
  }
  const std::vector<CaseOverride> overrides = overrides_from(a);
  const std::string ext = lower_extension(input);
  CaseConfig config;
  if (ext == ".toml") {
    config = load_case_file(input, overrides);
  } else if (ext == ".crv" || ext == ".dat" || ext == ".poly") {
    config = case_for_geometry_file(input, overrides);
  } else {
    throw InputError(fmt::format("{}: unknown input type '{}' (expected a case .toml or a .crv, .dat or .poly geometry "
                                 "file)", a.input, ext));
  }
  config.out_dir = a.out;
  config.quiet = a.quiet;
  config.max_nodes = a.max_nodes;
  return config;
}

void add_mesh_options(CLI::App& mesh, MeshArguments& a) {
  mesh.add_option("INPUT", a.input, "Case file (.toml) or geometry file (.crv, .dat, .poly; default settings)")
      ->required();
  mesh.add_option("--out,-o", a.out, "Output directory (created if missing)")->required()->type_name("DIR");
  mesh.add_option("--set", a.sets,
                  "Override a case-file key: section.key=VALUE (TOML value; a bare word is a string). Repeatable")
      ->type_name("KEY=VALUE")
      ->take_all();
  mesh.add_option("--iterations", a.iterations, "simulation.iterations: number of time steps (>= 0)")->type_name("N");
  mesh.add_option("--dt", a.dt, "simulation.dt_initial: initial global maximum time step (> 0)")->type_name("DT");
  mesh.add_option("--cutoff", a.cutoff, "simulation.cutoff: cut-off distance factor times q_i (> 0)")->type_name("F");
  mesh.add_option("--method", a.method, "init.method: structured | random")->type_name("METHOD");
  mesh.add_option("--seed", a.seed, "init.seed: seed of the random fill and overloading (>= 0)")->type_name("N");
  mesh.add_option("--total", a.total, "init.total: total node count to reach by overloading (0 = off)")
      ->type_name("N");
  mesh.add_option("--device", a.device, "simulation.device: auto | host | opencl | opencl:P:D")->type_name("DEV");
  mesh.add_option("--precision", a.precision, "simulation.precision: double | float")->type_name("P");
  mesh.add_option("--formats", a.formats, "output.formats, comma-separated: msh,msh22,vtu,su2,triangle,png,svg")
      ->type_name("LIST");
  mesh.add_option("--view", a.views,
                  "Extra zoomed picture initial_NAME.png of the window x0,y0,x1,y1 (NAME defaults to viewK). "
                  "Repeatable")
      ->type_name("[NAME=]x0,y0,x1,y1")
      ->allow_extra_args(false);
  mesh.add_flag("--tree", a.tree, "output.tree_overlay: draw the initialization tree on the initial pictures");
  mesh.add_flag("--quiet,-q", a.quiet, "No progress messages on stderr");
  mesh.add_option("--max-nodes", a.max_nodes,
                  "Refuse cases whose estimated node count exceeds this (default 20000000)")
      ->type_name("N");
  mesh.footer("Options other than --out, --quiet and --max-nodes override keys of the case file; every key can be\n"
              "set with --set (see docs/cli.md). Direct options are applied after --set.");
}

}  // namespace

Cli::Cli() : app_(std::make_unique<CLI::App>("pdmesh: physics-based point placement and triangle meshing", "pdmesh")),
             mesh_(std::make_unique<MeshArguments>()) {
  app_->set_version_flag("--version", std::string("pdmesh ") + PDMESH_VERSION);
  app_->require_subcommand(1);
  CLI::App* mesh = app_->add_subcommand("mesh", "Distribute nodes for a case and write them and their pictures");
  add_mesh_options(*mesh, *mesh_);
  commands_.emplace_back(mesh, [this] { return run_mesh(config_from(*mesh_)); });
}

Cli::~Cli() = default;

void Cli::parse(int argc, const char* const* argv) { app_->parse(argc, argv); }

int Cli::run() {
  for (const auto& [command, runner] : commands_) {
    if (command->parsed()) return runner();
  }
  throw Error("no command was selected");
}

}  // namespace pdmesh
