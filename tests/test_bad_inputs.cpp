// The broken inputs of tests/data/bad (listed in its MANIFEST): each must end `pdmesh mesh` with
// exit status 2, one "pdmesh: error:" message containing the expected text, and no output directory.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "run_pdmesh.hpp"

namespace fs = std::filesystem;

namespace {

struct BadInput {
  std::string file;
  std::string expected;
};

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t");
  const auto b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

std::vector<BadInput> manifest() {
  std::ifstream in(PDMESH_SOURCE_DIR "/tests/data/bad/MANIFEST");
  std::vector<BadInput> out;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    const auto bar = line.find('|');
    if (bar == std::string::npos) continue;
    out.push_back({trim(line.substr(0, bar)), trim(line.substr(bar + 1))});
  }
  return out;
}

}  // namespace

TEST_CASE("every broken input exits 2 with a clear message and writes nothing", "[cli][bad]") {
  const auto inputs = manifest();
  REQUIRE(inputs.size() >= 18);  // the list the robustness issue asks for
  const fs::path out_root = fs::temp_directory_path() / ("pdmesh_bad_" + std::to_string(::getpid()));
  fs::remove_all(out_root);
  for (const BadInput& bad : inputs) {
    INFO(bad.file);
    const fs::path input = fs::path(PDMESH_SOURCE_DIR) / "tests/data/bad" / bad.file;
    REQUIRE(fs::exists(input));
    const fs::path out = out_root / bad.file;
    const auto r = pdmesh_test::run_pdmesh("mesh '" + input.string() + "' --out '" + out.string() + "'");
    INFO(r.output);
    CHECK(r.status == 2);
    CHECK(r.output.rfind("pdmesh: error: ", 0) == 0);               // the message comes first
    CHECK(r.output.find(bad.expected) != std::string::npos);        // and says what is wrong
    CHECK(r.output.find('\n') == r.output.size() - 1);              // on one line
    CHECK(r.output.find("terminate called") == std::string::npos);  // no library exception text
    CHECK_FALSE(fs::exists(out));                                   // nothing written
  }
  fs::remove_all(out_root);
}

TEST_CASE("an OpenCL device that is not there is refused before anything is written", "[cli][bad][opencl]") {
  const fs::path out = fs::temp_directory_path() / ("pdmesh_bad_device_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string args = "mesh '" PDMESH_SOURCE_DIR "/cases/square200' --out '" + out.string() + "' --iterations 5";
  // A device index that does not exist: exit 2, the available devices listed.
  auto r = pdmesh_test::run_pdmesh(args + " --device opencl:7:0");
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK(r.output.find("no such OpenCL device") != std::string::npos);
  CHECK(r.output.find("Available") != std::string::npos);
  CHECK_FALSE(fs::exists(out));
  // No OpenCL platform at all (the ICD loader pointed at an empty directory).
  const fs::path empty_icd = out.string() + "_icd";
  fs::create_directories(empty_icd);
  const std::string no_icd = "OCL_ICD_VENDORS='" + empty_icd.string() + "'";
  r = pdmesh_test::run_pdmesh(args + " --device opencl", no_icd);
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK(r.output.find("no OpenCL device is available") != std::string::npos);
  CHECK_FALSE(fs::exists(out));
  // auto falls back to the host reference with a notice and succeeds.
  r = pdmesh_test::run_pdmesh(args + " --device auto --formats png", no_icd + " PDMESH_TEST_AUTO_HOST_BELOW=0");
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK(r.output.find("simulating on the host reference") != std::string::npos);
  CHECK(fs::exists(out / "final.nodes"));
  fs::remove_all(out);
  fs::remove_all(empty_icd);
}
