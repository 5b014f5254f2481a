// The environment check before a command (app/config/environment.hpp): each variable with a value is
// read through its reader's parser, a malformed value is an input error naming the variable and the
// value, and the command stops before it writes anything.
#include <catch2/catch.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "app/config/environment.hpp"
#include "core/errors.hpp"
#include "opencl/measure_overlap.hpp"
#include "run_pdmesh.hpp"
#include "scoped_env.hpp"
#include "sim/row_locality.hpp"
#include "sim/step_trace.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
using pdmesh_test::fresh_path;
using pdmesh_test::ScopedEnv;

namespace fs = std::filesystem;

namespace {

// Every variable the check reads, unset for one scope so that the caller's environment does not leak in.
struct CleanEnvironment {
  ScopedEnv force_loop{"PDMESH_FORCE_LOOP", std::nullopt};
  ScopedEnv overlap{"PDMESH_MEASURE_OVERLAP", std::nullopt};
  ScopedEnv profile{"PDMESH_KERNEL_PROFILE", std::nullopt};
  ScopedEnv locality{"PDMESH_ROW_LOCALITY", std::nullopt};
  ScopedEnv trace{"PDMESH_SIM_TRACE", std::nullopt};
};

struct BadValue {
  const char* variable;
  const char* value;
  const char* message;  // a part of the error message
};

const std::vector<BadValue>& bad_values() {
  static const std::vector<BadValue> values = {
      {"PDMESH_FORCE_LOOP", "fast", "PDMESH_FORCE_LOOP must be auto, vector or scalar, got 'fast'"},
      {"PDMESH_MEASURE_OVERLAP", "off", "PDMESH_MEASURE_OVERLAP must be 0, 1 or full, got 'off'"},
      {"PDMESH_KERNEL_PROFILE", "/nonexistent-pdmesh-folder/k.tsv",
       "PDMESH_KERNEL_PROFILE names '/nonexistent-pdmesh-folder/k.tsv', whose folder '/nonexistent-pdmesh-folder' "
       "does not exist"},
      {"PDMESH_ROW_LOCALITY", "wide",
       "PDMESH_ROW_LOCALITY must be a positive number (a radius in q) or empty, got 'wide'"},
      {"PDMESH_ROW_LOCALITY", "-1", "got '-1'"},
      {"PDMESH_ROW_LOCALITY", "2.7q", "got '2.7q'"},
      {"PDMESH_SIM_TRACE", "5", "PDMESH_SIM_TRACE must be FIRST-LAST (iterations, 0 <= FIRST <= LAST), got '5'"},
      {"PDMESH_SIM_TRACE", "9-3", "got '9-3'"},
      {"PDMESH_SIM_TRACE", "1-2x", "got '1-2x'"},
  };
  return values;
}

}  // namespace

TEST_CASE("the environment check accepts every well-formed value and unset variables", "[environment]") {
  const CleanEnvironment clean;
  CHECK_NOTHROW(check_environment());
  const fs::path profile = fresh_path("environment_profile") / "k.tsv";
  fs::create_directories(profile.parent_path());
  const ScopedEnv loop("PDMESH_FORCE_LOOP", "scalar");
  const ScopedEnv overlap("PDMESH_MEASURE_OVERLAP", "full");
  const ScopedEnv kernel("PDMESH_KERNEL_PROFILE", profile.string());
  const ScopedEnv locality("PDMESH_ROW_LOCALITY", "");
  const ScopedEnv trace("PDMESH_SIM_TRACE", "3-7");
  CHECK_NOTHROW(check_environment());
  CHECK(ocl::measure_overlap(true) == ocl::MeasureOverlap::Full);
  CHECK(row_locality_factor() == 2.25);  // empty: the best preset's list radius
  const TraceRange range = TraceRange::from_environment();
  CHECK((range.first == 3 && range.last == 7));
  fs::remove_all(profile.parent_path());
}

TEST_CASE("the overlapped measurement's default depends on the device type", "[environment]") {
  const ScopedEnv unset("PDMESH_MEASURE_OVERLAP", std::nullopt);
  CHECK(ocl::measure_overlap(true) == ocl::MeasureOverlap::Off);
  CHECK(ocl::measure_overlap(false) == ocl::MeasureOverlap::On);
  const ScopedEnv off("PDMESH_MEASURE_OVERLAP", "0");
  CHECK(ocl::measure_overlap(false) == ocl::MeasureOverlap::Off);
}

TEST_CASE("a malformed environment variable is an input error naming it and its value", "[environment]") {
  for (const BadValue& bad : bad_values()) {
    const CleanEnvironment clean;
    const ScopedEnv set(bad.variable, std::string(bad.value));
    INFO(bad.variable << "=" << bad.value);
    REQUIRE_THROWS_AS(check_environment(), InputError);
    REQUIRE_THROWS_WITH(check_environment(), Catch::Contains(bad.message));
  }
  const CleanEnvironment clean;
  const fs::path folder = fresh_path("environment_profile_folder");
  fs::create_directories(folder);
  const ScopedEnv set("PDMESH_KERNEL_PROFILE", folder.string());
  REQUIRE_THROWS_WITH(check_environment(), Catch::Contains("a folder: it must name the file to write"));
  fs::remove_all(folder);
}

// The variables were read where a stage first used them: PDMESH_MEASURE_OVERLAP after initial.nodes
// and the first pictures were written, PDMESH_SIM_TRACE's malformed value ignored.
TEST_CASE("pdmesh mesh with a malformed environment variable exits 2 and writes nothing", "[environment][cli]") {
  for (const BadValue& bad : bad_values()) {
    const fs::path dir = fresh_path("environment_bad_value");
    const auto r = pdmesh_test::run_pdmesh(
        "mesh '" PDMESH_SOURCE_DIR "/cases/circle_circle/case.toml' --out '" + dir.string() + "' -q",
        std::string(bad.variable) + "='" + bad.value + "'");
    INFO(bad.variable << "=" << bad.value << "\n" << r.output);
    CHECK(r.status == 2);
    CHECK(r.output.find(bad.message) != std::string::npos);
    CHECK_FALSE(fs::exists(dir));
    fs::remove_all(dir);
  }
}
