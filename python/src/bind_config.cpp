// pdmesh._core.Config: a validated case (CaseConfig) made from a case file, geometry files or curves
// in memory, with settings applied through the same validator as the command's --set.
#include <algorithm>
#include <fmt/format.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include "app/config/adapt_keys.hpp"
#include "app/pipeline/smooth_pipeline.hpp"
#include "app/pipeline/solution_transfer.hpp"
#include "bindings.hpp"
#include "callable_spacing.hpp"
#include "core/errors.hpp"
#include "geometry/geometry_files.hpp"
#include "init/initial_distribution.hpp"
#include "io/mesh_geometry.hpp"
#include "io/point_data_file.hpp"

namespace pdmesh::py {

namespace {

// (key, TOML value, label) as the Python layer (pdmesh/_settings.py) writes them.
using Setting = std::tuple<std::string, std::string, std::string>;
using Ring = nb::ndarray<const double, nb::shape<-1, 2>, nb::c_contig, nb::device::cpu>;
// Rows of x, y, attribute (regions given in memory).
using RegionRows = nb::ndarray<const double, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;

std::vector<CaseOverride> overrides_from(const std::vector<Setting>& settings) {
  std::vector<CaseOverride> out;
  for (const auto& [key, value, label] : settings) out.push_back({key, value, label});
  return out;
}

nb::ndarray<nb::numpy, double> points_array(const std::vector<Vec2>& points) {
  auto* v = new std::vector<Vec2>(points);
  nb::capsule owner(v, [](void* p) noexcept { delete static_cast<std::vector<Vec2>*>(p); });
  return nb::ndarray<nb::numpy, double>(v->empty() ? nullptr : &(*v)[0].x, {v->size(), 2}, owner);
}

// The validated geometry of a case, as MeshInputs reads it: curves, loops (closed rings with their
// nesting depth: even = an outer boundary, odd = a hole), area and extents.
nb::dict geometry_of(const CaseConfig& c) {
  Geometry g;
  {
    nb::gil_scoped_release release;
    GeometryOptions options;
    options.join_tolerance = c.geometry.join_tolerance;
    options.corner_angle_deg = c.geometry.corner_angle;
    options.hull = c.geometry.hull;
    std::vector<std::string> files;
    for (const auto& f : c.geometry.files) files.push_back(f.string());
    g = c.geometry.given_curves.empty()
            ? read_geometry(files, c.geometry.curve_names, options,
                            {c.geometry.projection, nullptr, {}, mesh_geometry_files()})
            : geometry_from_curves(c.geometry.given_curves, c.geometry.curve_names, options, c.geometry.given_points,
                                   {c.geometry.projection, nullptr, {}, {}});
  }
  nb::list names, curves, loops;
  for (const Curve& curve : g.curves) {
    names.append(curve.name);
    curves.append(points_array(curve.points));
  }
  for (const Loop& loop : g.loops) {
    std::vector<Vec2> ring;
    for (std::size_t k = 0; k < loop.curves.size(); ++k) {
      std::vector<Vec2> pts = g.curves[loop.curves[k]].points;
      if (loop.reversed[k]) std::reverse(pts.begin(), pts.end());
      // Consecutive curves share their joint: keep it once; the ring ends where it starts.
      ring.insert(ring.end(), pts.begin() + (ring.empty() ? 0 : 1), pts.end());
    }
    nb::dict d;
    d["ring"] = points_array(ring);
    d["curves"] = std::vector<int>(loop.curves);
    d["depth"] = loop.depth;
    d["signed_area"] = loop.signed_area;
    loops.append(d);
  }
  nb::dict d;
  d["names"] = names;
  d["curves"] = curves;
  d["loops"] = loops;
  d["area"] = g.area;
  d["extents"] = std::vector<double>{g.extents.lo.x, g.extents.lo.y, g.extents.hi.x, g.extents.hi.y};
  return d;
}

// The [motion] keys a MovingMesher takes its defaults from.
nb::dict motion_keys(const CaseConfig& c) {
  const CaseConfig::Motion& mo = c.motion;
  nb::dict d;
  d["enabled"] = mo.enabled;
  d["curves"] = mo.curves;
  d["pivot"] = nb::make_tuple(mo.pivot[0], mo.pivot[1]);
  d["iterations"] = mo.iterations;
  d["blend"] = mo.blend;
  return d;
}

}  // namespace

void bind_config(nb::module_& m) {
  nb::class_<CaseConfig>(m, "Config", "A validated case: every key of the case file, checked as the command checks it.")
      .def_prop_ro("name", [](const CaseConfig& c) { return c.name; })
      .def_prop_ro("source", [](const CaseConfig& c) { return c.source.string(); })
      .def_prop_ro("preset", [](const CaseConfig& c) { return std::string(to_string(c.preset)); })
      .def_prop_ro("geometry_files",
                   [](const CaseConfig& c) {
                     std::vector<std::string> files;
                     for (const auto& f : c.geometry.files) files.push_back(f.string());
                     return files;
                   })
      .def_prop_ro("curve_names", [](const CaseConfig& c) { return c.geometry.curve_names; })
      .def_prop_ro("iterations", [](const CaseConfig& c) { return c.simulation.iterations; })
      .def_prop_ro("device", [](const CaseConfig& c) { return c.simulation.device; })
      .def_prop_ro("seed", [](const CaseConfig& c) { return c.init.seed; })
      .def_prop_ro("method", [](const CaseConfig& c) { return std::string(to_string(c.init.method)); })
      .def_prop_ro("formats", [](const CaseConfig& c) { return c.output.formats; })
      .def_prop_ro("motion", &motion_keys, "The [motion] section's keys (enabled False without one).")
      .def("geometry", &geometry_of, "The validated geometry: curves, loops, area, extents.")
      .def_prop_ro("has_size_callable", [](const CaseConfig& c) { return c.spacing.given != nullptr; })
      .def(
          "with_size_callable",
          [](const CaseConfig& c, nb::object sample) {
            CaseConfig copy = c;
            copy.spacing.given = std::make_shared<CallableSpacing>(std::move(sample));
            return copy;
          },
          nb::arg("sample"), "A copy whose spacing field is `sample(xy[N,2]) -> h[N]` (sampled once, vectorised).")
      .def(
          "for_smoothing",
          [](const CaseConfig& c, const std::string& mesh_file, const std::string& label, bool by_mesh) {
            CaseConfig copy = c;
            {
              nb::gil_scoped_release release;
              const Mesh mesh = read_smooth_mesh(mesh_file, label);
              make_smooth_config(copy, mesh, mesh_file, label, by_mesh ? SmoothField::Mesh : SmoothField::Case);
            }
            return copy;
          },
          nb::arg("mesh_file"), nb::arg("label"), nb::arg("by_mesh"),
          "A copy that smooths the mesh in mesh_file (pdmesh smooth): checked against the geometry, its nodes "
          "the warm start, its edge lengths the spacing when by_mesh.");

  m.def(
      "smooth_settings",
      [](bool by_mesh) {
        std::vector<Setting> out;
        for (const CaseOverride& o : smooth_overrides(by_mesh ? SmoothField::Mesh : SmoothField::Case))
          out.emplace_back(o.key, o.value, o.label);
        return out;
      },
      nb::arg("by_mesh"), "The case keys pdmesh smooth sets before the caller's settings.");
  m.def(
      "adapt_settings",
      [](const std::string& solution, const std::vector<std::string>& arrays, const std::string& complexity,
         const std::optional<std::string>& hmin, const std::optional<std::string>& hmax,
         const std::optional<std::string>& gradation, const std::optional<std::string>& max_anisotropy,
         const std::optional<std::string>& norm) {
        AdaptOptions o;
        o.solution = solution;
        o.arrays = arrays;
        o.complexity = complexity;
        o.hmin = hmin;
        o.hmax = hmax;
        o.gradation = gradation;
        o.max_anisotropy = max_anisotropy;
        o.norm = norm;
        std::vector<Setting> out;
        for (const CaseOverride& c : adapt_overrides(o)) out.emplace_back(c.key, c.value, c.label);
        return out;
      },
      nb::arg("solution"), nb::arg("arrays"), nb::arg("complexity"), nb::arg("hmin").none(), nb::arg("hmax").none(),
      nb::arg("gradation").none(), nb::arg("max_anisotropy").none(), nb::arg("norm").none(),
      "The case keys pdmesh adapt sets before the caller's settings (its [spacing] replaced); the metric's "
      "values as TOML text.");
  m.def(
      "adapt_mesh_file",
      [](const CaseConfig& c, const std::string& out_dir) -> std::optional<std::string> {
        CaseConfig config = c;
        config.out_dir = out_dir;
        const std::optional<std::filesystem::path> file = adapted_mesh_file(config);
        if (!file) return std::nullopt;
        return file->string();
      },
      nb::arg("config"), nb::arg("out_dir"),
      "The mesh file in out_dir that pdmesh adapt makes solution.vtu on (None: output.formats writes none).");
  m.def(
      "write_adapted_solution",
      [](const CaseConfig& c, const std::string& out_dir, const std::string& solution) {
        CaseConfig config = c;
        config.out_dir = out_dir;
        const std::optional<std::filesystem::path> file = adapted_mesh_file(config);
        if (!file) throw InputError(fmt::format("{}: output.formats writes no mesh file", out_dir));
        AdaptedSolution a;
        {
          nb::gil_scoped_release release;
          a = write_adapted_solution(config, solution, *file);
        }
        return point_value_list(a.target.point_data);
      },
      nb::arg("config"), nb::arg("out_dir"), nb::arg("solution"),
      "After the run wrote its files in out_dir: out_dir/solution.vtu as pdmesh adapt writes it; returns its "
      "arrays [(name, (N, k) values)].");
  m.def(
      "point_array_names", [](const std::string& path) { return point_array_names(path); }, nb::arg("path"),
      "The point arrays of a .vtu or .msh file, as pdmesh adapt and pdmesh transfer list them.");
  m.def(
      "case_keys", [] { return case_file_keys(); }, "Every valid dotted case-file key.");
  m.def(
      "load_case",
      [](const std::string& path, const std::vector<Setting>& settings) {
        return load_case_file(path, overrides_from(settings));
      },
      nb::arg("path"), nb::arg("settings"), "Reads and validates a case file (TOML); settings as --set.");
  m.def(
      "case_for_files",
      [](const std::vector<std::string>& paths, const std::vector<Setting>& settings) {
        std::vector<std::filesystem::path> files(paths.begin(), paths.end());
        return case_for_geometry_files(files, overrides_from(settings));
      },
      nb::arg("paths"), nb::arg("settings"), "A case for geometry files (.crv/.dat/.poly) with the preset's defaults.");
  m.def(
      "case_for_curves",
      [](const std::vector<Ring>& curves, const std::vector<std::string>& labels, const std::string& source,
         const std::vector<Setting>& settings, const std::vector<int>& constraint, const Ring& points,
         const std::string& points_label, const RegionRows& regions, const std::vector<std::string>& region_names) {
        if (labels.size() != curves.size())
          throw InputError(fmt::format("{} curves but {} labels", curves.size(), labels.size()));
        if (!constraint.empty() && constraint.size() != curves.size())
          throw InputError(fmt::format("{} curves but {} constraint flags", curves.size(), constraint.size()));
        std::vector<RawCurve> raw;
        for (std::size_t k = 0; k < curves.size(); ++k) {
          RawCurve c;
          c.file = labels[k];
          c.constraint = !constraint.empty() && constraint[k] != 0;
          const Ring& a = curves[k];
          for (std::size_t i = 0; i < a.shape(0); ++i) {
            c.points.push_back({a(i, 0), a(i, 1)});
            c.lines.push_back(static_cast<int>(i));  // messages say "LABEL:i" for point i
          }
          raw.push_back(std::move(c));
        }
        CaseConfig config = case_for_curves(std::move(raw), source, overrides_from(settings));
        for (std::size_t i = 0; i < points.shape(0); ++i)  // messages say "POINTS_LABEL:i" for point i
          config.geometry.given_points.push_back({{points(i, 0), points(i, 1)}, points_label, static_cast<int>(i)});
        if (!region_names.empty() && region_names.size() != regions.shape(0))
          throw InputError(fmt::format("{} regions but {} region names", regions.shape(0), region_names.size()));
        for (std::size_t i = 0; i < regions.shape(0); ++i) {  // messages say "regions:i" for region i
          GeometryRegion r;
          r.p = {regions(i, 0), regions(i, 1)};
          r.attribute = regions(i, 2);
          r.file = "regions";
          r.line = static_cast<int>(i);
          if (!region_names.empty()) r.name = region_names[i];
          config.geometry.given_regions.push_back(std::move(r));
        }
        return config;
      },
      nb::arg("curves"), nb::arg("labels"), nb::arg("source"), nb::arg("settings"), nb::arg("constraint"),
      nb::arg("points"), nb::arg("points_label"), nb::arg("regions"), nb::arg("region_names"),
      "A case for curves given as (N, 2) arrays (constraint[k]: curve k is an embedded constraint), embedded "
      "points given as an (M, 2) array and regions as a (K, 3) array of x, y, attribute with their names (empty: "
      "none); labels name each in messages.");
}

}  // namespace pdmesh::py
