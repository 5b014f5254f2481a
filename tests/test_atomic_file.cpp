// Tests of the atomic file writers: content arrives whole, temporaries never remain.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;

namespace {

fs::path fresh_dir(const std::string& tag) { return pdmesh_test::fresh_dir("atomic_" + tag); }
using pdmesh_test::entries;
using pdmesh_test::slurp;

}  // namespace

TEST_CASE("write_file_atomically writes and replaces content", "[atomic]") {
  const fs::path d = fresh_dir("replace");
  const fs::path f = d / "out.txt";
  write_file_atomically(f, "first version\n");
  CHECK(slurp(f) == "first version\n");
  std::string binary("a\0b\xff", 4);
  write_file_atomically(f, binary);
  CHECK(slurp(f) == binary);
  write_file_atomically(d / "empty", "");
  CHECK(fs::file_size(d / "empty") == 0);
  CHECK(entries(d) == 2);
  fs::remove_all(d);
}

TEST_CASE("write_file_atomically names the path when the directory is missing", "[atomic]") {
  const fs::path d = fresh_dir("missing");
  const fs::path f = d / "no" / "such" / "out.txt";
  try {
    write_file_atomically(f, "x");
    FAIL("expected InputError");
  } catch (const InputError& e) {
    const std::string m = e.what();
    CHECK(m.find(f.string()) != std::string::npos);
    CHECK(m.find("No such file or directory") != std::string::npos);
  }
  fs::remove_all(d);
}

TEST_CASE("write_atomically removes the temporary when the writer throws", "[atomic]") {
  const fs::path d = fresh_dir("throw");
  const fs::path f = d / "picture.png";
  write_file_atomically(f, "old");
  CHECK_THROWS_AS(write_atomically(f,
                                   [](const fs::path& tmp) {
                                     std::ofstream(tmp) << "half a file";
                                     throw std::runtime_error("writer failed");
                                   }),
                  std::runtime_error);
  CHECK(slurp(f) == "old");  // the previous complete file survives
  CHECK(entries(d) == 1);
  CHECK_FALSE(fs::exists(temporary_path_for(f)));
  fs::remove_all(d);
}

TEST_CASE("write_atomically uses a hidden temporary beside the target", "[atomic]") {
  const fs::path d = fresh_dir("tmpname");
  const fs::path f = d / "x.svg";
  fs::path seen;
  write_atomically(f, [&](const fs::path& tmp) {
    seen = tmp;
    std::ofstream(tmp) << "<svg/>";
  });
  CHECK(seen.parent_path() == d);
  CHECK(seen.filename().string().rfind(".x.svg.tmp.", 0) == 0);
  CHECK(slurp(f) == "<svg/>");
  CHECK_THROWS_AS(write_atomically(d / "y", [](const fs::path&) {}), InputError);
  CHECK_FALSE(fs::exists(d / "y"));
  fs::remove_all(d);
}
