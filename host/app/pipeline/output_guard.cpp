// Output checks and the output directory's lock; see output_guard.hpp.
#include "app/pipeline/output_guard.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <mutex>
#include <set>
#include <string>
#include <fmt/format.h>

#include "app/pipeline/resume.hpp"
#include "core/errors.hpp"
#include "io/mesh_formats.hpp"

namespace pdmesh {

namespace fs = std::filesystem;

std::vector<fs::path> planned_outputs(const CaseConfig& config) {
  std::vector<std::string> names{"initial.nodes", "final.nodes",  "mesh.nodes",
                                 "history.csv",   "quality.json", checkpoint_path("").filename().string()};
  const bool png = config.output.wants("png"), svg = config.output.wants("svg");
  for (const std::string stage : {"initial", "final", "mesh"}) {
    if (png) {
      names.push_back(stage + ".png");
      for (const ViewWindow& view : config.output.views) names.push_back(fmt::format("{}_{}.png", stage, view.name));
    }
    if (svg) names.push_back(stage + ".svg");
  }
  if (png) names.emplace_back("history.png");
  if (png && config.geometry.heal) names.emplace_back("healing.png");
  if (config.output.spacing_picture) {
    names.emplace_back("spacing.png");
    for (const ViewWindow& view : config.output.views) names.push_back(fmt::format("spacing_{}.png", view.name));
  }
  std::vector<fs::path> out;
  for (const std::string& n : names) out.push_back(config.out_dir / n);
  for (const std::string& f : config.output.formats)
    if (is_mesh_format(f))
      for (const fs::path& file : mesh_format_files(f, "mesh")) out.push_back(config.out_dir / file);
  if (config.timings_file) out.push_back(*config.timings_file);
  return out;
}

namespace {

// The files a run reads (those that exist).
std::vector<fs::path> input_files(const CaseConfig& config) {
  std::vector<fs::path> in;
  if (!config.source.empty()) in.push_back(config.source);
  for (const fs::path& f : config.geometry.files) in.push_back(f);
  if ((config.spacing.field == SpacingKind::Mesh || config.spacing.metric()) && !config.spacing.file.empty())
    in.push_back(config.spacing.file);
  if (config.spacing.metric() && !config.spacing.sol.empty()) in.push_back(config.spacing.sol);
  return in;
}

bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  return fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec) && !ec;
}

// The nearest existing folder at or above `dir` (where creating `dir` starts).
fs::path existing_ancestor(fs::path dir) {
  std::error_code ec;
  if (dir.empty()) dir = ".";
  while (!fs::exists(dir, ec)) {
    const fs::path parent = dir.has_parent_path() && dir.parent_path() != dir ? dir.parent_path() : fs::path(".");
    if (parent == dir) break;
    dir = parent;
  }
  return dir;
}

void check_writable_directory(const fs::path& dir, const std::string& what) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError(fmt::format("{}: '{}' is not a directory", what, dir.string()));
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw InputError(fmt::format("{}: cannot write in '{}': {}", what, dir.string(), std::strerror(errno)));
}

}  // namespace

void check_outputs(const CaseConfig& config) {
  if (!config.write_outputs) return;
  std::error_code ec;
  const fs::path resumed =
      config.resume ? (fs::is_directory(*config.resume, ec) ? checkpoint_path(*config.resume) : *config.resume)
                    : fs::path();
  const std::vector<fs::path> inputs = input_files(config);
  for (const fs::path& output : planned_outputs(config)) {
    if (!resumed.empty() && same_file(output, resumed)) continue;
    for (const fs::path& input : inputs)
      if (same_file(output, input))
        throw InputError(
            fmt::format("the output '{}' would replace the input '{}': choose another --out (or "
                        "--timings) for this input",
                        output.string(), input.string()));
    if (fs::is_directory(output, ec))
      throw InputError(fmt::format("cannot write the output '{}': a directory of that name exists", output.string()));
  }
  // The output directory: writable if it exists, else creatable in its nearest existing parent.
  if (fs::exists(config.out_dir, ec)) {
    check_writable_directory(config.out_dir, "--out");
  } else {
    check_writable_directory(existing_ancestor(config.out_dir), fmt::format("--out {}", config.out_dir.string()));
  }
  if (config.timings_file) {
    const fs::path parent = config.timings_file->parent_path();
    check_writable_directory(parent.empty() ? fs::path(".") : parent,
                             fmt::format("--timings {}", config.timings_file->string()));
  }
  if (fs::is_directory(config.out_dir, ec)) lock_output_directory(config.out_dir);
}

void lock_output_directory(const fs::path& dir) {
  static std::mutex mutex;
  static std::set<std::string> held;
  std::error_code ec;
  const std::string key = fs::weakly_canonical(dir, ec).string();
  const std::lock_guard lock(mutex);
  if (held.count(key)) return;
  // The directory itself is locked: nothing is added to it, and nothing is left behind to go stale.
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0)
    throw InputError(
        fmt::format("--out {}: cannot open the directory to lock it: {}", dir.string(), std::strerror(errno)));
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    ::close(fd);
    if (error == EWOULDBLOCK)
      throw InputError(
          fmt::format("--out {}: another pdmesh run is writing there (it holds the directory's lock); "
                      "wait for it to end or choose another --out",
                      dir.string()));
    throw InputError(fmt::format("--out {}: cannot lock the directory: {}", dir.string(), std::strerror(error)));
  }
  held.insert(key);  // the descriptor stays open (and locked) until the process ends
}

}  // namespace pdmesh
