// Checked reading of user input files, the count check and message quoting (see input_file.hpp).
#include "core/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "core/errors.hpp"

namespace pdmesh {
namespace {

constexpr std::uint64_t kMiB = 1024ull * 1024ull;
constexpr std::uint64_t kGiB = 1024ull * kMiB;

// What a file that is not a regular file is, for the message.
const char* file_type(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a named pipe (FIFO)";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

std::string size_text(std::uint64_t bytes) {
  if (bytes >= kGiB && bytes % kGiB == 0) return fmt::format("{} GiB", bytes / kGiB);
  if (bytes >= kMiB && bytes % kMiB == 0) return fmt::format("{} MiB", bytes / kMiB);
  return fmt::format("{} bytes", bytes);
}

// Closes the descriptor on every way out.
class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

}  // namespace

const char* input_noun(InputKind kind) {
  switch (kind) {
    case InputKind::Geometry:
      return "geometry file";
    case InputKind::Case:
      return "case file";
    case InputKind::Mesh:
      return "mesh file";
    case InputKind::NodeFile:
      return "node file";
    case InputKind::Checkpoint:
      return "checkpoint";
    case InputKind::Text:
      return "file";
  }
  return "file";
}

std::uint64_t input_size_limit(InputKind kind) {
  switch (kind) {
    case InputKind::Geometry:
      return kGiB;
    case InputKind::Case:
      return kMiB;
    case InputKind::Mesh:
    case InputKind::NodeFile:
    case InputKind::Checkpoint:
      return 8 * kGiB;
    case InputKind::Text:
      return kGiB;
  }
  return kGiB;
}

std::string read_input_file(const std::filesystem::path& path, InputKind kind) {
  const char* noun = input_noun(kind);
  const std::string name = path.string();
  const auto refuse = [&](const std::string& why) {
    throw InputError(fmt::format("cannot read {} '{}': {}", noun, name, why));
  };
  // stat() first: opening a named pipe blocks until a writer comes, and a device never ends.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) refuse(std::strerror(errno));
  if (!S_ISREG(st.st_mode)) refuse(fmt::format("it is {}, not a regular file", file_type(st.st_mode)));
  const std::uint64_t limit = input_size_limit(kind);
  const auto too_large = [&](std::uint64_t size) {
    refuse(fmt::format("it has {} bytes, more than the {} a {} may have (docs/robustness.md)", size, size_text(limit),
                       noun));
  };
  if (static_cast<std::uint64_t>(st.st_size) > limit) too_large(static_cast<std::uint64_t>(st.st_size));
  // Non-blocking, in case the name was replaced by a pipe since the stat(); fstat() then decides.
  const Descriptor fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY));
  if (fd.get() < 0) refuse(std::strerror(errno));
  if (::fstat(fd.get(), &st) != 0) refuse(std::strerror(errno));
  if (!S_ISREG(st.st_mode)) refuse(fmt::format("it is {}, not a regular file", file_type(st.st_mode)));
  if (static_cast<std::uint64_t>(st.st_size) > limit) too_large(static_cast<std::uint64_t>(st.st_size));

  std::string text;
  text.resize(static_cast<std::size_t>(st.st_size));
  std::size_t have = 0;
  for (;;) {
    if (have == text.size()) {
      // The file may have grown since fstat(): read on, within the limit (one byte over it tells).
      if (text.size() > limit) too_large(text.size());
      text.resize(static_cast<std::size_t>(std::min<std::uint64_t>(limit + 1, text.size() + 64 * 1024)));
    }
    const ssize_t got = ::read(fd.get(), text.data() + have, text.size() - have);
    if (got < 0) {
      if (errno == EINTR) continue;
      refuse(fmt::format("read failed after {} bytes: {}", have, std::strerror(errno)));
    }
    if (got == 0) break;
    have += static_cast<std::size_t>(got);
  }
  text.resize(have);
  return text;
}

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

void skip_utf8_bom(std::string& text) {
  if (text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
}

std::string quote_input(std::string_view text, std::size_t max_chars) {
  std::string out;
  const std::size_t shown = std::min(text.size(), max_chars);
  for (std::size_t i = 0; i < shown; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '\\') {
      out += "\\\\";
    } else if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      out += fmt::format("\\x{:02x}", static_cast<unsigned>(c));
    }
  }
  if (shown < text.size()) out += fmt::format("... ({} bytes)", text.size());
  return out;
}

void check_count_fits(std::string_view where, std::string_view what, std::uint64_t count, std::uint64_t bytes_left,
                      std::uint64_t min_bytes_each) {
  // The last item may lack its line break.
  if (min_bytes_each == 0 || count <= (bytes_left + 1) / min_bytes_each) return;
  throw InputError(
      fmt::format("{}: {} {} cannot fit in the {} bytes left in the file (each needs at least {}): the "
                  "count is wrong or the file is truncated",
                  where, what, count, bytes_left, min_bytes_each));
}

}  // namespace pdmesh
