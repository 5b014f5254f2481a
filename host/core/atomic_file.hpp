// Atomic output files: everything pdmesh writes goes to a temporary name in the destination's
// directory and is renamed into place only when complete, so readers never see half a file.
#pragma once
#include <filesystem>
#include <functional>
#include <string_view>

namespace pdmesh {

// Writes `content` to `path` atomically. Throws InputError naming the path and the system error.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

// For writers that create the file themselves (cairo): `write` receives a temporary path in the
// same directory and must create it; it is then renamed to `path`. If `write` throws, the
// temporary is removed and the exception propagates. Throws InputError when the temporary was not
// created or cannot be renamed.
void write_atomically(const std::filesystem::path& path,
                      const std::function<void(const std::filesystem::path& tmp)>& write);

// The temporary name used for `path`: ".NAME.tmp.PID" beside it (exposed for tests).
std::filesystem::path temporary_path_for(const std::filesystem::path& path);

// Removes the temporaries ".NAME.tmp.PID" in `dir` (not its subdirectories) whose process PID no
// longer exists: what a run killed between writing and renaming leaves behind. Returns how many.
// Those of live processes (another run writing there now) are kept.
std::size_t remove_stale_temporaries(const std::filesystem::path& dir);

// Test-only hook (docs/robustness.md): with PDMESH_TEST_STOP_BEFORE_RENAME=NAME in the environment,
// the process stops itself (SIGSTOP) after writing the temporary of the file named NAME and before
// renaming it, so that a test can kill it at exactly that point.

}  // namespace pdmesh
