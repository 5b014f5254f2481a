// The documentation's case-file snippets and key table against the case-file reader: every ```toml
// block of README.md and docs/*.md must be accepted as the user would paste it, and every key the
// reader knows must be described in docs/cli.md's key table.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "core/errors.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;

namespace {

struct Snippet {
  std::string where;  // FILE:LINE of the opening fence
  std::string text;
};

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  REQUIRE(in);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The ```toml blocks of one Markdown file.
std::vector<Snippet> toml_blocks(const fs::path& path, const std::string& label) {
  std::vector<Snippet> out;
  std::istringstream in(read_text(path));
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.rfind("```toml", 0) != 0) continue;
    Snippet s{label + ":" + std::to_string(number), ""};
    while (std::getline(in, line) && line.rfind("```", 0) != 0) {
      ++number;
      s.text += line + "\n";
    }
    ++number;
    out.push_back(s);
  }
  return out;
}

std::vector<Snippet> documented_toml() {
  const fs::path root = PDMESH_SOURCE_DIR;
  std::vector<fs::path> files = {root / "README.md"};
  for (const auto& e : fs::directory_iterator(root / "docs"))
    if (e.path().extension() == ".md") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::vector<Snippet> out;
  for (const fs::path& f : files) {
    const auto blocks = toml_blocks(f, fs::relative(f, root).string());
    out.insert(out.end(), blocks.begin(), blocks.end());
  }
  return out;
}

}  // namespace

TEST_CASE("every toml block of the documentation is a case file the reader accepts", "[app][case][docs]") {
  const auto snippets = documented_toml();
  // README's full example, boundary layers, metric and Hessian fields, motion, far field.
  REQUIRE(snippets.size() >= 7);
  for (const Snippet& s : snippets) {
    INFO(s.where << ":\n" << s.text);
    // Most blocks show one section; the geometry comes from the user's own case, as --set gives it.
    std::vector<CaseOverride> overrides;
    if (s.text.find("files = ") == std::string::npos)
      overrides.push_back(parse_set_option("geometry.files=[\"a.crv\"]"));
    std::string error;
    try {
      parse_case_text(s.text, fs::path("/docs/case.toml"), overrides);
    } catch (const InputError& e) {
      error = e.what();
    }
    CHECK(error == "");
  }
}

TEST_CASE("every case-file key is described in docs/cli.md", "[app][case][docs]") {
  // The keys a row of a table names in its first cell: "| `spacing.h1`, `spacing.h2` | ...".
  std::vector<std::string> described;
  std::istringstream in(read_text(fs::path(PDMESH_SOURCE_DIR) / "docs/cli.md"));
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("| `", 0) != 0) continue;
    const std::string cell = line.substr(0, line.find(" |", 1));
    for (std::size_t a = cell.find('`'); a != std::string::npos; a = cell.find('`', a + 1)) {
      const std::size_t b = cell.find('`', a + 1);
      if (b == std::string::npos) break;
      described.push_back(cell.substr(a + 1, b - a - 1));
      a = b;
    }
  }
  const auto has = [&](const std::string& k) {
    return std::find(described.begin(), described.end(), k) != described.end();
  };
  const auto& keys = case_file_keys();
  REQUIRE(keys.size() > 50);
  for (const std::string& key : keys) {
    INFO(key);
    // A sub-key (simulation.dt_initial.random) is described in its parent's row.
    const std::size_t dot = key.rfind('.');
    CHECK((has(key) || (dot != std::string::npos && has(key.substr(0, dot)))));
  }
}
