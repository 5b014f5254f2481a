// Boundary-layer prototype (docs/boundary-layers.md): grows layers from the named wall curves of a
// case's geometry, the core spacing being the case's spacing field, prints the layer measures and
// writes the layer cells as they are (quads and triangles, with their kind, curve and layer) as
// OUT/layer_cells.vtu, split into triangles as OUT/layers.vtu and .msh (the fronts as boundary
// edges), with pictures of the whole layer and of each view given.
//
//   layers_prototype CASE.toml OUT H1 GROWTH THICKNESS CURVE[,CURVE...] [split] [NAME=X0,Y0,X1,Y1 ...]
//
// `split` writes each layer quad as two triangles (LayerSettings::split_quads) and measures those.
//
// Example: build/layers_prototype cases/naca0012/case.toml /tmp/bl 1e-5 1.2 0.05 upper,lower
//            le=-0.02,-0.05,0.08,0.05 te=0.95,-0.03,1.01,0.03
#include <fmt/format.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "io/mesh_formats.hpp"
#include "layers/boundary_layers.hpp"
#include "layers/front_geometry.hpp"
#include "layers/layer_measures.hpp"
#include "render/mesh_picture.hpp"

using namespace pdmesh;

namespace {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, sep);) out.push_back(item);
  return out;
}

