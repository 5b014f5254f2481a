// The history CSV file.
#include "sim/history.hpp"

#include <fmt/format.h>

#include "core/atomic_file.hpp"

namespace pdmesh {

std::string history_csv(const std::vector<HistoryRow>& rows) {
  std::string out =
      "iteration,average_force,average_kinetic_energy,max_force,dt_gm,snapped,clamped,fixed,boundary,interior,inserted,"
      "removed\n";
  for (const HistoryRow& r : rows)
    out += fmt::format("{},{:.17g},{:.17g},{:.17g},{:.17g},{},{},{},{},{},{},{}\n", r.iteration, r.average_force,
                       r.average_kinetic, r.max_force, r.dt_gm, r.snapped, r.clamped, r.fixed, r.boundary, r.interior,
                       r.inserted, r.removed);
  return out;
}

void write_history_csv(const std::filesystem::path& path, const std::vector<HistoryRow>& rows) {
  write_file_atomically(path, history_csv(rows));
}

}  // namespace pdmesh
