// The history plot (thesis fig. 6.1): average |F| (red) and average kinetic energy (blue) per
// iteration, logarithmic y axis, written as a PNG.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "sim/history.hpp"

namespace pdmesh {

// Writes the plot to `path` atomically. Non-positive values (log scale) break the lines.
// Throws InputError when the file cannot be written.
void write_history_plot(const std::filesystem::path& path, const std::vector<HistoryRow>& rows,
                        const std::string& title);

}  // namespace pdmesh
