// Fuzz entry points shared by the libFuzzer targets (tests/fuzz/fuzz_*.cpp) and the corpus-replay
// test (tests/test_fuzz_corpus.cpp): bytes -> a scratch file with the right extension -> the reader.
#pragma once
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "app/config/case_file.hpp"
#include "core/errors.hpp"
#include "geometry/curve_reader.hpp"
#include "geometry/geometry_files.hpp"
#include "geometry/poly_reader.hpp"
#include "io/medit_reader.hpp"
#include "io/mesh_formats.hpp"
#include "io/mixed_mesh.hpp"
#include "io/metric_mesh_file.hpp"
#include "nodes/node_file.hpp"
#include "sim/checkpoint.hpp"
#include "sim/simulation.hpp"
#include "io/spacing_mesh_file.hpp"
#include "spacing/mesh_spacing.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh::fuzz {

// One scratch directory per process, so that parallel fuzzers and test runs never share files;
// removed at normal exit.
class ScratchDir {
 public:
  ScratchDir() : path_(std::filesystem::temp_directory_path() / ("pdmesh_fuzz_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline const std::filesystem::path& scratch_dir() {
  static const ScratchDir dir;
  return dir.path();
}

// Writes the bytes to scratch_dir()/name (replacing it) and returns the path.
inline std::filesystem::path write_scratch(const std::string& name, std::string_view bytes) {
  const auto path = scratch_dir() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path;
}

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// Each entry runs one reader on the bytes. InputError (and its subclasses GeometryError and
// LimitError) is the documented answer to bad input and is swallowed; anything else escapes.

// .crv reader, then the same file through read_geometry so build_geometry sees what parsed.
inline void curve_reader(const std::uint8_t* data, std::size_t size) {
  const auto path = write_scratch("input.crv", as_text(data, size));
  try {
    read_curve_file(path.string());
    read_geometry({path.string()}, {});
  } catch (const InputError&) {
  }
}

// .poly reader, then read_geometry (build_geometry with hole points).
inline void poly_reader(const std::uint8_t* data, std::size_t size) {
  const auto path = write_scratch("input.poly", as_text(data, size));
  try {
    read_poly_file(path.string());
    read_geometry({path.string()}, {});
  } catch (const InputError&) {
  }
}

// case.toml: TOML syntax, keys, types and ranges (geometry files are named, not read).
inline void case_file(const std::uint8_t* data, std::size_t size) {
  const auto path = write_scratch("case.toml", as_text(data, size));
  try {
    load_case_file(path);
  } catch (const InputError&) {
  }
}

inline void node_file(const std::uint8_t* data, std::size_t size) {
  const auto path = write_scratch("input.nodes", as_text(data, size));
  try {
    read_node_file(path);
  } catch (const InputError&) {
  }
}

inline void read_mesh_file(const std::filesystem::path& path) {
  try {
    MeshReadReport report;
    read_mesh(path, report);
  } catch (const InputError&) {
  }
  // As `pdmesh quality` and Python's Mesh.read read it: the quads and the boundary-layer region too.
  try {
    MeshReadReport report;
    SurfaceCells cells;
    cells.region = kLayerRegion;
    const Mesh mesh = read_mesh(path, report, &cells);
    (void)mixed_mesh_of(mesh, cells);
  } catch (const InputError&) {
  }
  // .vtu and .msh are also background meshes of data fields: point data, binary arrays, the
  // field's checks and its point-location structure.
  const std::string ext = path.extension().string();
  if (ext != ".vtu" && ext != ".msh") return;
  try {
    const auto field = load_mesh_spacing(path, "q");
    (void)field->at({0.5, 0.5});
  } catch (const InputError&) {
  }
  // And as metric data: a 3-component array "metric" (io/metric_mesh_file).
  try {
    const auto field = make_mesh_metric_field(load_metric_mesh(path, "metric"));
    (void)field->at({0.5, 0.5});
  } catch (const InputError&) {
  }
}

// .msh: both Gmsh 2.2 and 4.1 (the reader picks the version from $MeshFormat).
inline void mesh_reader_msh(const std::uint8_t* data, std::size_t size) {
  read_mesh_file(write_scratch("input.msh", as_text(data, size)));
}

inline void mesh_reader_vtu(const std::uint8_t* data, std::size_t size) {
  read_mesh_file(write_scratch("input.vtu", as_text(data, size)));
}

inline void mesh_reader_su2(const std::uint8_t* data, std::size_t size) {
  read_mesh_file(write_scratch("input.su2", as_text(data, size)));
}

inline void mesh_reader_medit(const std::uint8_t* data, std::size_t size) {
  read_mesh_file(write_scratch("input.mesh", as_text(data, size)));
}

// Triangle needs several files: the input is split at form feeds ('\f') into STEM.node, STEM.ele
// and, when a third part is present, STEM.poly. Missing parts are empty files (or no .poly).
inline constexpr char kTriangleSeparator = '\f';
inline void mesh_reader_triangle(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = as_text(data, size);
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  while (parts.size() < 2) {
    const std::size_t cut = text.find(kTriangleSeparator, start);
    if (cut == std::string_view::npos) break;
    parts.push_back(text.substr(start, cut - start));
    start = cut + 1;
  }
  parts.push_back(text.substr(start));
  parts.resize(std::max<std::size_t>(parts.size(), 2));
  write_scratch("input.node", parts[0]);
  const auto ele = write_scratch("input.ele", parts[1]);
  const auto poly = scratch_dir() / "input.poly";
  if (parts.size() > 2) {
    write_scratch("input.poly", parts[2]);
  } else {
    std::error_code ignored;
    std::filesystem::remove(poly, ignored);
  }
  read_mesh_file(ele);
}

// Medit metric data: the input is split at the first form feed ('\f') into STEM.mesh and STEM.sol
// (an empty .sol when there is none); the pair is read, and its field built and evaluated.
inline void metric_reader_medit(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = as_text(data, size);
  const std::size_t cut = text.find('\f');
  const auto mesh = write_scratch("input.mesh", text.substr(0, cut));
  const auto sol =
      write_scratch("input.sol", cut == std::string_view::npos ? std::string_view() : text.substr(cut + 1));
  try {
    const auto field = make_mesh_metric_field(load_medit_metric(mesh, sol));
    (void)field->at({0.5, 0.5});
  } catch (const InputError&) {
  }
}

// The fixed case the checkpoint entry continues: the unit square as two curves (so that a
// checkpoint has two node lists joined at Fixed nodes), points every 0.25 along the sides (they
// become the Boundary nodes), uniform spacing 0.25. Also used by make_seeds.cpp to write the seeds,
// which then fit it.
struct CheckpointCase {
  Geometry geometry;
  std::unique_ptr<GeometryTree> tree;
  ExpressionSpacing spacing{"0.25"};
  CheckpointCase() {
    // Two sides of the square from `from` by unit steps along d1, then d2, in quarters.
    const auto sides = [](Vec2 from, Vec2 d1, Vec2 d2) {
      std::vector<Vec2> points{from};
      for (const Vec2 d : {d1, d2})
        for (int k = 1; k <= 4; ++k) points.push_back(points.back() + 0.25 * d);
      return points;
    };
    RawCurve a{"bottom_right", sides({0, 0}, {1, 0}, {0, 1}), "square", 1, {}};
    RawCurve b{"top_left", sides({1, 1}, {-1, 0}, {0, -1}), "square", 10, {}};
    geometry = build_geometry({a, b});
    tree = std::make_unique<GeometryTree>(geometry);
  }
};
inline CheckpointCase& checkpoint_case() {
  static CheckpointCase c;
  return c;
}

// Two more iterations from a checkpoint's state, as `--resume` would run them.
inline SimOptions continue_options(const Checkpoint& c) {
  SimOptions o;
  o.iterations = c.state.iterations_done + 2;
  o.quiet = true;
  o.exact_spacing = true;  // the background field would be rebuilt on every input
  o.resume = &c.state;
  return o;
}

// Checkpoint: parse_checkpoint (from memory: read_checkpoint only adds reading the file), then
// check_checkpoint_fits on checkpoint_case(), and when it fits, two iterations of the host
// simulation from it. A SimulationError from those is a documented outcome, like an InputError.
inline void checkpoint_reader(const std::uint8_t* data, std::size_t size) {
  try {
    Checkpoint c = parse_checkpoint(std::string(as_text(data, size)), "input.pdmesh");
    CheckpointCase& world = checkpoint_case();
    check_checkpoint_fits(c, *world.tree, "input.pdmesh");
    try {
      run_simulation(c.nodes, *world.tree, world.spacing, continue_options(c));
    } catch (const SimulationError&) {
    }
  } catch (const InputError&) {
  }
}

struct Target {
  const char* name;  // the corpus folder under tests/fuzz/corpus/ and tests/fuzz/regressions/
  void (*run)(const std::uint8_t*, std::size_t);
};

inline const std::vector<Target>& targets() {
  static const std::vector<Target> all{
      {"fuzz_curve_reader", curve_reader},
      {"fuzz_poly_reader", poly_reader},
      {"fuzz_case_file", case_file},
      {"fuzz_node_file", node_file},
      {"fuzz_mesh_reader_msh", mesh_reader_msh},
      {"fuzz_mesh_reader_vtu", mesh_reader_vtu},
      {"fuzz_mesh_reader_su2", mesh_reader_su2},
      {"fuzz_mesh_reader_medit", mesh_reader_medit},
      {"fuzz_mesh_reader_triangle", mesh_reader_triangle},
      {"fuzz_checkpoint", checkpoint_reader},
      {"fuzz_metric_reader_medit", metric_reader_medit},
  };
  return all;
}

}  // namespace pdmesh::fuzz
