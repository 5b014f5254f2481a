// Shared checks and helpers of the mesh writers and readers.
#include "io/mesh_io_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numeric>
#include <optional>
#include <set>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/g17.hpp"
#include "core/predicates.hpp"

namespace pdmesh {

std::string writable_name(std::string name, bool no_blanks) {
  for (char& ch : name) {
    if (ch == '"' || ch == '\n' || ch == '\r' || (no_blanks && (ch == ' ' || ch == '\t'))) ch = '_';
  }
  return name;
}

std::string curve_label(const Mesh& mesh, std::size_t c, bool no_blanks) {
  std::string name = c < mesh.curve_names.size() ? mesh.curve_names[c] : std::string();
  if (name.empty()) name = fmt::format("curve{}", c);
  return writable_name(std::move(name), no_blanks);
}

void check_mesh_for_writing(const Mesh& mesh, const std::string& what) {
  const auto n = static_cast<long long>(mesh.points.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int v : mesh.triangles[t]) {
      if (v < 0 || v >= n) {
        throw InputError(fmt::format("{}: triangle {} refers to point {} but the mesh has {} points", what, t, v, n));
      }
    }
  }
  const auto curves = static_cast<long long>(mesh.curve_names.size());
  for (std::size_t e = 0; e < mesh.boundary_edges.size(); ++e) {
    const auto& be = mesh.boundary_edges[e];
    if (be.a < 0 || be.a >= n || be.b < 0 || be.b >= n) {
      throw InputError(
          fmt::format("{}: boundary edge {} ({}-{}) refers to a point outside 0..{}", what, e, be.a, be.b, n - 1));
    }
    if (be.curve < 0 || be.curve >= curves) {
      throw InputError(fmt::format("{}: boundary edge {} is on curve {} but the mesh has {} curve names", what, e,
                                   be.curve, curves));
    }
  }
  for (const CurveGroupTag& g : mesh.curve_groups) {
    if (g.tag <= 0)
      throw InputError(fmt::format("{}: curve group '{}' has tag {}; tags are positive", what, g.name, g.tag));
    for (const int c : g.curves)
      if (c < 0 || c >= curves)
        throw InputError(fmt::format("{}: curve group '{}' lists curve {} but the mesh has {} curve names", what,
                                     g.name, c, curves));
  }
  if (!mesh.kind.empty() && mesh.kind.size() != mesh.points.size()) {
    throw InputError(fmt::format("{}: {} node kinds for {} points", what, mesh.kind.size(), n));
  }
  if (!mesh.spacing.empty() && mesh.spacing.size() != mesh.points.size()) {
    throw InputError(fmt::format("{}: {} spacing values for {} points", what, mesh.spacing.size(), n));
  }
  for (const PointValues& d : mesh.point_data)
    if (d.components < 1 || d.values.size() != static_cast<std::size_t>(d.components) * mesh.points.size())
      throw InputError(fmt::format("{}: point data '{}' has {} values for {} points of {} components", what, d.name,
                                   d.values.size(), n, d.components));
}

std::string_view region_name(const Mesh& mesh, double attribute) {
  const auto named = std::lower_bound(mesh.region_names.begin(), mesh.region_names.end(), attribute,
                                      [](const RegionName& r, double a) { return r.attribute < a; });
  if (named == mesh.region_names.end() || named->attribute != attribute) return {};
  return named->name;
}

std::string region_label(const Mesh& mesh, double attribute) {
  const std::string_view name = region_name(mesh, attribute);
  return name.empty() ? fmt::format("region_{}", attribute) : writable_name(std::string(name));
}

namespace {

// A regional attribute that is a positive integer a physical tag can hold.
bool whole_tag(double a) { return a >= 1.0 && a <= 2147483647.0 && a == std::floor(a); }

}  // namespace

