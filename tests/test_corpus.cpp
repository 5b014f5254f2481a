// The evaluation corpus (cases/corpus/, written by tools/cases/make_corpus.py): every case names only its
// geometry, curve names and views (so it runs with the best defaults), and every geometry is valid
// and meshes in a short host run. Label `cases-corpus` (ctest -L corpus; whole-case runs, so the
// sanitizer pass of CI, -LE cases, leaves it out).
#include <catch2/catch.hpp>

#include <toml++/toml.h>

#include <algorithm>
#include <filesystem>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "run_pdmesh.hpp"
#include "temp_files.hpp"

namespace {

const std::filesystem::path kCorpus = std::filesystem::path(PDMESH_SOURCE_DIR) / "cases" / "corpus";

std::vector<std::string> corpus_cases() {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(kCorpus)) {
    if (entry.is_directory() && std::filesystem::exists(entry.path() / "case.toml")) {
      names.push_back(entry.path().filename().string());
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

TEST_CASE("corpus cases name only geometry, curve names and views", "[corpus]") {
  const auto names = corpus_cases();
  REQUIRE(names.size() >= 6);
  const std::set<std::string> allowed = {"name", "geometry", "output"};
  for (const auto& name : names) {
    INFO("case " << name);
    const toml::table config = toml::parse_file((kCorpus / name / "case.toml").string());
    for (const auto& [key, value] : config) CHECK(allowed.count(std::string(key.str())) == 1);
    CHECK(config["name"].value<std::string>() == name);
    const auto* geometry = config["geometry"].as_table();
    REQUIRE(geometry != nullptr);
    for (const auto& [key, value] : *geometry) CHECK((key.str() == "files" || key.str() == "curve_names"));
    const auto* output = config["output"].as_table();
    REQUIRE(output != nullptr);
    for (const auto& [key, value] : *output) CHECK(key.str() == "views");
    const auto* views = config["output"]["views"].as_array();
    REQUIRE(views != nullptr);
    CHECK(views->size() >= 3);
  }
}

TEST_CASE("every corpus geometry is valid and meshes", "[corpus]") {
  const auto dir = pdmesh_test::fresh_dir("corpus");
  // The corpus is meant to run in seconds: a few thousand to a few tens of thousands of nodes.
  const std::regex initial(R"(initial distribution: (\d+) nodes)");
  for (const auto& name : corpus_cases()) {
    INFO("case " << name);
    const auto out = dir / name;
    const auto r = pdmesh_test::run_pdmesh("mesh '" + (kCorpus / name).string() + "' --out '" + out.string() +
                                           "' --iterations 20 --formats msh --device host --check");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(std::filesystem::file_size(out / "mesh.msh") > 0);
    std::smatch m;
    REQUIRE(std::regex_search(r.output, m, initial));
    const long nodes = std::stol(m[1].str());
    CHECK(nodes >= 1000);
    CHECK(nodes <= 100000);
  }
  std::filesystem::remove_all(dir);
}
