// Checks of `pdmesh mesh`'s outputs before any work: no output may replace an input, every output
// path must be writable, and the output directory is this run's alone while it runs (a lock).
#pragma once
#include <filesystem>
#include <vector>

#include "app/config/case_file.hpp"

namespace pdmesh {

// Every file a run of `config` may write (the formats, views and pictures it asks for), in out_dir
// (or, for the openfoam format, in the directories below it that it makes), and the --timings file.
std::vector<std::filesystem::path> planned_outputs(const CaseConfig& config);

// Before anything runs: throws InputError (exit 2) naming both paths when an output would replace
// an input (the case file, a geometry file, a spacing mesh file; not the checkpoint of --resume,
// which a run rewrites by design), naming the path when an output cannot be written (the output
// directory cannot be created or written, an output path is a directory, the --timings file's
// directory is missing or not writable). Then locks out_dir when it exists
// (lock_output_directory). Nothing is written when config.write_outputs is false.
void check_outputs(const CaseConfig& config);

// Locks the directory DIR itself (flock on the directory, exclusive, held until the process ends;
// the kernel drops it with the process, so a killed run leaves no lock behind, and no lock file is
// added to DIR). Throws InputError when
// another process holds it: a second run into the same directory would mix its files with the
// first's. Taking it again in the same process does nothing.
void lock_output_directory(const std::filesystem::path& dir);

}  // namespace pdmesh
