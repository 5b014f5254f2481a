// Atomic output files: write to ".NAME.tmp.PID" beside the destination, then rename(2) over it.
#include "core/atomic_file.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/interrupt.hpp"

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
    throw InputError(fmt::format("cannot write '{}': rename from '{}' failed: {}", path.string(), tmp.string(),
                                 std::strerror(errno)));
  }
}

}  // namespace

void write_file_atomically(const fs::path& path, std::string_view content) {
  write_atomically(path, [&](const fs::path& tmp) {
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (f == nullptr) {
      throw InputError(fmt::format("cannot write '{}': {}", path.string(), std::strerror(errno)));
    }
    // In pieces, so that a stop request (core/interrupt) ends a write of hundreds of megabytes within
    // a fraction of a second: the temporary is then removed (write_atomically).
    constexpr std::size_t kPiece = std::size_t{8} << 20;
    std::size_t written = 0;
    while (written < content.size()) {
      if (interrupt_requested()) {
        std::fclose(f);
        throw_interrupted();
      }
      const std::size_t piece = std::min(kPiece, content.size() - written);
      const std::size_t n = std::fwrite(content.data() + written, 1, piece, f);
      written += n;
      if (n != piece) break;
    }
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
    throw InputError(fmt::format("cannot write '{}': the writer did not create '{}'", path.string(), tmp.string()));
  }
  if (const char* stop = std::getenv("PDMESH_TEST_STOP_BEFORE_RENAME"); stop && path.filename() == stop)
    ::raise(SIGSTOP);
  rename_into_place(tmp, path);
  guard.release();
}

std::size_t remove_stale_temporaries(const fs::path& dir) {
  std::size_t removed = 0;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    // ".NAME.tmp.PID": a leading dot, and digits after the last ".tmp.".
    const std::size_t mark = name.rfind(".tmp.");
    if (name.size() < 2 || name[0] != '.' || mark == std::string::npos || mark == 0) continue;
    const std::string digits = name.substr(mark + 5);
    if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    const auto pid = static_cast<pid_t>(std::stol(digits));
    if (pid == ::getpid() || pid <= 0) continue;
    // kill(pid, 0) fails with ESRCH only when no such process exists (EPERM: it exists).
    if (::kill(pid, 0) == 0 || errno != ESRCH) continue;
    std::error_code ignored;
    if (entry.is_regular_file(ignored) && fs::remove(entry.path(), ignored)) ++removed;
  }
  return removed;
}

}  // namespace pdmesh
