// Writes the seed corpora of the mesh, node-file and checkpoint fuzz targets with pdmesh's own writers:
// fuzz_make_seeds CORPUS_DIR (normally tests/fuzz/corpus). Geometry and case seeds are copied
// from tests/data/ and cases/ by hand; see docs/robustness.md.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/errors.hpp"
#include "fuzz_entries.hpp"
#include "init/initial_distribution.hpp"
#include "io/medit_writer.hpp"
#include "io/mesh_formats.hpp"
#include "io/mixed_mesh.hpp"
#include "mesh/mesh.hpp"
#include "nodes/node_file.hpp"
#include "../temp_files.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;

namespace {

using pdmesh_test::slurp;

void put(const fs::path& path, const std::string& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << bytes;
  std::printf("%s (%zu bytes)\n", path.string().c_str(), bytes.size());
}

// The unit square cut into four triangles around its centre; two boundary curves, one of
// them with a blank and a quote in its name (writers must escape it).
Mesh small_mesh() {
  Mesh m;
  m.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0.5}};
  m.triangles = {{{0, 1, 4}}, {{1, 2, 4}}, {{2, 3, 4}}, {{3, 0, 4}}};
  m.boundary_edges = {{0, 1, 0}, {1, 2, 0}, {2, 3, 1}, {3, 0, 1}};
  m.curve_names = {"bottom_right", "top \"left\""};
  return m;
}

// A boundary layer's quad under two core triangles, as a layered run writes it (quads, and the
// "boundary_layer" region), for the readers' quad path (`pdmesh quality`).
MixedMesh small_mixed_mesh() {
  MixedMesh m;
  m.points = {{0, 0}, {1, 0}, {1, 0.2}, {0, 0.2}, {1, 1}, {0, 1}};
  m.cells = {{0, 1, 2, 3}, {3, 2, 4, -1}, {3, 4, 5, -1}};
  m.layer = {1, 0, 0};
  m.boundary_edges = {{0, 1, 0}, {1, 2, 1}, {2, 4, 1}, {4, 5, 1}, {5, 3, 1}, {3, 0, 1}};
  m.curve_names = {"wall", "outer"};
  return m;
}

NodeSet small_nodes() {
  NodeSet n;
  n.add({0, 0}, 0.5, NodeKind::Fixed, 0);
  n.add({1, 0}, 0.5, NodeKind::Boundary, 0);
  n.add({1, 1}, 0.5, NodeKind::Fixed, 0);
  n.add({0, 1}, 0.25, NodeKind::Boundary, 1);
  n.add({0.5, 0.5}, 0.125, NodeKind::Interior, -1);
  n.curve_nodes = {{0, 1, 2}, {2, 3, 0}};
  return n;
}

// Checkpoints of fuzz::checkpoint_case() (so that they fit it and the entry runs the simulation):
// the initial state, the state after 3 iterations, and that one cut in half (truncated).
void checkpoint_seeds(const fs::path& corpus) {
  fuzz::CheckpointCase& world = fuzz::checkpoint_case();
  NodeSet nodes = make_initial_distribution(*world.tree, world.spacing, {InitMethod::Structured, 1, {}}).nodes;
  const std::vector<std::pair<std::string, std::string>> keys = {
      {"geometry.file.0", "square.crv (60 bytes, FNV-1a 0123456789abcdef)"},
      {"spacing.field", "expression"},
      {"spacing.expression", "0.25"}};
  SimOptions options;
  options.iterations = 0;
  options.quiet = true;
  options.exact_spacing = true;
  const SimResult initial = run_simulation(nodes, *world.tree, world.spacing, options);
  put(corpus / "fuzz_checkpoint" / "square_initial.pdmesh", format_checkpoint({keys, nodes, initial.state}));
  options.iterations = 3;
  const SimResult after = run_simulation(nodes, *world.tree, world.spacing, options);
  const std::string text = format_checkpoint({keys, nodes, after.state});
  put(corpus / "fuzz_checkpoint" / "square_3_iterations.pdmesh", text);
  put(corpus / "fuzz_checkpoint" / "square_truncated.pdmesh", text.substr(0, text.size() / 2));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_make_seeds CORPUS_DIR\n");
    return 2;
  }
  const fs::path corpus = argv[1];
  const fs::path work = fs::temp_directory_path() / "pdmesh_fuzz_seeds";
  fs::remove_all(work);
  fs::create_directories(work / "a");
  fs::create_directories(work / "b");
  try {
    const Mesh mesh = small_mesh();
    write_mesh(mesh, work / "a", "m", {"msh", "vtu", "su2", "triangle", "mesh"});
    write_mesh(mesh, work / "b", "m", {"msh22"});
    put(corpus / "fuzz_mesh_reader_msh" / "square_41.msh", slurp(work / "a" / "m.msh"));
    put(corpus / "fuzz_mesh_reader_msh" / "square_22.msh", slurp(work / "b" / "m.msh"));
    put(corpus / "fuzz_mesh_reader_vtu" / "square.vtu", slurp(work / "a" / "m.vtu"));
    put(corpus / "fuzz_mesh_reader_su2" / "square.su2", slurp(work / "a" / "m.su2"));
    put(corpus / "fuzz_mesh_reader_medit" / "square.mesh", slurp(work / "a" / "m.mesh"));
    const std::string node = slurp(work / "a" / "m.node"), ele = slurp(work / "a" / "m.ele");
    const std::string poly = slurp(work / "a" / "m.poly");
    put(corpus / "fuzz_mesh_reader_triangle" / "square_with_poly", node + '\f' + ele + '\f' + poly);
    put(corpus / "fuzz_mesh_reader_triangle" / "square_no_poly", node + '\f' + ele);
    const MixedMesh mixed = small_mixed_mesh();
    put(corpus / "fuzz_mesh_reader_msh" / "layer_quads_41.msh", mixed_msh41_string(mixed));
    put(corpus / "fuzz_mesh_reader_vtu" / "layer_quads.vtu", mixed_vtu_string(mixed));
    put(corpus / "fuzz_mesh_reader_su2" / "layer_quads.su2", mixed_su2_string(mixed));
    put(corpus / "fuzz_mesh_reader_medit" / "layer_quads.mesh", mixed_medit_string(mixed));
    put(corpus / "fuzz_node_file" / "square.nodes", format_node_file(small_nodes(), {"bottom_right", "top_left"}));
    checkpoint_seeds(corpus);
  } catch (const Error& e) {
    std::fprintf(stderr, "fuzz_make_seeds: %s\n", e.what());
    return 1;
  }
  fs::remove_all(work);
  return 0;
}
