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

}  // namespace pdmesh
