// pdmesh._core.Mesh: a triangle mesh with zero-copy numpy views, its boundary edges by curve name,
// the quality measures of `pdmesh quality`, and the command's writers and pictures.
#include <cmath>
#include <filesystem>
#include <numbers>
#include <fmt/format.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "bindings.hpp"
#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "io/mesh_formats.hpp"
#include "io/mixed_mesh.hpp"
#include "mesh/quality.hpp"
#include "io/quality_report.hpp"
#include "io/region_quality.hpp"
#include "render/mesh_picture.hpp"

namespace pdmesh::py {

namespace fs = std::filesystem;

namespace {

using Values2 = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;

// The per-triangle measures by their names (docs/quality.md; the command's --color-by names).
const std::vector<std::pair<const char*, double TriangleQuality::*>> kMetrics = {
    {"min_angle", &TriangleQuality::min_angle},
    {"max_angle", &TriangleQuality::max_angle},
    {"aspect_ratio", &TriangleQuality::aspect_ratio},
    {"skewness", &TriangleQuality::skewness},
    {"condition_number", &TriangleQuality::condition_number},
    {"min_jacobian", &TriangleQuality::min_jacobian},
};

std::vector<double> metric_values(const std::vector<TriangleQuality>& q, double TriangleQuality::*member) {
  std::vector<double> v(q.size());
  for (std::size_t t = 0; t < q.size(); ++t) v[t] = q[t].*member;
  return v;
}

double TriangleQuality::*metric_named(const std::string& name) {
  std::string names;
  for (const auto& [n, member] : kMetrics) {
    if (name == n) return member;
    names += (names.empty() ? "" : ", ") + std::string(n);
  }
  throw InputError(fmt::format("color_by: unknown metric '{}' ({}; or region)", name, names));
}

// With layers, the core's triangles (as the command's table and quality.json).
std::string quality_json_of(const MeshHandle& h) {
  nb::gil_scoped_release release;
  const Mesh& mesh = h.layers ? h.layers->core : *h.mesh;
  if (!h.session) {
    QualitySummary summary = summarize_quality(mesh);
    if (!h.layers) add_region_quality(mesh, summary);
    return quality_json(summary, h.name);
  }
  std::lock_guard lock(h.session->mutex);
  const SpacingField& spacing = h.session->spacing->asked();
  const SpacingCallback q = [&spacing](Vec2 p) { return spacing.at(p); };
  QualitySummary summary = summarize_quality(mesh, q);
  // A layered mesh's regions are its core and its layer (the "boundary_layer" member), as the command's.
  if (!h.layers) add_region_quality(mesh, summary, q);
  return quality_json(summary, h.name);
}

nb::dict triangle_metrics(const MeshHandle& h) {
  std::vector<TriangleQuality> q;
  {
    nb::gil_scoped_release release;
    q = triangle_qualities(*h.mesh);
  }
  nb::dict d;
  for (const auto& [name, member] : kMetrics) {
    auto* v = new std::vector<double>(metric_values(q, member));
    nb::capsule owner(v, [](void* p) noexcept { delete static_cast<std::vector<double>*>(p); });
    d[name] = nb::ndarray<nb::numpy, double>(v->data(), {v->size()}, owner);
  }
  return d;
}

// Boundary edges grouped by curve name, (K, 2) int32 each, in curve order.
nb::dict boundary_edges(const MeshHandle& h) {
  const Mesh& mesh = *h.mesh;
  std::vector<std::vector<std::int32_t>> per(mesh.curve_names.size());
  for (const BoundaryEdge& e : mesh.boundary_edges) {
    if (e.curve < 0 || static_cast<std::size_t>(e.curve) >= per.size()) continue;
    per[e.curve].push_back(e.a);
    per[e.curve].push_back(e.b);
  }
  nb::dict d;
  for (std::size_t c = 0; c < per.size(); ++c) {
    auto* v = new std::vector<std::int32_t>(std::move(per[c]));
    nb::capsule owner(v, [](void* p) noexcept { delete static_cast<std::vector<std::int32_t>*>(p); });
    d[nb::str(mesh.curve_names[c].c_str())] =
        nb::ndarray<nb::numpy, std::int32_t>(v->data(), {v->size() / 2, 2}, owner);
  }
  return d;
}

// `format` is a write_mesh name (msh, msh22, vtu, su2, triangle, fort14, 2dm, mesh, openfoam, cgns); the file is
// DIR/STEM.<ext> (openfoam: the directory DIR/STEM_openfoam). `open_boundaries`: the curves fort14 writes
// as open boundaries; `walls`: the curves whose openfoam patches are walls.
std::vector<std::string> write(const MeshHandle& h, const std::string& path, const std::string& format,
                               const std::vector<std::string>& open_boundaries, const std::vector<std::string>& walls) {
  const fs::path p(path);
  const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  std::vector<fs::path> written;
  {
    nb::gil_scoped_release release;
    // With layers the mixed-cell writers (msh, vtu, su2, mesh, openfoam, cgns; InputError for the others).
    // The msh formats carry the pairs ($Periodic), as the run's mesh.msh, and the point data as
    // $NodeData views, which Mesh.read takes back.
    const std::vector<PeriodicLink>* periodic = h.periodic->links.empty() ? nullptr : &h.periodic->links;
    MeshWriteOptions options;
    options.open_boundaries = open_boundaries;
    options.periodic = periodic;
    options.msh_point_data = true;
    options.walls = walls;
    if (h.layers) options.walls.insert(options.walls.end(), h.layers->walls.begin(), h.layers->walls.end());
    written = h.layers ? write_mixed_mesh(h.layers->mixed, dir, p.stem().string(), {format}, periodic, options.walls)
                       : write_mesh(*h.mesh, dir, p.stem().string(), {format}, options);
  }
  std::vector<std::string> out;
  for (const fs::path& w : written) out.push_back(w.string());
  return out;
}

// One dict per periodic link: the curves' names, the (image, source) point pairs (K, 2) int32, the
// 4 x 4 affine matrix (row-major, image = A source; None for a file's link without one), the largest
// |A p_source - p_image| (NaN without an affine), and for a run's mesh the table's transform as the run
// applied it ({"translate": (dx, dy)} or {"rotate": {"center": (x, y), "angle_deg": a}}; None when read).
nb::list periodic_links(const MeshHandle& h) {
  const Mesh& mesh = *h.mesh;
  const PeriodicPairs& pairs = *h.periodic;
  nb::list out;
  for (std::size_t k = 0; k < pairs.links.size(); ++k) {
    const PeriodicLink& l = pairs.links[k];
    nb::dict d;
    d["source"] = nb::str(mesh.curve_names.at(static_cast<std::size_t>(l.source_curve)).c_str());
    d["image"] = nb::str(mesh.curve_names.at(static_cast<std::size_t>(l.curve)).c_str());
    static_assert(sizeof(l.nodes[0]) == 2 * sizeof(int));
    d["nodes"] = shared_view<int, 2>(l.nodes.empty() ? nullptr : l.nodes[0].data(), l.nodes.size(), h.periodic);
    const bool has_affine = !std::isnan(l.max_mismatch);
    if (has_affine) {
      d["affine"] = shared_view<double, 4>(l.affine.data(), 4, h.periodic);
    } else {
      d["affine"] = nb::none();
    }
    d["max_mismatch"] = l.max_mismatch;
    if (k < pairs.transforms.size()) {
      const PeriodicTransform& t = pairs.transforms[k];
      nb::dict transform;
      if (t.is_rotation()) {
        nb::dict rotate;
        rotate["center"] = nb::make_tuple(t.center.x, t.center.y);
        rotate["angle_deg"] = t.angle_rad * 180.0 / std::numbers::pi;
        transform["rotate"] = rotate;
      } else {
        transform["translate"] = nb::make_tuple(t.shift.x, t.shift.y);
      }
      d["transform"] = transform;
    } else {
      d["transform"] = nb::none();
    }
    out.append(d);
  }
  return out;
}

void picture(const MeshHandle& h, const std::string& path, const std::string& color_by, const std::string& title,
             std::optional<std::vector<double>> window, int long_side) {
  MeshPictureOptions options;
  options.title = title;
  options.long_side = long_side;
  if (window) {
    if (window->size() != 4 || !((*window)[0] < (*window)[2] && (*window)[1] < (*window)[3]))
      throw InputError("window must be [x0, y0, x1, y1] with x0 < x1 and y0 < y1");
    options.window = Box{{(*window)[0], (*window)[1]}, {(*window)[2], (*window)[3]}};
  }
  // "region": the triangles filled by their regions with a legend (with layers, the core's cells and
  // the layer's, as the command's mesh.png).
  options.fill_regions = color_by == "region";
  double TriangleQuality::*member = color_by == "none" || options.fill_regions ? nullptr : metric_named(color_by);
  nb::gil_scoped_release release;
  // With layers, the quads drawn split (as the command's mesh.png); coloured, the triangles alone.
  Mesh drawn = h.layers && member == nullptr ? triangulated(h.layers->mixed) : Mesh{};
  if (h.layers && options.fill_regions) add_layer_regions(h.layers->mixed, drawn);
  const Mesh& mesh = h.layers && member == nullptr ? drawn : *h.mesh;
  std::vector<double> values;
  if (member != nullptr) {
    values = metric_values(triangle_qualities(mesh), member);
    options.triangle_values = &values;
    options.value_label = color_by;
  }
  write_mesh_picture(path, mesh, options);
}

// A copy of `h` whose mesh holds the point arrays `arrays` ((N, k) float64 each, N its points) as its
// point data, which its .vtu then writes (with layers, the merged mesh's too).
MeshHandle with_point_data(const MeshHandle& h, const std::vector<std::pair<std::string, Values2>>& arrays) {
  std::vector<PointValues> data;
  for (const auto& [name, a] : arrays) {
    if (a.shape(0) != h.mesh->points.size())
      throw InputError(
          fmt::format("point data '{}': {} rows for a mesh of {} points", name, a.shape(0), h.mesh->points.size()));
    data.push_back(
        {name, static_cast<int>(a.shape(1)), std::vector<double>(a.data(), a.data() + a.shape(0) * a.shape(1)), false});
  }
  MeshHandle out = h;
  auto mesh = std::make_shared<Mesh>(*h.mesh);
  mesh->point_data = data;
  out.mesh = std::move(mesh);
  if (h.layers) {
    auto layers = std::make_shared<LayerParts>(*h.layers);
    layers->mixed.point_data = std::move(data);
    out.layers = std::move(layers);
  }
  return out;
}

// A file's point arrays (read_mesh's `data`, every array decoded) as Mesh.read hands them on: "q"
// with one value at every point is the spacing field the writers write from Mesh::spacing; a .vtu's
// "kind" is Mesh::kind, which the reader took from it; every other array is point data, in file
// order. `layered` gets q among them, as the mixed-cell writers write no spacing.
void take_point_arrays(const std::string& path, MeshPointData& data, Mesh& mesh, MixedMesh* layered) {
  const bool vtu = lower_extension(path) == ".vtu";
  for (PointDataArray& a : data.arrays) {
    if (vtu && a.name == "kind") continue;
    PointValues v{a.name, a.components, std::move(a.values), a.integer};
    if (v.name == "q" && v.components == 1 && a.given.empty() && mesh.spacing.empty()) {
      if (layered != nullptr) layered->point_data.push_back(v);
      mesh.spacing = std::move(v.values);
      continue;
    }
    if (layered != nullptr) layered->point_data.push_back(v);
    mesh.point_data.push_back(std::move(v));
  }
}

}  // namespace

void bind_mesh(nb::module_& m) {
  nb::class_<MeshHandle>(m, "Mesh", "A triangle mesh (use pdmesh.Mesh).")
      .def_prop_ro(
          "points",
          [](const MeshHandle& h) {
            const auto& p = h.mesh->points;
            return shared_view<double, 2>(p.empty() ? nullptr : &p[0].x, p.size(), h.mesh);
          },
          nb::rv_policy::automatic, "(N, 2) float64 points, read-only, no copy.")
      .def_prop_ro(
          "triangles",
          [](const MeshHandle& h) {
            const auto& t = h.mesh->triangles;
            static_assert(sizeof(t[0]) == 3 * sizeof(int));
            return shared_view<int, 3>(t.empty() ? nullptr : t[0].data(), t.size(), h.mesh);
          },
          nb::rv_policy::automatic, "(M, 3) int32 counter-clockwise triangles, 0-based, read-only, no copy.")
      .def_prop_ro(
          "kinds",
          [](const MeshHandle& h) {
            const auto* k = reinterpret_cast<const std::uint8_t*>(h.mesh->kind.data());
            return shared_view<std::uint8_t, 1>(k, h.mesh->kind.size(), h.mesh);
          },
          nb::rv_policy::automatic,
          "(N,) uint8 point kinds (0 fixed, 1 boundary, 2 interior); empty where a file does not give them.")
      .def_prop_ro(
          "regions",
          [](const MeshHandle& h) {
            const auto& r = h.mesh->region;
            return shared_view<double, 1>(r.data(), r.size(), h.mesh);
          },
          nb::rv_policy::automatic, "(M,) float64 per triangle: its region's attribute (empty without regions).")
      .def_prop_ro(
          "region_names",
          [](const MeshHandle& h) {
            nb::dict names;
            for (const RegionName& r : h.mesh->region_names) names[nb::float_(r.attribute)] = r.name;
            return names;
          },
          "dict attribute -> name of the regions that have a name (the others are region_<attribute>).")
      .def_prop_ro(
          "curve_groups",
          [](const MeshHandle& h) {
            nb::dict groups;
            for (const CurveGroupTag& g : h.mesh->curve_groups) {
              nb::list curves;
              for (const int c : g.curves)
                curves.append(nb::str(h.mesh->curve_names[static_cast<std::size_t>(c)].c_str()));
              groups[nb::int_(g.tag)] = nb::make_tuple(nb::str(g.name.c_str()), curves);
            }
            return groups;
          },
          "dict physical tag -> (name, [curve names]) of the curves' physical groups a mesh file gave.")
      .def_prop_ro(
          "spacing",
          [](const MeshHandle& h) {
            const auto& q = h.mesh->spacing;
            return shared_view<double, 1>(q.data(), q.size(), h.mesh);
          },
          nb::rv_policy::automatic,
          "(N,) float64 spacing field q at each point (read from a file: its point array q; empty without one).")
      .def_prop_ro(
          "quads",
          [](const MeshHandle& h) {
            static const std::vector<std::array<int, 4>> none;
            const auto& q = h.layers ? h.layers->quads : none;
            static_assert(sizeof(q[0]) == 4 * sizeof(int));
            return shared_view<int, 4>(q.empty() ? nullptr : q[0].data(), q.size(), h.layers);
          },
          nb::rv_policy::automatic, "(K, 4) int32 counter-clockwise quadrangles (boundary-layer cells), no copy.")
      .def_prop_ro(
          "triangle_layer",
          [](const MeshHandle& h) {
            static const std::vector<std::uint8_t> none;
            const auto& l = h.layers ? h.layers->triangle_layer : none;
            return shared_view<std::uint8_t, 1>(l.data(), l.size(), h.layers);
          },
          nb::rv_policy::automatic, "(M,) uint8 per triangle: 1 in a boundary layer (empty without layers).")
      .def_prop_ro("curve_names", [](const MeshHandle& h) { return h.mesh->curve_names; })
      .def_prop_ro(
          "point_data", [](const MeshHandle& h) { return point_value_list(h.mesh->point_data); },
          "The mesh's point arrays as [(name, (N, k) float64)], copies.")
      .def("with_point_data", &with_point_data, nb::arg("arrays"),
           "A copy of the mesh with these point arrays [(name, (N, k) float64)] as its point data.")
      .def_prop_ro("name", [](const MeshHandle& h) { return h.name; })
      .def("boundary_edges", &boundary_edges, "Boundary edges by curve name, (K, 2) int32 each.")
      .def("periodic_links", &periodic_links, "The periodic pairs, one dict per link (image, source).")
      .def("quality_json", &quality_json_of, "The quality.json document of this mesh.")
      .def("triangle_metrics", &triangle_metrics, "Per-triangle quality arrays.")
      .def("write", &write, nb::arg("path"), nb::arg("format"), nb::arg("open_boundaries"), nb::arg("walls"),
           "Writes the mesh; returns the paths written.")
      .def("picture", &picture, nb::arg("path"), nb::arg("color_by") = "none", nb::arg("title") = "",
           nb::arg("window").none() = nb::none(), nb::arg("long_side") = 1600, "Draws the mesh into a .png or .svg.");

  m.def(
      "mesh_formats",
      [] {
        std::vector<std::pair<std::string, std::vector<std::string>>> formats;
        for (const std::string& name : mesh_format_names()) formats.emplace_back(name, mesh_format_extensions(name));
        return formats;
      },
      "The writers' formats in documentation order: (name, the extensions of the files it writes).");
  m.def(
      "read_mesh",
      [](const std::string& path) {
        Mesh mesh;
        auto periodic = std::make_shared<PeriodicPairs>();
        std::shared_ptr<LayerParts> layers;
        {
          nb::gil_scoped_release release;
          MeshReadReport report;
          SurfaceCells cells;
          cells.region = kLayerRegion;
          MeshPointData data;
          data.decode_all = true;
          mesh = read_mesh(path, report, &cells, &data);
          periodic->links = std::move(report.periodic);  // an MSH file's $Periodic curve links
          // A file with quads (a layered run's, in any of its formats) as `pdmesh quality` reads it:
          // the quads and the layer flags beside the triangles; its quality is the triangles' table.
          if (!cells.quads.empty()) {
            layers = std::make_shared<LayerParts>();
            layers->mixed = mixed_mesh_of(mesh, cells);
            layers->quads = std::move(cells.quads);
            layers->triangle_layer.assign(layers->mixed.layer.begin(),
                                          layers->mixed.layer.begin() + static_cast<long>(mesh.triangles.size()));
          }
          take_point_arrays(path, data, mesh, layers ? &layers->mixed : nullptr);
          if (layers) layers->core = mesh;
        }
        return MeshHandle{std::make_shared<const Mesh>(std::move(mesh)), nullptr, fs::path(path).stem().string(),
                          std::move(layers), std::move(periodic)};
      },
      nb::arg("path"),
      "Reads a .msh (2.2/4.1), .vtu, .su2, Medit .mesh or Triangle .ele mesh, with the quads of the first four "
      "and the point arrays of .msh ($NodeData) and .vtu files (q as the spacing).");
}

}  // namespace pdmesh::py
