// Atomic output files: write to ".NAME.tmp.PID" beside the destination, then rename(2) over it.
#include "core/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fmt/format.h>

#include "core/errors.hpp"

namespace pdmesh {

namespace fs = std::filesystem;

fs::path temporary_path_for(const fs::path& path) {
  const std::string name = fmt::format(".{}.tmp.{}", path.filename().string(), static_cast<long>(::getpid()));
  return path.parent_path() / name;
}

namespace {

// Removes the temporary unless released; keeps failed writes from leaving litter behind.
class TemporaryGuard {
 public:
  explicit TemporaryGuard(fs::path p) : path_(std::move(p)) {}
  ~TemporaryGuard() {
    if (!path_.empty()) {
      std::error_code ignored;
      fs::remove(path_, ignored);
    }
  }
  TemporaryGuard(const TemporaryGuard&) = delete;
  TemporaryGuard& operator=(const TemporaryGuard&) = delete;
  void release() { path_.clear(); }

 private:
  fs::path path_;
};

void rename_into_place(const fs::path& tmp, const fs::path& path) {
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    throw InputError(fmt::format("cannot write '{}': rename from '{}' failed: {}", path.string(),
                                 tmp.string(), std::strerror(errno)));
  }
}

}  // namespace

void write_file_atomically(const fs::path& path, std::string_view content) {
  write_atomically(path, [&](const fs::path& tmp) {
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (f == nullptr) {
      throw InputError(fmt::format("cannot write '{}': {}", path.string(), std::strerror(errno)));
    }
    const std::size_t written = content.empty() ? 0 : std::fwrite(content.data(), 1, content.size(), f);
    const int write_errno = errno;
    const bool flushed = std::fflush(f) == 0;
    const int flush_errno = errno;
    const bool closed = std::fclose(f) == 0;
    if (written != content.size() || !flushed || !closed) {
      const int e = written != content.size() ? write_errno : (!flushed ? flush_errno : errno);
      throw InputError(fmt::format("cannot write '{}': {}", path.string(), std::strerror(e)));
    }
  });
}

void write_atomically(const fs::path& path, const std::function<void(const fs::path& tmp)>& write) {
  const fs::path tmp = temporary_path_for(path);
  TemporaryGuard guard(tmp);
  write(tmp);
  std::error_code ec;
  if (!fs::is_regular_file(tmp, ec)) {
    throw InputError(fmt::format("cannot write '{}': the writer did not create '{}'", path.string(),
                                 tmp.string()));
  }
  rename_into_place(tmp, path);
  guard.release();
}

}  // namespace pdmesh
