// Checkpoints of `pdmesh mesh` (docs/checkpoint.md): where they live, and the case identity that a
// resumed run compares against the checkpoint's before continuing.
#pragma once
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "app/config/case_file.hpp"
#include "sim/checkpoint.hpp"

namespace pdmesh {

// DIR/checkpoint.pdmesh.
std::filesystem::path checkpoint_path(const std::filesystem::path& dir);

// The settings that determine the node placement (geometry file names and content hashes, spacing,
// init and simulation settings except iterations, device and precision), as checkpoint case keys.
std::vector<std::pair<std::string, std::string>> case_identity(const CaseConfig& config);

// Reads the checkpoint named by --resume (a directory holding checkpoint.pdmesh, or the file) and
// checks that it belongs to `config`'s case (InputError naming the first key that differs) and that
// its state fits the case's geometry (check_checkpoint_fits).
Checkpoint read_checkpoint_for(const std::filesystem::path& resume, const CaseConfig& config, const GeometryTree& tree);

}  // namespace pdmesh
