// docs/geometry-input.md's error table against the command: for each row, an input that makes the
// quoted error, and `pdmesh mesh` must print the row's example message (its first `...` span, with
// "..." standing for text left out) after "pdmesh: error: ", exit 2 and write nothing.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "run_pdmesh.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;

namespace {

struct File {
  std::string name;
  // "@bad/NAME": a copy of tests/data/bad/NAME; "@link:TARGET": a symbolic link; "@size:N": N bytes,
  // sparse (the reader refuses the size before it reads a byte).
  std::string text;
};

struct Input {
  std::vector<File> files;
  std::string argument;  // the file given to `pdmesh mesh`
};

const std::string kSquare4 = "2\n0 0\n1 0\n2\n1 0\n1 1\n2\n1 1\n0 1\n2\n0 1\n0 0\n";  // four curves
const std::string kPolySquare = "4 2 0 0\n1 0 0\n2 2 0\n3 2 2\n4 0 2\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n";
const std::string kPolyTriangle = "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 2 3\n3 3 1\n0\n";

// A Gmsh 2.2 file of these points and triangles (1-based node numbers).
std::string msh22(const std::string& nodes, const std::string& triangles, int count) {
  return "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" + nodes + "$EndNodes\n$Elements\n" + std::to_string(count) +
         "\n" + triangles + "$EndElements\n";
}

Input crv(const std::string& text) { return {{{"a.crv", text}}, "a.crv"}; }
Input poly(const std::string& text) { return {{{"a.poly", text}}, "a.poly"}; }
Input json(const std::string& text) { return {{{"a.geojson", text}}, "a.geojson"}; }
Input with_case(std::vector<File> files, const std::string& toml) {
  files.push_back({"case.toml", toml});
  return {files, "case.toml"};
}

// One input per row of the table, by the row's first cell.
std::map<std::string, Input> inputs() {
  return {
      {"file cannot be opened", with_case({}, "[geometry]\nfiles = [\"a.crv\"]\n")},
      {"not a regular file (directory, device, named pipe)",
       with_case({{"z.crv", "@link:/dev/zero"}}, "[geometry]\nfiles = [\"z.crv\"]\n")},
      {"larger than 1 GiB", with_case({{"big.crv", "@size:2147483648"}}, "[geometry]\nfiles = [\"big.crv\"]\n")},
      {"unsupported extension", with_case({{"a.stl", "solid\n"}}, "[geometry]\nfiles = [\"a.stl\"]\n")},
      {"airfoil point line that is not `x y`", {{{"s.dat", "x\n1 0\n0.5 0.1\n0.5\n0 0\n"}}, "s.dat"}},
      {"airfoil of fewer than 3 distinct points", {{{"s.dat", "x\n1 0\n0 0\n1 0\n"}}, "s.dat"}},
      {"malformed JSON", {{{"a.geojson", "@bad/malformed.geojson"}}, "a.geojson"}},
      {"unknown GeoJSON type",
       json("{\"type\": \"FeatureCollection\", \"features\": [{\"type\": \"Feature\", \"properties\": {\"name\": "
            "\"c\"},\n\"geometry\": {\"type\": \"Circle\", \"coordinates\": [0, 0]}}]}\n")},
      {"bad GeoJSON position",
       json(
           "{\"type\": \"FeatureCollection\", \"features\": [\n"
           "{\"type\": \"Feature\", \"properties\": {}, \"geometry\": {\"type\": \"Point\", \"coordinates\": [0, 0]}}, "
           "{\"type\": \"Feature\", \"properties\": {}, \"geometry\": {\"type\": \"Point\", \"coordinates\": [1, "
           "0]}},\n"
           "{\"type\": \"Feature\", \"properties\": {}, \"geometry\": {\"type\": \"Point\", \"coordinates\": "
           "[1,\"a\"]}}]}\n")},
      {"ring of fewer than 3 points", json("{\"type\": \"Polygon\", \"coordinates\": [[[0,0],[1,0],[0,0]]]}\n")},
      {"GIS file of points only",
       {{{"wells.shp", "@bad/points_only.shp"}, {"wells.shx", "@bad/points_only.shx"}}, "wells.shp"}},
      {"shapefile that cannot be opened", {{{"a.shp", "@bad/points_only.shp"}}, "a.shp"}},
      {"projection of data that is not lon/lat",
       with_case({{"utm.geojson", "@bad/projection_utm.geojson"}},
                 "[geometry]\nfiles = [\"utm.geojson\"]\nprojection = \"equirectangular\"\n")},
      {"file is not text (NUL or control byte)", crv(std::string("3\n0 0\n1 0\n") + '\0' + " 1\n")},
      {"empty file / only comments", crv("# nothing\n")},
      {"count line with other text", crv("3\n0 0\n1 0\n1 1\n1 2\n0 0\n")},
      {"negative or non-integer count", crv("-3\n0 0\n")},
      {"block longer than the rest of the file", crv("2\n0 0\n1 0\n5\n0 0\n1 0\n1 1\n")},
      {"count larger than its block", crv("5\n0 0\n1 0\n1 1\n0 1\n2\n0 0\n")},
      {"extra tokens on a point line", crv("3\n0 0 0\n1 0 7 7\n0 1\n")},
      {"malformed number", crv("3\n0 0\n1 0x\n0 1\n")},
      {"NaN / infinity", crv("3\n0 0\n1 nan\n0 1\n")},
      {"absurd value (\\|v\\| > 1e150)", crv("3\n0 0\n1e308 0\n0 1\n")},
      {"`.poly` vertex count 0", poly("0 2 0 0\n")},
      {"`.poly` dimension not 2", poly("3 3 0 0\n")},
      {"`.poly` line with the wrong number of values (wrong counts)",
       poly("5 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n")},
      {"`.poly` count larger than the rest of the file", poly("99999999 2 0 0\n1 0 0\n2 1 0\n")},
      {"`.poly` section missing", poly(kPolySquare)},
      {"`.poly` index out of order / first index not 0 or 1", poly("3 2 0 0\n1 0 0\n2 1 0\n5 0 1\n")},
      {"`.poly` segment with a missing vertex", poly("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 2 9\n3 3 1\n0\n")},
      {"`.poly` degenerate segment", poly("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 3 3\n3 3 1\n0\n")},
      {"wrong number of curve names",
       with_case({{"a.crv", kSquare4}}, "[geometry]\nfiles = [\"a.crv\"]\ncurve_names = [\"a\", \"b\"]\n")},
      {"repeated / empty curve name",
       with_case({{"a.crv", kSquare4}},
                 "[geometry]\nfiles = [\"a.crv\"]\ncurve_names = [\"a\", \"b\", \"a\", \"c\"]\n")},
      {"curve with fewer than 2 points", crv("1\n0 0\n")},
      {"repeated point / zero-length segment",
       with_case({{"a.crv", "4\n0 0\n1 0\n1 0\n0 0\n"}}, "[geometry]\nfiles = [\"a.crv\"]\ncurve_names = [\"rep\"]\n")},
      {"dangling end", crv("2\n0 0\n1 0\n")},
      {"three or more ends at a point",
       with_case({{"a.crv", "# three curves\n2\n0 0\n1 0\n2\n1 0\n0 0\n2\n0 0\n0 1\n"}},
                 "[geometry]\nfiles = [\"a.crv\"]\ncurve_names = [\"a\", \"b\", \"c\"]\n")},
      {"self-intersection (also folding back)",
       with_case({{"a.crv", "5\n0 0\n2 2\n2 0\n0 2\n0 0\n"}},
                 "[geometry]\nfiles = [\"a.crv\"]\ncurve_names = [\"bow\"]\n")},
      {"two curves crossing, touching, T-junction, overlapping",
       with_case({{"a.crv", "5\n0 0\n2 0\n2 2\n0 2\n0 0\n"}, {"b.crv", "5\n1 -1\n3 -1\n3 1\n1 1\n1 -1\n"}},
                 "[geometry]\nfiles = [\"a.crv\", \"b.crv\"]\ncurve_names = [\"a\", \"b\"]\nheal = false\n")},
      {"loop of (almost) no area", {{{"thin_loop.crv", "@bad/thin_loop.crv"}}, "thin_loop.crv"}},
      {"`.poly` hole point on a segment", poly(kPolySquare + "1\n1 1 0\n")},
      {"`.poly` nothing left to mesh", poly(kPolySquare + "1\n1 1 1\n")},
      {"`.poly` malformed region line", poly(kPolyTriangle + "1\n1 0.2 0.2 x 0\n")},
      {"`.poly` region point on a segment", poly(kPolyTriangle + "1\n1 0.5 0 1 0\n")},
      {"`.poly` text after the regions", poly(kPolySquare + "0\n1\n1 0.5 0.5 1 0\nmore\n")},
      {"mesh file whose boundary pinches",
       {{{"p.msh", msh22("5\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 2 1 0\n5 2 2 0\n", "1 2 2 0 1 1 2 3\n2 2 2 0 1 3 4 5\n", 2)}},
        "p.msh"}},
      {"mesh file with an edge of three cells",
       {{{"f.msh", msh22("5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 1 1 0\n5 0.5 -1 0\n",
                         "1 2 2 0 1 1 2 3\n2 2 2 0 1 2 4 3\n3 2 2 0 1 1 5 2\n4 2 2 0 1 1 2 4\n", 4)}},
        "f.msh"}},
      {"3-D mesh file (a point off z = 0)",
       {{{"z.msh", msh22("3\n1 0 0 0\n2 1 0 0.5\n3 0 1 0\n", "1 2 2 0 1 1 2 3\n", 1)}}, "z.msh"}},
      {"mesh file with an inverted triangle",
       {{{"v.msh", msh22("4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 2 0 0\n", "1 2 2 0 1 1 2 3\n2 2 2 0 1 2 3 4\n", 2)}},
        "v.msh"}},
      {"bad options", with_case({{"a.crv", kSquare4}}, "[geometry]\nfiles = [\"a.crv\"]\njoin_tolerance = 2\n")},
  };
}

struct Row {
  std::string error;    // the first cell
  std::string example;  // the second cell's first `...` span, "\|" unescaped
};

std::vector<Row> error_table() {
  std::istringstream in(pdmesh_test::slurp(fs::path(PDMESH_SOURCE_DIR) / "docs/geometry-input.md"));
  std::vector<Row> rows;
  bool in_table = false;
  for (std::string line; std::getline(in, line);) {
    if (line == "| Error | Example message |") {
      in_table = true;
      continue;
    }
    if (!in_table) continue;
    if (line.rfind("|", 0) != 0) break;
    if (line.rfind("|---", 0) == 0) continue;
    // "| error | `example` ... |": the first cell ends at the first " | " outside backticks.
    std::size_t bar = std::string::npos;
    bool code = false;
    for (std::size_t i = 1; i + 2 < line.size(); ++i) {
      if (line[i] == '`') code = !code;
      if (!code && line.compare(i, 3, " | ") == 0) {
        bar = i;
        break;
      }
    }
    REQUIRE(bar != std::string::npos);
    Row row;
    row.error = line.substr(2, bar - 2);
    const std::size_t a = line.find('`', bar);
    const std::size_t b = line.find('`', a + 1);
    REQUIRE(b != std::string::npos);
    for (std::size_t i = a + 1; i < b; ++i) {
      if (line[i] == '\\' && i + 1 < b && line[i + 1] == '|') continue;
      row.example += line[i];
    }
    rows.push_back(row);
  }
  return rows;
}

// Whether `message` is `example` where each "..." of the example stands for any text.
bool matches(const std::string& message, const std::string& example) {
  std::vector<std::string> pieces;
  std::size_t from = 0;
  for (std::size_t at; (at = example.find("...", from)) != std::string::npos; from = at + 3)
    pieces.push_back(example.substr(from, at - from));
  pieces.push_back(example.substr(from));
  if (pieces.size() == 1) return message == example;
  if (message.rfind(pieces.front(), 0) != 0) return false;
  std::size_t at = pieces.front().size();
  for (std::size_t k = 1; k + 1 < pieces.size(); ++k) {
    at = message.find(pieces[k], at);
    if (at == std::string::npos) return false;
    at += pieces[k].size();
  }
  const std::string& last = pieces.back();
  return message.size() >= at + last.size() && message.compare(message.size() - last.size(), last.size(), last) == 0;
}

void write(const fs::path& dir, const File& f) {
  const fs::path path = dir / f.name;
  if (f.text.rfind("@size:", 0) == 0) {
    std::ofstream(path, std::ios::binary).close();
    fs::resize_file(path, std::stoull(f.text.substr(6)));
  } else if (f.text.rfind("@link:", 0) == 0) {
    fs::create_symlink(f.text.substr(6), path);
  } else if (f.text.rfind("@bad/", 0) == 0) {
    fs::copy_file(fs::path(PDMESH_SOURCE_DIR) / "tests/data/bad" / f.text.substr(5), path);
  } else {
    std::ofstream(path, std::ios::binary) << f.text;
  }
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t at = 0; (at = s.find(from, at)) != std::string::npos; at += to.size())
    s.replace(at, from.size(), to);
  return s;
}

}  // namespace

