// No surprise overwrites (docs/robustness.md): an output that would replace an input is refused
// before anything runs, naming both; a second run into an --out another run holds is refused (a lock
// on the directory, flock, which a dead process does not hold); every output path, --timings too, is checked
// writable before the work starts.
#include <catch2/catch.hpp>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "app/config/case_file.hpp"
#include "app/pipeline/output_guard.hpp"
#include "io/mesh_formats.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using pdmesh_test::run_pdmesh;
using pdmesh_test::slurp;

namespace {
const fs::path kCases = fs::path(PDMESH_SOURCE_DIR) / "cases";
}  // namespace

TEST_CASE("an output that would replace an input is refused before anything runs, naming both", "[cli][outputs]") {
  const fs::path dir = pdmesh_test::fresh_dir("guard_overwrite");
  // A geometry named like one of the Triangle outputs, meshed into its own folder.
  fs::copy_file(kCases / "corpus" / "plate" / "plate.poly", dir / "mesh.poly");
  const std::string before = slurp(dir / "mesh.poly");
  const auto r = run_pdmesh("mesh '" + (dir / "mesh.poly").string() + "' --out '" + dir.string() +
                            "' --formats triangle --iterations 5 --device host");
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Catch::Contains("would replace the input") && Catch::Contains((dir / "mesh.poly").string()));
  CHECK(slurp(dir / "mesh.poly") == before);
  CHECK(pdmesh_test::entries(dir) == 1);  // nothing written
  // --timings onto the input: refused the same way.
  const auto t =
      run_pdmesh("mesh '" + (dir / "mesh.poly").string() + "' --out '" + (dir / "out").string() +
                 "' --formats msh --iterations 5 --device host --timings '" + (dir / "mesh.poly").string() + "'");
  CHECK(t.status == 2);
  CHECK_THAT(t.output, Catch::Contains("would replace the input"));
  CHECK(slurp(dir / "mesh.poly") == before);
  CHECK_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

TEST_CASE("an unwritable --timings or --out is refused before the work starts", "[cli][outputs]") {
  const fs::path dir = pdmesh_test::fresh_dir("guard_writable");
  const std::string input = (kCases / "square200" / "square.crv").string();
  const auto t = run_pdmesh("mesh '" + input + "' --out '" + (dir / "out").string() +
                            "' --formats msh --iterations 5 --device host --timings '" +
                            (dir / "missing" / "t.json").string() + "'");
  INFO(t.output);
  CHECK(t.status == 2);
  CHECK_THAT(t.output, Catch::Contains("--timings") && Catch::Contains("missing"));
  CHECK_FALSE(fs::exists(dir / "out"));  // refused before the output directory was made
  // An output path that is a directory.
  fs::create_directories(dir / "out2" / "mesh.msh");
  const auto d = run_pdmesh("mesh '" + input + "' --out '" + (dir / "out2").string() +
                            "' --formats msh --iterations 5 --device host");
  CHECK(d.status == 2);
  CHECK_THAT(d.output, Catch::Contains("mesh.msh") && Catch::Contains("directory"));
  CHECK_FALSE(fs::exists(dir / "out2" / "initial.nodes"));
  // --out under a regular file.
  { std::ofstream(dir / "file") << "x"; }
  const auto f = run_pdmesh("mesh '" + input + "' --out '" + (dir / "file" / "out").string() +
                            "' --formats msh --iterations 5 --device host");
  CHECK(f.status == 2);
  CHECK_THAT(f.output, Catch::Contains("--out"));
  fs::remove_all(dir);
}

