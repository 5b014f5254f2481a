// mesh_as_geometry(): a mesh's cells turned into boundary loops, constraints, region seeds and fixed
// points (see mesh_geometry.hpp); read_mesh_geometry() reads and checks the file first.
#include "io/mesh_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <unordered_map>
#include <utility>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "core/predicates.hpp"
#include "geometry/geometry_detail.hpp"
#include "geometry/gis_features.hpp"
#include "io/mesh_formats.hpp"
#include "io/mesh_io_common.hpp"

namespace pdmesh {

bool is_mesh_geometry_extension(const std::string& ext) {
  return ext == ".msh" || ext == ".vtu" || ext == ".su2" || ext == ".mesh" || ext == ".ele";
}

std::string mesh_node_text(const Mesh& mesh, int i) {
  const Vec2 p = mesh.points[static_cast<std::size_t>(i)];
  return fmt::format("{} ({}, {})", i, p.x, p.y);
}

namespace {

std::string triangle_text(const Mesh& mesh, std::size_t t) {
  const auto& v = mesh.triangles[t];
  return fmt::format("triangle {} (nodes {}, {}, {})", t, mesh_node_text(mesh, v[0]), mesh_node_text(mesh, v[1]),
                     mesh_node_text(mesh, v[2]));
}

}  // namespace

void check_mesh_triangles(const Mesh& mesh, const std::vector<std::size_t>& reoriented, const std::string& label) {
  if (mesh.triangles.empty()) throw InputError(fmt::format("{}: the mesh has no triangles", label));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& v = mesh.triangles[t];
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2] ||
        orient2d(mesh.points[v[0]], mesh.points[v[1]], mesh.points[v[2]]) == 0.0)
      throw InputError(fmt::format("{}: {} has zero area", label, triangle_text(mesh, t)));
  }
  const std::size_t n = mesh.triangles.size();
  if (reoriented.empty() || reoriented.size() == n) return;
  std::size_t first = 0;
  if (2 * reoriented.size() <= n) {
    first = reoriented.front();
  } else {
    std::vector<std::uint8_t> turned(n, 0);
    for (const std::size_t t : reoriented) turned[t] = 1;
    while (turned[first]) ++first;
  }
  throw InputError(fmt::format("{}: {} is inverted (its orientation is the opposite of {} of the {} triangles)", label,
                               triangle_text(mesh, first), n - std::min(reoriented.size(), n - reoriented.size()), n));
}

namespace {

std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// One side of a cell: the cell, and the edge's direction in it (counter-clockwise, domain on the left).
struct EdgeUse {
  int a = 0, b = 0;
  int cell = 0;
};

struct EdgeInfo {
  int count = 0;
  EdgeUse first;
  int second_cell = -1;
  int name = -1;  // index into Mesh::curve_names, -1 when no boundary edge names it
};

// The state of one conversion: the cells, their edges and what is built from them.
class MeshGeometryBuilder {
 public:
  MeshGeometryBuilder(const Mesh& mesh, const std::vector<std::array<int, 4>>& quads, std::string file)
      : mesh_(mesh), quads_(quads), file_(std::move(file)) {}

  RawGeometry build() {
    check_cells();
    collect_edges();
    trace_boundary();
    trace_constraints();
    seed_regions();
    add_fixed_points();
    unique_names();
    return std::move(raw_);
  }

 private:
  int cell_count() const { return static_cast<int>(mesh_.triangles.size() + quads_.size()); }
  bool is_quad(int c) const { return static_cast<std::size_t>(c) >= mesh_.triangles.size(); }
  std::vector<int> cell(int c) const {
    if (!is_quad(c)) {
      const auto& t = mesh_.triangles[static_cast<std::size_t>(c)];
      return {t[0], t[1], t[2]};
    }
    const auto& q = quads_[static_cast<std::size_t>(c) - mesh_.triangles.size()];
    return {q[0], q[1], q[2], q[3]};
  }
  std::string point_text(int i) const { return mesh_node_text(mesh_, i); }
  Vec2 at(int i) const { return mesh_.points[static_cast<std::size_t>(i)]; }
  // The attribute of a cell's region; NaN for a quad or a mesh without regions.
  double region_of(int c) const {
    return mesh_.region.empty() || is_quad(c) ? std::nan("") : mesh_.region[static_cast<std::size_t>(c)];
  }