TEST_CASE("docs/geometry-input.md's error table quotes what pdmesh mesh prints", "[cli][bad][docs]") {
  const auto rows = error_table();
  REQUIRE(rows.size() >= 40);
  const auto cases = inputs();
  const fs::path root = pdmesh_test::fresh_dir("doc_errors");
  std::size_t checked = 0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Row& row = rows[k];
    INFO("row: " << row.error << "\ndoc:    " << row.example);
    const auto it = cases.find(row.error);
    // The one row without a file: a non-finite coordinate can only be built in code (the Python API).
    if (it == cases.end()) {
      CHECK(row.error == "non-finite coordinate (built in code)");
      continue;
    }
    const fs::path dir = root / std::to_string(k);
    fs::create_directories(dir);
    for (const File& f : it->second.files) write(dir, f);
    const fs::path out = dir / "out";
    const auto r =
        pdmesh_test::run_pdmesh("mesh '" + (dir / it->second.argument).string() + "' --out '" + out.string() + "' -q");
    // Paths come back as given: the directory's prefix is not part of the documented message.
    const std::string output = replace_all(r.output, dir.string() + "/", "");
    INFO("binary: " << output);
    CHECK(r.status == 2);
    REQUIRE(output.rfind("pdmesh: error: ", 0) == 0);
    const std::string message = output.substr(15, output.find('\n') - 15);
    CHECK(matches(message, row.example));
    CHECK_FALSE(fs::exists(out));
    ++checked;
  }
  CHECK(checked + 1 == rows.size());
}
