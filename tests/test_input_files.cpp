// Every reader takes regular files only, within a size limit, with a byte-order mark skipped and
// input quoted bounded and escaped in its messages (core/input_file.hpp, docs/robustness.md).
#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <sys/types.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "geometry/curve_reader.hpp"
#include "geometry/poly_reader.hpp"
#include "io/mesh_formats.hpp"
#include "nodes/node_file.hpp"
#include "run_pdmesh.hpp"
#include "sim/checkpoint.hpp"
#include "io/spacing_mesh_file.hpp"
#include "spacing/mesh_spacing.hpp"
#include "error_message.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using pdmesh::InputError;
using pdmesh::InputKind;

namespace {

void write(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
}

// Every reader of a user file, by the extension it wants.
struct Reader {
  std::string extension;
  std::function<void(const fs::path&)> read;
};

std::vector<Reader> readers() {
  return {
      {".crv", [](const fs::path& p) { pdmesh::read_curve_file(p.string()); }},
      {".poly", [](const fs::path& p) { pdmesh::read_poly_file(p.string()); }},
      {".toml", [](const fs::path& p) { pdmesh::load_case_file(p); }},
      {".msh", [](const fs::path& p) { pdmesh::read_mesh(p); }},
      {".vtu", [](const fs::path& p) { pdmesh::read_mesh(p); }},
      {".su2", [](const fs::path& p) { pdmesh::read_mesh(p); }},
      {".ele", [](const fs::path& p) { pdmesh::read_mesh(p); }},
      {".nodes", [](const fs::path& p) { pdmesh::read_node_file(p); }},
      {".pdmesh", [](const fs::path& p) { pdmesh::read_checkpoint(p); }},
      {".vtu", [](const fs::path& p) { pdmesh::load_mesh_spacing(p, "q"); }},
  };
}

}  // namespace

TEST_CASE("every reader refuses a directory, a device and a named pipe without reading it", "[input]") {
  const fs::path dir = pdmesh_test::fresh_dir("input_kinds");
  const fs::path fifo = dir / "pipe";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  for (const Reader& r : readers()) {
    INFO(r.extension);
    // Through links with the reader's extension, so the mesh readers pick their format.
    const fs::path folder = dir / ("folder" + r.extension);
    fs::create_directories(folder);
    const fs::path zero = dir / ("zero" + r.extension), random = dir / ("random" + r.extension);
    const fs::path pipe = dir / ("pipe" + r.extension);
    fs::remove(zero);
    fs::remove(random);
    fs::remove(pipe);
    fs::create_symlink("/dev/zero", zero);
    fs::create_symlink("/dev/urandom", random);
    fs::create_symlink(fifo, pipe);
    // The Triangle reader reads STEM.node first: make it the same kind of thing.
    const auto read = [&](const fs::path& p) {
      if (r.extension == ".ele") {
        fs::path node = p;
        node.replace_extension(".node");
        fs::remove_all(node);
        if (fs::is_directory(p))
          fs::create_directories(node);
        else
          fs::create_symlink(fs::read_symlink(p), node);
      }
      r.read(p);
    };
    const std::string m_dir = pdmesh_test::error_message<InputError>([&] { read(folder); });
    CHECK(m_dir.find("it is a directory, not a regular file") != std::string::npos);
    CHECK(m_dir.find((dir / "folder.").string()) != std::string::npos);
    const std::string m_zero = pdmesh_test::error_message<InputError>([&] { read(zero); });
    CHECK(m_zero.find("it is a character device, not a regular file") != std::string::npos);
    CHECK(pdmesh_test::error_message<InputError>([&] { read(random); }).find("character device") != std::string::npos);
    // Opening a pipe without a writer would block: the reader must refuse it before.
    CHECK(pdmesh_test::error_message<InputError>([&] {
            read(pipe);
          }).find("it is a named pipe (FIFO), not a regular file") != std::string::npos);
  }
}

TEST_CASE("a file larger than its kind's limit is refused by its size, before it is read", "[input]") {
  const fs::path dir = pdmesh_test::fresh_dir("input_size");
  // Sparse files: the size is what counts, no disk is used.
  for (const auto& [kind, ext] : {std::pair{InputKind::Case, ".toml"}, std::pair{InputKind::Geometry, ".crv"}}) {
    const fs::path big = dir / (std::string("big") + ext);
    write(big, "");
    fs::resize_file(big, pdmesh::input_size_limit(kind) + 1);
    const std::string m = pdmesh_test::error_message<InputError>([&] { pdmesh::read_input_file(big, kind); });
    CHECK(m.find(big.string()) != std::string::npos);
    CHECK(m.find(std::to_string(pdmesh::input_size_limit(kind) + 1) + " bytes, more than the") != std::string::npos);
    fs::resize_file(big, pdmesh::input_size_limit(kind));
    CHECK(pdmesh::read_input_file(big, kind).size() == pdmesh::input_size_limit(kind));
  }
  CHECK(pdmesh::input_size_limit(InputKind::Case) == 1024 * 1024);
  CHECK(pdmesh::input_size_limit(InputKind::Mesh) == 8ull << 30);
}

TEST_CASE("a missing or unreadable file names the file and the reason", "[input]") {
  const fs::path dir = pdmesh_test::fresh_dir("input_missing");
  CHECK(pdmesh_test::error_message<InputError>([&] {
          pdmesh::read_input_file(dir / "nope.crv", InputKind::Geometry);
        }) == "cannot read geometry file '" + (dir / "nope.crv").string() + "': No such file or directory");
}