  void check_cells() {
    if (cell_count() == 0) throw InputError(fmt::format("{}: the mesh has no triangles or quadrangles", file_));
    for (int c = static_cast<int>(mesh_.triangles.size()); c < cell_count(); ++c) {
      const std::vector<int> v = cell(c);
      double twice = 0.0;
      for (int k = 0; k < 4; ++k) twice += cross(at(v[k]), at(v[(k + 1) % 4]));
      if (!(twice > 0.0))
        throw InputError(fmt::format("{}: quadrangle {} (nodes {}, {}, {}, {}) has zero area", file_,
                                     c - static_cast<int>(mesh_.triangles.size()), point_text(v[0]), point_text(v[1]),
                                     point_text(v[2]), point_text(v[3])));
    }
  }

  void collect_edges() {
    for (int c = 0; c < cell_count(); ++c) {
      const std::vector<int> v = cell(c);
      for (std::size_t k = 0; k < v.size(); ++k) {
        const int a = v[k], b = v[(k + 1) % v.size()];
        EdgeInfo& e = edges_[edge_key(a, b)];
        if (++e.count == 1) {
          e.first = {a, b, c};
          order_.push_back(edge_key(a, b));
        } else if (e.count == 2) {
          e.second_cell = c;
        } else {
          throw InputError(
              fmt::format("{}: the edge from point {} to point {} is a side of {} cells; an edge of a 2-D "
                          "mesh is a side of one or two",
                          file_, point_text(a), point_text(b), e.count));
        }
      }
    }
    for (const BoundaryEdge& b : mesh_.boundary_edges) {
      const auto it = edges_.find(edge_key(b.a, b.b));
      if (it != edges_.end() && it->second.name < 0) it->second.name = b.curve;
    }
  }

  // The name a stretch of edges carries in the file, "" when none.
  std::string file_name(int name) const {
    return name < 0 ? std::string() : gis::plain_name(mesh_.curve_names[static_cast<std::size_t>(name)]);
  }

  void add_curve(const std::vector<int>& vertices, int name, bool constraint) {
    RawCurve r;
    r.name = file_name(name);
    if (r.name.empty())
      r.name = constraint ? fmt::format("interface{}", unnamed_constraints_++)
                          : fmt::format("boundary{}", unnamed_boundaries_++);
    for (const int v : vertices) r.points.push_back(at(v));
    r.file = file_;
    r.constraint = constraint;
    raw_.curves.push_back(std::move(r));
    source_.push_back(name);
  }

  // The turning angle at b of a -> b -> c (0 straight on).
  double turn(int a, int b, int c) const { return detail::turning_angle(at(b) - at(a), at(c) - at(b)); }

  void trace_boundary() {
    std::unordered_map<int, int> next;  // boundary point -> the end of its boundary edge
    std::vector<std::uint64_t> starts;
    for (const std::uint64_t key : order_) {
      const EdgeInfo& e = edges_[key];
      if (e.count != 1) continue;
      if (!next.emplace(e.first.a, e.first.b).second)
        throw InputError(
            fmt::format("{}: the boundary pinches at point {}: two boundary loops pass through it; a mesh "
                        "used as a geometry must have a boundary of separate loops (move the cells apart "
                        "or join them with a cell)",
                        file_, point_text(e.first.a)));
      starts.push_back(key);
    }
    std::set<int> done;
    for (const std::uint64_t key : starts) {
      const int start = edges_[key].first.a;
      if (done.count(start) != 0) continue;
      std::vector<int> loop;
      for (int v = start;;) {
        loop.push_back(v);
        done.insert(v);
        const auto to = next.find(v);
        if (to == next.end())
          throw InputError(
              fmt::format("{}: the boundary does not close at point {}: the cells there overlap or are "
                          "inverted",
                          file_, point_text(v)));
        v = to->second;
        if (v == start) break;
      }
      for (const int v : loop) on_boundary_.insert(v);
      split_loop(loop);
    }
  }

  // One boundary loop into curves at the points where the edges' name changes.
  void split_loop(std::vector<int> loop) {
    const std::size_t n = loop.size();
    const auto name_of = [&](std::size_t i) { return edges_[edge_key(loop[i], loop[(i + 1) % n])].name; };
    std::size_t start = n;
    for (std::size_t i = 0; i < n && start == n; ++i)
      if (name_of(i) != name_of((i + n - 1) % n)) start = i;
    if (start == n) {
      // One name all round: one closed curve from its sharpest vertex.
      start = 0;
      double sharpest = -1.0;
      for (std::size_t i = 0; i < n; ++i) {
        const double t = turn(loop[(i + n - 1) % n], loop[i], loop[(i + 1) % n]);
        if (t > sharpest) sharpest = t, start = i;
      }
    }
    std::rotate(loop.begin(), loop.begin() + static_cast<std::ptrdiff_t>(start), loop.end());
    std::vector<int> stretch{loop[0]};
    for (std::size_t i = 0; i < n; ++i) {
      stretch.push_back(loop[(i + 1) % n]);
      if (i + 1 == n || name_of(i + 1) != name_of(i)) {
        curve_ends_.insert(stretch.front());
        add_curve(stretch, name_of(i), false);
        stretch = {loop[(i + 1) % n]};
      }
    }
  }

