// File helpers of the tests that write outputs: a fresh per-process temporary path or directory, a
// file's whole content, a text's lines, and the number of entries in a directory (to see that no
// temporaries are left).
#pragma once
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace pdmesh_test {

// The fresh paths this process handed out, removed when it exits: a whole suite's outputs would
// otherwise stay in the temporary directory, on a disk that CI shares.
class TempPaths {
 public:
  ~TempPaths() {
    std::error_code ignored;
    for (const auto& p : paths_) std::filesystem::remove_all(p, ignored);
  }
  void add(const std::filesystem::path& p) { paths_.push_back(p); }

 private:
  std::vector<std::filesystem::path> paths_;
};

inline TempPaths& temp_paths() {
  static TempPaths paths;
  return paths;
}

// A path in the temporary directory named after the tag and this process, removed if an earlier run
// left it (and when this process exits): for a command that must create its output folder itself,
// or write nothing there.
inline std::filesystem::path fresh_path(const std::string& tag) {
  const auto d = std::filesystem::temp_directory_path() / ("pdmesh_test_" + tag + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  temp_paths().add(d);
  return d;
}

// fresh_path(tag), created as an empty directory.
inline std::filesystem::path fresh_dir(const std::string& tag) {
  const auto d = fresh_path(tag);
  std::filesystem::create_directories(d);
  return d;
}

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

inline std::size_t entries(const std::filesystem::path& d) {
  return static_cast<std::size_t>(
      std::distance(std::filesystem::directory_iterator(d), std::filesystem::directory_iterator()));
}

}  // namespace pdmesh_test