TEST_CASE("a second run into an --out that another run holds is refused, a released one is not", "[cli][outputs]") {
  const fs::path dir = pdmesh_test::fresh_dir("guard_lock");
  const std::string command = "mesh '" + (kCases / "square200" / "square.crv").string() + "' --out '" + dir.string() +
                              "' --formats msh --iterations 5 --device host -q";
  // This process stands for the other run: it holds the lock.
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  REQUIRE(fd >= 0);
  REQUIRE(::flock(fd, LOCK_EX | LOCK_NB) == 0);
  const auto held = run_pdmesh(command);
  INFO(held.output);
  CHECK(held.status == 2);
  CHECK_THAT(held.output, Catch::Contains("another pdmesh run") && Catch::Contains(dir.string()));
  CHECK_FALSE(fs::exists(dir / "mesh.msh"));
  // Released (as when the other run's process ended): the next run goes ahead, and leaves no lock file.
  ::close(fd);
  const auto free = run_pdmesh(command);
  INFO(free.output);
  CHECK(free.status == 0);
  CHECK(fs::exists(dir / "mesh.msh"));
  for (const auto& e : fs::directory_iterator(dir))
    CHECK(e.path().filename().string().find("lock") == std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("a run writes its OpenFOAM directory again into the same --out, not over a directory in a file's place",
          "[cli][outputs]") {
  const fs::path dir = pdmesh_test::fresh_dir("guard_openfoam");
  const std::string command = "mesh '" + (kCases / "square200" / "square.crv").string() + "' --out '" + dir.string() +
                              "' --formats openfoam --iterations 5 --device host -q";
  const fs::path points = dir / "mesh_openfoam" / "constant" / "polyMesh" / "points";
  const auto first = run_pdmesh(command);
  INFO(first.output);
  REQUIRE(first.status == 0);
  fs::remove(points);
  const auto again = run_pdmesh(command);
  INFO(again.output);
  CHECK(again.status == 0);
  CHECK(fs::exists(points));
  // A directory where a polyMesh file goes: refused before the run, naming it.
  fs::remove(points);
  fs::create_directory(points);
  const auto blocked = run_pdmesh(command);
  INFO(blocked.output);
  CHECK(blocked.status == 2);
  CHECK_THAT(blocked.output, Catch::Contains("a directory of that name exists") && Catch::Contains("points"));
  fs::remove_all(dir);
}

TEST_CASE("every file a run writes, in every output format, is one the guard checked before the run",
          "[cli][outputs]") {
  const fs::path dir = pdmesh_test::fresh_dir("guard_planned");
  const fs::path input = kCases / "square200" / "square.crv";
  // Every format (msh22 writes mesh.msh as msh does: the two cannot be asked for together).
  std::string formats;
  for (const std::string& f : pdmesh::CaseConfig::Output::format_names())
    if (f != "msh22") formats += (formats.empty() ? "" : ",") + f;
  const auto r = run_pdmesh("mesh '" + input.string() + "' --out '" + dir.string() + "' --formats " + formats +
                            " --iterations 5 --device host -q");
  INFO(r.output);
  REQUIRE(r.status == 0);
  pdmesh::CaseConfig config = pdmesh::case_for_geometry_file(input);
  config.output.formats.clear();
  for (const std::string& f : pdmesh::CaseConfig::Output::format_names())
    if (f != "msh22") config.output.formats.push_back(f);
  config.out_dir = dir;
  const std::vector<fs::path> planned = pdmesh::planned_outputs(config);
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    INFO(entry.path().string());
    // A planned file, or a directory that planned files lie in (the openfoam format's).
    const bool holds_planned = std::any_of(planned.begin(), planned.end(), [&](const fs::path& p) {
      return p.string().rfind(entry.path().string() + "/", 0) == 0;
    });
    CHECK((std::find(planned.begin(), planned.end(), entry.path()) != planned.end() || holds_planned));
    ++files;
  }
  // Each mesh format's files are there, named by its extensions.
  for (const std::string& f : pdmesh::mesh_format_names()) {
    if (f == "msh22") continue;
    for (const std::string& ext : pdmesh::mesh_format_extensions(f)) {
      INFO(f << ext);
      CHECK(fs::exists(dir / ("mesh" + ext)));
    }
  }
  CHECK(files >= 14);
  fs::remove_all(dir);
}