  // An edge between two cells that must stay an edge: named in the file, or between two regions.
  bool is_constraint(const EdgeInfo& e) const {
    if (e.count != 2) return false;
    if (e.name >= 0) return true;
    const double r1 = region_of(e.first.cell), r2 = region_of(e.second_cell);
    return !std::isnan(r1) && !std::isnan(r2) && r1 != r2;
  }

  void trace_constraints() {
    std::unordered_map<int, std::vector<std::uint64_t>> at_point;
    std::vector<std::uint64_t> constraint_edges;
    for (const std::uint64_t key : order_) {
      const EdgeInfo& e = edges_[key];
      if (!is_constraint(e)) continue;
      constraint_edges.push_back(key);
      at_point[e.first.a].push_back(key);
      at_point[e.first.b].push_back(key);
    }
    const auto stop = [&](int v) {
      const std::vector<std::uint64_t>& here = at_point[v];
      return here.size() != 2 || on_boundary_.count(v) != 0 || edges_[here[0]].name != edges_[here[1]].name;
    };
    std::set<std::uint64_t> used;
    const auto walk = [&](int from, std::uint64_t key) {
      std::vector<int> chain{from};
      const int name = edges_[key].name;
      for (int v = from;;) {
        used.insert(key);
        const EdgeInfo& e = edges_[key];
        v = e.first.a == v ? e.first.b : e.first.a;
        chain.push_back(v);
        if (v == from || stop(v)) break;
        const std::vector<std::uint64_t>& here = at_point[v];
        key = here[0] == key ? here[1] : here[0];
      }
      add_curve(chain, name, true);
    };
    // Open chains from their stops first, then the closed ones that have none.
    for (const std::uint64_t key : constraint_edges)
      for (const int v : {edges_[key].first.a, edges_[key].first.b})
        if (used.count(key) == 0 && stop(v)) walk(v, key);
    for (const std::uint64_t key : constraint_edges)
      if (used.count(key) == 0) walk(edges_[key].first.a, key);
  }

  // A seed per part of the domain between constraints, at a triangle's centroid, with its attribute
  // and name.
  void seed_regions() {
    if (mesh_.region.empty()) return;
    std::vector<int> part(static_cast<std::size_t>(cell_count()), -1);
    std::unordered_map<int, std::vector<int>> neighbours;
    for (const std::uint64_t key : order_) {
      const EdgeInfo& e = edges_[key];
      if (e.count != 2 || is_constraint(e)) continue;
      neighbours[e.first.cell].push_back(e.second_cell);
      neighbours[e.second_cell].push_back(e.first.cell);
    }
    for (int c = 0; c < static_cast<int>(mesh_.triangles.size()); ++c) {
      if (part[static_cast<std::size_t>(c)] >= 0) continue;
      std::vector<int> stack{c};
      part[static_cast<std::size_t>(c)] = c;
      while (!stack.empty()) {
        const int d = stack.back();
        stack.pop_back();
        for (const int n : neighbours[d])
          if (part[static_cast<std::size_t>(n)] < 0) part[static_cast<std::size_t>(n)] = c, stack.push_back(n);
      }
      const double attribute = mesh_.region[static_cast<std::size_t>(c)];
      if (attribute == 0.0) continue;
      const auto& t = mesh_.triangles[static_cast<std::size_t>(c)];
      GeometryRegion r;
      r.p = (at(t[0]) + at(t[1]) + at(t[2])) * (1.0 / 3.0);
      r.attribute = attribute;
      r.name = region_name(mesh_, attribute);
      r.file = file_;
      raw_.regions.push_back(r);
    }
  }

  void add_fixed_points() {
    if (mesh_.kind.size() != mesh_.points.size()) return;
    std::vector<std::uint8_t> used(mesh_.points.size(), 0), on_quad(mesh_.points.size(), 0);
    for (int c = 0; c < cell_count(); ++c)
      for (const int v : cell(c)) {
        used[static_cast<std::size_t>(v)] = 1;
        if (is_quad(c)) on_quad[static_cast<std::size_t>(v)] = 1;
      }
    for (std::size_t i = 0; i < mesh_.points.size(); ++i) {
      if (mesh_.kind[i] != NodeKind::Fixed || !used[i]) continue;
      const int v = static_cast<int>(i);
      const bool boundary = on_boundary_.count(v) != 0;
      if (boundary ? curve_ends_.count(v) != 0 : on_quad[i] != 0) continue;
      raw_.points.push_back({mesh_.points[i], file_, 0});
    }
  }

