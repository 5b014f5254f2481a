// The locality measure of the neighbour rows; see row_locality.hpp.
#include "sim/row_locality.hpp"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstdio>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "sim/reference/reference_backend.hpp"

namespace pdmesh {

RowLocality row_locality(const NodeSet& nodes, double radius_factor) {
  RowLocality out;
  const std::size_t n = nodes.size();
  if (n == 0) return out;
  // The rows as the reference search builds them (sim/reference/binning.cpp), at radius_factor q_i.
  SimParticles p;
  p.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    p.x[i] = nodes.x[i].x;
    p.y[i] = nodes.x[i].y;
    p.q[i] = nodes.q[i];
    p.kind[i] = static_cast<std::uint8_t>(nodes.kind[i]);
  }
  NeighbourList list;
  NeighbourFlags flags;
  reference::build_neighbours(p, radius_factor, list, flags);
  if (flags.overflow != 0) {
    list.stride = flags.max_count;
    reference::build_neighbours(p, radius_factor, list, flags);
  }
  double sum = 0.0;
  std::uint64_t near64 = 0, near1024 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (p.kind[i] != kSimInterior) continue;
    const std::size_t base = i * static_cast<std::size_t>(list.stride);
    for (int k = 0; k < list.count[i]; ++k) {
      const double d = std::fabs(static_cast<double>(i) - static_cast<double>(list.index[base + k]));
      ++out.entries;
      sum += d;
      near64 += d <= 64.0;
      near1024 += d <= 1024.0;
    }
  }
  if (out.entries == 0) return out;
  const auto e = static_cast<double>(out.entries);
  out.mean_distance = sum / e;
  out.within_64 = static_cast<double>(near64) / e;
  out.within_1024 = static_cast<double>(near1024) / e;
  return out;
}

std::optional<double> row_locality_factor() {
  const char* value = std::getenv("PDMESH_ROW_LOCALITY");
  if (!value) return std::nullopt;
  if (*value == '\0') return 2.25;
  char* end = nullptr;
  const double factor = std::strtod(value, &end);
  if (end == value || *end != '\0' || !(factor > 0.0) || !std::isfinite(factor))
    throw InputError(
        fmt::format("the environment variable PDMESH_ROW_LOCALITY must be a positive number (a radius "
                    "in q) or empty, got '{}'",
                    quote_input(value)));
  return factor;
}

void trace_row_locality(const char* when, const NodeSet& nodes) {
  const std::optional<double> factor = row_locality_factor();
  if (!factor) return;
  const RowLocality r = row_locality(nodes, *factor);
  fmt::print(stderr,
             "row locality {}: {} nodes, {} row entries (radius {} q), mean |i - j| {:.1f}, within 64: {:.4f}, "
             "within 1024: {:.4f}\n",
             when, nodes.size(), r.entries, *factor, r.mean_distance, r.within_64, r.within_1024);
}

}  // namespace pdmesh