// The layer cells as they are (VTK_QUAD 9, VTK_TRIANGLE 5) with cell data kind, curve and layer.
std::string cells_vtu(const LayerMesh& layers) {
  std::string points, connectivity, offsets, types, kind, curve, layer;
  for (const Vec2 p : layers.nodes) points += fmt::format("{:.17g} {:.17g} 0\n", p.x, p.y);
  int offset = 0;
  for (const LayerCell& c : layers.cells) {
    const int k = c.triangle() ? 3 : 4;
    for (int i = 0; i < k; ++i) connectivity += fmt::format("{} ", c.v[i]);
    offset += k;
    offsets += fmt::format("{} ", offset);
    types += c.triangle() ? "5 " : "9 ";
    kind += fmt::format("{} ", static_cast<int>(c.kind));
    curve += fmt::format("{} ", c.curve);
    layer += fmt::format("{} ", c.layer);
  }
  return fmt::format(
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "<UnstructuredGrid>\n<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n"
      "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n{}</DataArray>\n</Points>\n"
      "<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n{}\n</DataArray>\n"
      "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n{}\n</DataArray>\n"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n{}\n</DataArray>\n</Cells>\n"
      "<CellData>\n<DataArray type=\"Int32\" Name=\"kind\" format=\"ascii\">\n{}\n</DataArray>\n"
      "<DataArray type=\"Int32\" Name=\"curve\" format=\"ascii\">\n{}\n</DataArray>\n"
      "<DataArray type=\"Int32\" Name=\"layer\" format=\"ascii\">\n{}\n</DataArray>\n</CellData>\n"
      "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n",
      layers.nodes.size(), layers.cells.size(), points, connectivity, offsets, types, kind, curve, layer);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 7) {
    fmt::print(stderr, "usage: {} CASE.toml OUT H1 GROWTH THICKNESS CURVE[,CURVE...] [split] [NAME=X0,Y0,X1,Y1 ...]\n",
               argv[0]);
    return 2;
  }
  try {
    const CaseConfig config = load_case_file(argv[1]);
    const std::filesystem::path out = argv[2];
    std::filesystem::create_directories(out);
    LayerSettings settings;
    settings.first_height = std::stod(argv[3]);
    settings.growth = std::stod(argv[4]);
    settings.thickness = std::stod(argv[5]);
    int first_view = 7;
    if (argc > 7 && std::string(argv[7]) == "split") {
      settings.split_quads = true;
      first_view = 8;
    }
    const MeshInputs inputs(config);
    const SpacingStage spacing(config, inputs, SpacingStage::Build::FieldOnly);
    const SpacingField& field = spacing.field();
    const CoreSpacing core = [&field](Vec2 p) { return field.at(p); };
    const std::vector<int> walls = curves_by_name(inputs.geometry, split(argv[6], ','), "wall curves");

    const auto start = std::chrono::steady_clock::now();
    const LayerMesh layers = build_boundary_layers(inputs.geometry, walls, settings, core);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const LayerMeasures m = measure_layers(layers, settings.first_height, core);
    std::vector<std::string> names;
    for (const Curve& c : inputs.geometry.curves) names.push_back(c.name);
    fmt::print("{}: {} wall nodes, {} rays, {} repair rounds, built in {:.3f} s\n{}", argv[1], layers.wall_nodes,
               layers.rays.size(), layers.repairs, seconds, format_layer_measures(m, names));

    if (std::getenv(
            "LAYERS_DUMP"))  // one line per ray: wall point, layers, thickness, free thickness, last layer's growth
      for (const LayerRay& r : layers.rays)
        fmt::print("ray {:.6f} {:.6f} {} {:.5g} {:.5g} {:.5f}\n", layers.nodes[r.wall_node].x,
                   layers.nodes[r.wall_node].y, r.nodes.size() - 1, r.thickness, r.free_thickness, r.last_growth);
    if (std::getenv("LAYERS_DUMP"))  // cells with an angle above LAYERS_DUMP degrees: kind, layer, the corner
      for (const LayerCell& c : layers.cells) {
        const int k = c.triangle() ? 3 : 4;
        for (int i = 0; i < k; ++i) {
          const Vec2 p = layers.nodes[c.v[(i + k - 1) % k]], v = layers.nodes[c.v[i]],
                     n = layers.nodes[c.v[(i + 1) % k]];
          if (std::atan2(cross(n - v, p - v), dot(n - v, p - v)) * 180.0 / 3.141592653589793 >
                  std::atof(std::getenv("LAYERS_DUMP")) ||
              std::atan2(cross(n - v, p - v), dot(n - v, p - v)) < 0.0)
            fmt::print("wide {} {} {:.6f} {:.6f} cell {}\n", static_cast<int>(c.kind), c.layer, v.x, v.y, [&] {
              std::string t;
              for (int j = 0; j < k; ++j)
                t += fmt::format(" ({:.6f},{:.6f})", layers.nodes[c.v[j]].x, layers.nodes[c.v[j]].y);
              return t;
            }());
        }
      }
    // The cells as triangles (quads split along v0-v2), the fronts as boundary edges.
    Mesh mesh;
    mesh.points = layers.nodes;
    mesh.curve_names = {"front"};
    std::vector<double> kind;
    for (const LayerCell& c : layers.cells) {
      mesh.triangles.push_back({c.v[0], c.v[1], c.v[2]});
      kind.push_back(static_cast<double>(c.kind));
      if (!c.triangle()) {
        mesh.triangles.push_back({c.v[0], c.v[2], c.v[3]});
        kind.push_back(static_cast<double>(c.kind));
      }
    }
    for (const LayerFront& f : layers.fronts) {
      const std::size_t n = f.nodes.size();
      for (std::size_t k = 0; k + (f.closed ? 0 : 1) < n; ++k)
        mesh.boundary_edges.push_back({f.nodes[k], f.nodes[(k + 1) % n], 0});
    }
    write_mesh(mesh, out, "layers", {"vtu", "msh"});
    write_file_atomically(out / "layer_cells.vtu", cells_vtu(layers));
    // The core's boundary (non-wall curves and the closed fronts) as a curve file and a case that
    // meshes it with the front nodes fixed (best preset otherwise): `pdmesh mesh OUT/core.toml --out DIR`.
    std::string crv, names_list;
    for (const RawCurve& c : front_curves(inputs.geometry, walls, layers)) {
      crv += fmt::format("{}\n", c.points.size());
      for (const Vec2 p : c.points) crv += fmt::format("{:.17g} {:.17g}\n", p.x, p.y);
      names_list += fmt::format("{}\"{}\"", names_list.empty() ? "" : ", ", c.name);
    }
    write_file_atomically(out / "core.crv", crv);
    // Per top node of a ray on the front: x, y, the last layer's height (for the junction with a core mesh).
    std::string tops = "# x y last_layer_height\n";
    for (const LayerRay& r : layers.rays)
      if (r.nodes.size() >= 2 && !r.merged) {
        const Vec2 t = layers.nodes[r.nodes.back()], u = layers.nodes[r.nodes[r.nodes.size() - 2]];
        tops += fmt::format("{:.17g} {:.17g} {:.17g}\n", t.x, t.y, dist(t, u) * r.correction);
      }
    write_file_atomically(out / "front_tops.txt", tops);
    // The boundary nodes at the curves' points, and every front vertex that turns at all a critical
    // point (fixed): the core keeps the layer's top nodes where they are.
    write_file_atomically(out / "core.toml", fmt::format("name = \"core\"\npreset = \"best\"\n\n[geometry]\n"
                                                         "files = [\"core.crv\"]\ncurve_names = [{}]\n"
                                                         "corner_angle = 0.001\n\n[boundary]\nnodes = \"input\"\n",
                                                         names_list));
    MeshPictureOptions options;
    options.triangle_values = &kind;
    options.value_label = "0 quad, 1 fan, 2 transition";
    options.value_range = std::make_pair(0.0, 3.0);
    options.title = "boundary layer";
    write_mesh_picture(out / "layers.png", mesh, options);
    for (int k = first_view; k < argc; ++k) {
      const std::vector<std::string> view = split(argv[k], '=');
      const std::vector<std::string> w = view.size() == 2 ? split(view[1], ',') : std::vector<std::string>{};
      if (w.size() != 4) throw InputError(fmt::format("view \"{}\": give NAME=X0,Y0,X1,Y1", argv[k]));
      Box box;
      box.add({std::stod(w[0]), std::stod(w[1])});
      box.add({std::stod(w[2]), std::stod(w[3])});
      options.window = box;
      options.title = "boundary layer: " + view[0];
      write_mesh_picture(out / ("layers_" + view[0] + ".png"), mesh, options);
    }
    return 0;
  } catch (const InputError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 1;
  }
}
