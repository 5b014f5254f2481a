// The adapt command (adapt_command.hpp).
#include "app/cli/adapt_command.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/pipeline/exit_codes.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "io/point_data_file.hpp"

namespace pdmesh {

namespace fs = std::filesystem;

int run_adapt(const CaseConfig& config, const AdaptOptions& options) {
  const fs::path solution = config.spacing.file;
  std::error_code ec;
  if (!fs::is_regular_file(solution, ec))
    throw InputError(fmt::format("--solution {}: cannot read '{}': no such file", options.solution, solution.string()));
  const std::vector<std::string> present = point_array_names(solution.string());
  for (const std::string& name : options.arrays)
    if (std::find(present.begin(), present.end(), name) == present.end())
      throw InputError(fmt::format("--array {}: {} has no point array '{}' (point arrays: {})", name, options.solution,
                                   name, present.empty() ? "none" : fmt::format("{}", fmt::join(present, ", "))));
  const std::optional<fs::path> mesh_file = adapted_mesh_file(config);
  const fs::path out = adapted_solution_path(config);
  if (options.transfer) {
    if (!mesh_file)
      throw InputError(fmt::format(
          "output.formats = [{}] writes no mesh file (msh, msh22, vtu, su2, mesh or triangle) for solution.vtu to "
          "follow: add one, or give --no-transfer",
          fmt::join(config.output.formats, ", ")));
    if (fs::equivalent(solution, out, ec))
      throw InputError(fmt::format("--solution {} is {}, which this run writes: give another --out", options.solution,
                                   out.string()));
  }
  const int status = run_mesh(config);
  if (status != kExitOk || !options.transfer) return status;
  const AdaptedSolution a = write_adapted_solution(config, solution.string(), *mesh_file);
  if (!config.quiet)
    fmt::print(stderr,
               "adapt: {} from {} ({} points) onto {} ({} points; {} outside the old mesh, at most {:.3g} away): "
               "wrote {}\n",
               fmt::join(a.moved.names, ", "), options.solution, a.moved.source_points, mesh_file->string(),
               a.target.points.size(), a.counts.outside, a.counts.max_distance, out.string());
  return status;
}

}  // namespace pdmesh