TEST_CASE("a read that fails is an error naming the file", "[input]") {
  // /proc/self/mem is a regular file whose first page is not mapped: read() fails with EIO.
  CHECK(pdmesh_test::error_message<InputError>([] { pdmesh::read_input_file("/proc/self/mem", InputKind::Text); }) ==
        "cannot read file '/proc/self/mem': read failed after 0 bytes: Input/output error");
}

TEST_CASE("quote_input shows at most 100 characters, escaped", "[input]") {
  CHECK(pdmesh::quote_input("plain text 1.5") == "plain text 1.5");
  CHECK(pdmesh::quote_input("\xEF\xBB\xBF"
                            "4") == "\\xef\\xbb\\xbf4");
  CHECK(pdmesh::quote_input(std::string("a\0b\x1b[2J\\", 8)) == "a\\x00b\\x1b[2J\\\\");
  const std::string long_text(50'000'000, 'x');
  const std::string q = pdmesh::quote_input(long_text);
  CHECK(q == std::string(100, 'x') + "... (50000000 bytes)");
}

TEST_CASE("a UTF-8 byte-order mark at the start of a .crv or .poly file is skipped", "[input]") {
  const fs::path dir = pdmesh_test::fresh_dir("input_bom");
  const std::string bom = "\xEF\xBB\xBF";
  write(dir / "a.crv", bom + "5\n0 0\n1 0\n1 1\n0 1\n0 0\n");
  const auto curves = pdmesh::read_curve_file((dir / "a.crv").string());
  REQUIRE(curves.size() == 1);
  CHECK(curves[0].points.size() == 5);
  write(dir / "a.poly", bom + "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n");
  CHECK(pdmesh::read_poly_file((dir / "a.poly").string()).curves.size() == 1);
  // The case file too (toml++ skips it); and a mark elsewhere is still refused, visibly.
  write(dir / "case.toml", bom + "[geometry]\nfiles = [\"a.crv\"]\n");
  CHECK(pdmesh::load_case_file(dir / "case.toml").geometry.files.size() == 1);
  write(dir / "b.crv", "5\n0 0\n1 0\n" + bom + "1 1\n0 1\n0 0\n");
  CHECK(pdmesh_test::error_message<InputError>([&] {
          pdmesh::read_curve_file((dir / "b.crv").string());
        }).find("x coordinate '\\xef\\xbb\\xbf1' is not a number") != std::string::npos);
}

TEST_CASE("reader messages quote at most about 100 characters of the input, escaped", "[input]") {
  const fs::path dir = pdmesh_test::fresh_dir("input_quote");
  const std::string junk = std::string(5'000'000, 'y') + "\x01";
  // One token of 5 MB in each reader: the message stays short and shows no raw control byte.
  const std::vector<std::pair<std::string, std::string>> files{
      {"a.crv", "3\n0 0\n1 " + std::string(5'000'000, 'y') + "\n0 1\n"},
      {"a.poly", "4 2 0 0\n1 0 " + std::string(5'000'000, 'y') + "\n2 1 0\n3 1 1\n4 0 1\n"},
      {"a.msh", "$MeshFormat\n" + junk + " 0 8\n$EndMeshFormat\n"},
      {"a.su2", "NDIME= 2\n" + junk + "\n"},
      {"a.nodes", "# pdmesh nodes v1\n" + junk + "\n"},
      {"a.pdmesh", "pdmesh-checkpoint 2\niterations_done " + junk + "\n"},
      {"a.vtu", "<VTKFile type=\"" + junk + "\">\n"},
  };
  for (const auto& [name, text] : files) {
    INFO(name);
    write(dir / name, text);
    const fs::path p = dir / name;
    const std::string ext = p.extension().string();
    const std::string m = pdmesh_test::error_message<InputError>([&] {
      if (ext == ".crv")
        pdmesh::read_curve_file(p.string());
      else if (ext == ".poly")
        pdmesh::read_poly_file(p.string());
      else if (ext == ".nodes")
        pdmesh::read_node_file(p);
      else if (ext == ".pdmesh")
        pdmesh::read_checkpoint(p);
      else
        pdmesh::read_mesh(p);
    });
    CHECK(m.find(p.string()) == 0);
    CHECK(m.size() < 400);
    CHECK(m.find(std::string(100, 'y') + "...") != std::string::npos);
    CHECK(m.find('\x01') == std::string::npos);
  }
}

TEST_CASE("pdmesh mesh refuses a device, a pipe or a directory as geometry: exit 2, nothing written", "[input][cli]") {
  const fs::path dir = pdmesh_test::fresh_dir("input_cli");
  fs::create_symlink("/dev/zero", dir / "zero.crv");
  fs::create_symlink("/dev/urandom", dir / "random.poly");
  REQUIRE(::mkfifo((dir / "pipe.crv").c_str(), 0600) == 0);
  fs::create_directories(dir / "folder.crv");
  write(dir / "case.toml", "[geometry]\nfiles = [\"folder.crv\"]\n");
  write(dir / "pipe_case.toml", "[geometry]\nfiles = [\"pipe.crv\"]\n");
  // (A directory named on the command line is a case directory; named in a case file, a file.)
  for (const std::string input : {"zero.crv", "random.poly", "pipe.crv", "case.toml", "pipe_case.toml"}) {
    INFO(input);
    const fs::path out = dir / "out";
    const auto r = pdmesh_test::run_pdmesh("mesh '" + (dir / input).string() + "' --out '" + out.string() + "' -q");
    CHECK(r.status == 2);
    CHECK(r.output.find("pdmesh: error: cannot read geometry file") != std::string::npos);
    CHECK(r.output.find("not a regular file") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
  }
}
