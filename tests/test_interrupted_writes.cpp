// A run killed while it writes its outputs (issue #7): every output under its final name is whole —
// the previous run's file or the new one, never a mix or a truncation — and the temporary the killed
// run left is removed by the next run. The kill lands exactly between write and rename through the
// test-only hook PDMESH_TEST_STOP_BEFORE_RENAME (core/atomic_file.hpp).
#include <catch2/catch.hpp>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <map>
#include <string>

#include "core/atomic_file.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using pdmesh_test::slurp;

namespace {

const std::string kCase = PDMESH_SOURCE_DIR "/cases/circle_circle";

// Every file under its final name (no leading dot) and its bytes.
std::map<std::string, std::string> outputs(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name[0] != '.') files[name] = slurp(e.path());
  }
  return files;
}

std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string()[0] == '.') names.push_back(e.path().filename().string());
  return names;
}

std::string arguments(const fs::path& dir, int iterations) {
  return "mesh '" + kCase + "' --out '" + dir.string() + "' --device host --formats msh,vtu --iterations " +
         std::to_string(iterations);
}

}  // namespace

TEST_CASE("SIGKILL between writing and renaming mesh.msh leaves every output whole", "[atomic][cli][signal]") {
  const fs::path dir = pdmesh_test::fresh_dir("killed_write"), reference = pdmesh_test::fresh_dir("killed_ref");
  // The previous run's outputs (5 iterations), and what the new run (9 iterations) writes when left alone.
  REQUIRE(pdmesh_test::run_pdmesh(arguments(dir, 5) + " -q").status == 0);
  REQUIRE(pdmesh_test::run_pdmesh(arguments(reference, 9) + " -q").status == 0);
  const auto old_files = outputs(dir), new_files = outputs(reference);
  REQUIRE(old_files.size() == new_files.size());
  REQUIRE(old_files.count("mesh.msh") == 1);
  REQUIRE(old_files.at("mesh.msh") != new_files.at("mesh.msh"));
  REQUIRE(old_files.at("final.nodes") != new_files.at("final.nodes"));

  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, STDOUT_FILENO);
    ::dup2(null, STDERR_FILENO);
    ::setenv("PDMESH_TEST_STOP_BEFORE_RENAME", "mesh.msh", 1);
    const std::string out = dir.string();
    ::execl(PDMESH_BINARY, PDMESH_BINARY, "mesh", kCase.c_str(), "--out", out.c_str(), "--device", "host", "--formats",
            "msh,vtu", "--iterations", "9", "-q", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  REQUIRE(::waitpid(pid, &status, WUNTRACED) == pid);
  REQUIRE(WIFSTOPPED(status));  // stopped itself with mesh.msh written under its temporary name
  const fs::path tmp = dir / (".mesh.msh.tmp." + std::to_string(pid));
  CHECK(slurp(tmp) == new_files.at("mesh.msh"));
  REQUIRE(::kill(pid, SIGKILL) == 0);
  REQUIRE(::waitpid(pid, &status, 0) == pid);
  CHECK(WIFSIGNALED(status));

  // Every final name holds a whole file: the new one where the run got that far, else the old one.
  const auto after = outputs(dir);
  CHECK(after.size() == old_files.size());
  for (const auto& [name, bytes] : after) {
    INFO(name);
    CHECK((bytes == old_files.at(name) || bytes == new_files.at(name)));
  }
  CHECK(after.at("mesh.msh") == old_files.at("mesh.msh"));        // killed before its rename
  CHECK(after.at("final.nodes") == new_files.at("final.nodes"));  // written before mesh.msh
  CHECK(after.at("history.csv") == new_files.at("history.csv"));
  CHECK(temporaries(dir) == std::vector<std::string>{tmp.filename().string()});

  // The next run removes the dead run's temporary and writes everything anew.
  const auto next = pdmesh_test::run_pdmesh(arguments(dir, 9));
  INFO(next.output);
  CHECK(next.status == 0);
  CHECK_THAT(next.output, Catch::Contains("removed 1 temporary file(s)"));
  CHECK(temporaries(dir).empty());
  CHECK(outputs(dir) == new_files);
  fs::remove_all(dir);
  fs::remove_all(reference);
}

TEST_CASE("stale temporaries: only those of processes that are gone are removed", "[atomic]") {
  const fs::path dir = pdmesh_test::fresh_dir("stale_tmp");
  // A process that has exited (and been reaped): its pid is free.
  const pid_t gone = ::fork();
  REQUIRE(gone >= 0);
  if (gone == 0) ::_exit(0);
  REQUIRE(::waitpid(gone, nullptr, 0) == gone);
  const auto touch = [&](const std::string& name) { pdmesh::write_file_atomically(dir / name, "x"); };
  touch(".mesh.msh.tmp." + std::to_string(gone));           // dead writer: removed
  touch(".final.nodes.tmp." + std::to_string(::getpid()));  // this process: kept
  touch(".history.csv.tmp.1");                              // pid 1 exists: kept
  touch("mesh.tmp.12345678");                               // not a temporary's name: kept
  touch(".notes.tmp.12x");                                  // not a pid: kept
  CHECK(pdmesh::remove_stale_temporaries(dir) == 1);
  CHECK_FALSE(fs::exists(dir / (".mesh.msh.tmp." + std::to_string(gone))));
  CHECK(pdmesh_test::entries(dir) == 4);
  CHECK(pdmesh::remove_stale_temporaries(dir) == 0);
  fs::remove_all(dir);
}