  // The physical group (Mesh::curve_groups) of the file's curve `name`; null for none.
  const CurveGroupTag* group_of(int name) const {
    if (name < 0) return nullptr;
    for (const CurveGroupTag& g : mesh_.curve_groups)
      if (std::find(g.curves.begin(), g.curves.end(), name) != g.curves.end()) return &g;
    return nullptr;
  }

  // A name given twice: NAME, NAME_2, NAME_3, ..., each with the group NAME. A physical group of the
  // file becomes a group with its tag over the curves made from it (the outputs write them as one).
  void unique_names() {
    std::map<std::string, std::vector<std::size_t>> by_name;
    std::set<std::string> taken;
    for (std::size_t c = 0; c < raw_.curves.size(); ++c) {
      by_name[raw_.curves[c].name].push_back(c);
      taken.insert(raw_.curves[c].name);
    }
    for (const auto& [name, curves] : by_name) {
      if (curves.size() < 2) continue;
      std::vector<std::string> names{name};
      for (std::size_t k = 1, suffix = 2; k < curves.size(); ++k) {
        std::string candidate;
        do candidate = fmt::format("{}_{}", name, suffix++);
        while (taken.count(candidate) != 0);
        taken.insert(candidate);
        raw_.curves[curves[k]].name = candidate;
        names.push_back(candidate);
      }
      raw_.groups.push_back({name, names});
      // One physical group: the outputs keep it whole, so the note says only how to select its parts.
      const CurveGroupTag* group = group_of(source_[curves.front()]);
      for (const std::size_t c : curves)
        if (group_of(source_[c]) != group) group = nullptr;
      if (group != nullptr)
        raw_.notes.push_back(fmt::format(
            "{}: the physical group '{}' (tag {}) is on {} separate curves: {} (a selection of curves by '{}' takes "
            "them all; the mesh files write them as one group '{}' with tag {})",
            file_, name, group->tag, curves.size(), fmt::join(names, ", "), name, name, group->tag));
      else
        raw_.notes.push_back(
            fmt::format("{}: '{}' names {} separate curves: {} (a selection of curves by '{}' takes them all)", file_,
                        name, curves.size(), fmt::join(names, ", "), name));
    }
    for (const CurveGroupTag& g : mesh_.curve_groups) {
      std::vector<std::string> names;
      for (std::size_t c = 0; c < raw_.curves.size(); ++c)
        if (group_of(source_[c]) == &g) names.push_back(raw_.curves[c].name);
      if (names.empty()) continue;
      const std::string name = gis::plain_name(g.name);
      const auto same = std::find_if(raw_.groups.begin(), raw_.groups.end(), [&](const CurveGroup& other) {
        return other.tag == 0 && other.name == name && other.curves == names;
      });
      if (same != raw_.groups.end())
        same->tag = g.tag;
      else
        raw_.groups.push_back({name, names, g.tag});
    }
  }

  const Mesh& mesh_;
  const std::vector<std::array<int, 4>>& quads_;
  std::string file_;
  std::unordered_map<std::uint64_t, EdgeInfo> edges_;
  std::vector<std::uint64_t> order_;  // edges in the order of their first cell, for a stable output
  std::vector<int> source_;           // per raw curve, the file's curve it came from (-1 none)
  std::set<int> on_boundary_, curve_ends_;
  int unnamed_boundaries_ = 0, unnamed_constraints_ = 0;
  RawGeometry raw_;
};

}  // namespace

RawGeometry mesh_as_geometry(const Mesh& mesh, const std::vector<std::array<int, 4>>& quads, const std::string& file) {
  return MeshGeometryBuilder(mesh, quads, file).build();
}

RawGeometry read_mesh_geometry(const std::string& path) {
  MeshReadReport report;
  SurfaceCells cells;
  const Mesh mesh = read_mesh(path, report, &cells);
  if (!report.off_plane.empty())
    throw InputError(fmt::format("{}: a mesh used as a geometry must lie in the plane z = 0 (a 2-D mesh); {}", path,
                                 report.off_plane));
  if (mesh.triangles.empty() && cells.quads.empty())
    throw InputError(fmt::format("{}: the mesh has no triangles or quadrangles", path));
  if (!mesh.triangles.empty()) check_mesh_triangles(mesh, report.reoriented, path);
  return mesh_as_geometry(mesh, cells.quads, path);
}

OtherGeometryFile mesh_geometry_files() {
  return [](const std::string& path, const std::string& ext) -> std::optional<RawGeometry> {
    if (!is_mesh_geometry_extension(ext)) return std::nullopt;
    return read_mesh_geometry(path);
  };
}

}  // namespace pdmesh
