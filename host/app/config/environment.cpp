// The environment check before a command; see environment.hpp.
#include "app/config/environment.hpp"

#include <cstdlib>
#include <filesystem>
#include <system_error>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "opencl/measure_overlap.hpp"
#include "opencl/step_program.hpp"
#include "sim/row_locality.hpp"
#include "sim/step_trace.hpp"

namespace pdmesh {
namespace {

// The kernel profile is written at exit (opencl/kernel_profile): a folder that does not exist would
// lose it silently after the whole run.
void check_kernel_profile_file() {
  const char* v = std::getenv("PDMESH_KERNEL_PROFILE");
  if (v == nullptr || *v == '\0') return;
  const std::filesystem::path file(v);
  const std::filesystem::path folder = file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec))
    throw InputError(
        fmt::format("the environment variable PDMESH_KERNEL_PROFILE names '{}', whose folder '{}' does "
                    "not exist",
                    quote_input(v), quote_input(folder.string())));
  if (std::filesystem::is_directory(file, ec))
    throw InputError(fmt::format(
        "the environment variable PDMESH_KERNEL_PROFILE names '{}', a folder: it must name the file to write",
        quote_input(v)));
}

}  // namespace

void check_environment() {
  if (const char* v = std::getenv("PDMESH_FORCE_LOOP"))
    ocl::parse_force_loop(v, "the environment variable PDMESH_FORCE_LOOP");
  ocl::measure_overlap(false);
  check_kernel_profile_file();
  row_locality_factor();
  TraceRange::from_environment();
}

}  // namespace pdmesh