RegionSurfaces region_surfaces(const Mesh& mesh, long long first) {
  RegionSurfaces s;
  s.of_triangle.assign(mesh.triangles.size(), 0);
  if (mesh.region.size() != mesh.triangles.size() || mesh.triangles.empty()) {
    s.names = {"domain"};
    s.tags = {first};
    return s;
  }
  std::vector<double>& attributes = s.attributes;
  attributes = mesh.region;
  std::sort(attributes.begin(), attributes.end());
  attributes.erase(std::unique(attributes.begin(), attributes.end()), attributes.end());
  std::set<long long> taken;
  for (const double a : attributes)
    if (whole_tag(a)) taken.insert(static_cast<long long>(a));
  for (std::size_t j = 0; j < attributes.size(); ++j) {
    const double a = attributes[j];
    s.names.push_back(region_label(mesh, a));
    if (whole_tag(a)) {
      s.tags.push_back(static_cast<long long>(a));
      continue;
    }
    long long tag = first + static_cast<long long>(j);
    while (taken.count(tag) != 0) ++tag;
    taken.insert(tag);
    s.tags.push_back(tag);
  }
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    s.of_triangle[i] =
        static_cast<int>(std::lower_bound(attributes.begin(), attributes.end(), mesh.region[i]) - attributes.begin());
  return s;
}

std::optional<double> region_attribute(std::string_view name) {
  constexpr std::string_view prefix = "region_";
  if (name.substr(0, prefix.size()) != prefix || name.size() == prefix.size()) return std::nullopt;
  const std::string number(name.substr(prefix.size()));
  // fmt's shortest form of a finite double: digits, '-', '.', 'e', '+'.
  if (number.find_first_not_of("0123456789-+.e") != std::string::npos) return std::nullopt;
  char* end = nullptr;
  const double a = std::strtod(number.c_str(), &end);
  if (end != number.c_str() + number.size() || !std::isfinite(a)) return std::nullopt;
  return a;
}

CurveTags curve_tags(const Mesh& mesh) {
  CurveTags t;
  const std::size_t curves = mesh.curve_names.size();
  t.of_curve.assign(curves, 0);
  std::map<long long, CurveTags::Group> by_tag;
  for (const CurveGroupTag& g : mesh.curve_groups)
    for (const int c : g.curves) {
      if (t.of_curve[static_cast<std::size_t>(c)] != 0) continue;
      t.of_curve[static_cast<std::size_t>(c)] = g.tag;
      CurveTags::Group& group = by_tag[g.tag];
      if (group.curves.empty()) group = {g.tag, g.name, {}};
      group.curves.push_back(c);
    }
  long long next = 1;
  for (std::size_t c = 0; c < curves; ++c) {
    if (t.of_curve[c] != 0) continue;
    while (by_tag.count(next) != 0) ++next;
    t.of_curve[c] = next;
    by_tag[next] = {next, curve_label(mesh, c), {static_cast<int>(c)}};
  }
  for (auto& [tag, group] : by_tag) {
    std::sort(group.curves.begin(), group.curves.end());
    t.groups.push_back(std::move(group));
  }
  return t;
}

std::size_t CurveTags::group_of_tag(long long tag) const {
  return static_cast<std::size_t>(
      std::lower_bound(groups.begin(), groups.end(), tag, [](const Group& g, long long v) { return g.tag < v; }) -
      groups.begin());
}

std::vector<std::size_t> boundary_edges_by_curve(const Mesh& mesh) {
  std::vector<std::size_t> order(mesh.boundary_edges.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) {
    return mesh.boundary_edges[i].curve < mesh.boundary_edges[j].curve;
  });
  return order;
}

std::string coord(double v) {
  std::string out;
  append_g17(out, v);
  return out;
}

void orient_triangles_ccw(Mesh& mesh, MeshReadReport& report) {
  std::size_t flipped = 0;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    auto& t = mesh.triangles[i];
    if (orient2d(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]) < 0.0) {
      std::swap(t[1], t[2]);
      report.reoriented.push_back(i);
      ++flipped;
    }
  }
  report.reoriented_triangles += flipped;
  if (flipped > 0) report.notes.push_back(fmt::format("turned {} clockwise triangles counter-clockwise", flipped));
}

void orient_quads_ccw(const std::vector<Vec2>& points, std::vector<std::array<int, 4>>& quads, const std::string& file,
                      MeshReadReport& report) {
  std::size_t flipped = 0;
  for (auto& q : quads) {
    double area = 0.0;
    for (std::size_t k = 0; k < 4; ++k) area += cross(points[q[k]], points[q[(k + 1) % 4]]);
    if (area < 0.0) {
      std::swap(q[1], q[3]);
      ++flipped;
    }
  }
  if (flipped > 0)
    report.notes.push_back(fmt::format("{}: turned {} clockwise quadrangles counter-clockwise", file, flipped));
}

}  // namespace pdmesh
