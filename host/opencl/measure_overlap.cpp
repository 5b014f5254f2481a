// The overlapped measurement's mode; see measure_overlap.hpp.
#include "opencl/measure_overlap.hpp"

#include <cstdlib>
#include <string_view>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"

namespace pdmesh::ocl {

MeasureOverlap measure_overlap(bool cpu_device) {
  const char* v = std::getenv("PDMESH_MEASURE_OVERLAP");
  if (!v) return cpu_device ? MeasureOverlap::Off : MeasureOverlap::On;
  const std::string_view text(v);
  if (text == "0") return MeasureOverlap::Off;
  if (text == "1") return MeasureOverlap::On;
  if (text == "full") return MeasureOverlap::Full;
  throw InputError(
      fmt::format("the environment variable PDMESH_MEASURE_OVERLAP must be 0, 1 or full, got '{}'", quote_input(text)));
}

}  // namespace pdmesh::ocl
