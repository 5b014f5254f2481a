// The per-iteration history of a simulation run (thesis fig. 6.1 data) and its CSV file.
#pragma once
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace pdmesh {

struct HistoryRow {
  int iteration = 0;             // 1 for the first iteration
  double average_force = 0.0;    // mean |F_i| over moving (Boundary + Interior) nodes, before the move
  double average_kinetic = 0.0;  // mean 1/2 |dx_i / dt_i|^2 = dt_i^2 |F_i|^2 / 8 over moving nodes
  double max_force = 0.0;        // max |F_i| over moving nodes
  double dt_gm = 0.0;            // global maximum time step used in this iteration
  std::size_t snapped = 0;       // interior nodes snapped onto a curve in this iteration
  std::size_t clamped = 0;       // boundary moves cut short at the allowed arc range
  std::size_t fixed = 0, boundary = 0, interior = 0;  // node counts by kind after the iteration
  std::size_t inserted = 0, removed = 0;              // nodes population control inserted and removed after it
};

// Header line and one line per row; numbers with 17 significant digits (round-trip exact).
std::string history_csv(const std::vector<HistoryRow>& rows);

// Writes history_csv(rows) to `path` atomically (temporary beside it, then rename).
void write_history_csv(const std::filesystem::path& path, const std::vector<HistoryRow>& rows);

}  // namespace pdmesh
