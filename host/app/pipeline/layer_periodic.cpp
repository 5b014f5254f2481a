// [[periodic]] with [[boundary_layer]]: the wall chain ends on periodic curves, their tied end columns
// made exact transforms of each other, and the merged mesh's pairs.
#include "app/pipeline/layer_periodic.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"

namespace pdmesh {

namespace {

int curve_named(const Geometry& g, const std::string& name) { return curves_by_name(g, {name}, "periodic layers")[0]; }

// The curve among `curves` (all of the geometry's when null) other than `not_this` with an end at p;
// -1 when none.
int curve_ending_at(const Geometry& g, const std::vector<int>* curves, Vec2 p, int not_this = -1) {
  const auto ends_here = [&](int c) {
    const Curve& k = g.curves[static_cast<std::size_t>(c)];
    return c != not_this && !k.points.empty() && (k.points.front() == p || k.points.back() == p);
  };
  if (curves != nullptr) {
    for (const int c : *curves)
      if (ends_here(c)) return c;
    return -1;
  }
  for (std::size_t c = 0; c < g.curves.size(); ++c)
    if (ends_here(static_cast<int>(c))) return static_cast<int>(c);
  return -1;
}

std::string table_head(const CaseConfig::Periodic& p) {
  return fmt::format("{}: [[periodic]] curves = [\"{}\", \"{}\"]", p.where, quote_input(p.source),
                     quote_input(p.image));
}

// The angle (degrees) between the wall at end ray r's wall node and `curve` leaving the same point.
double meeting_angle(const LayerMesh& m, int r, const Curve& curve) {
  const Vec2 p = m.nodes[static_cast<std::size_t>(m.rays[static_cast<std::size_t>(r)].wall_node)];
  const bool first = std::binary_search(m.chain_ray_begin.begin(), m.chain_ray_begin.end(), r);
  const int step = first ? 1 : -1;
  Vec2 along{0.0, 0.0};
  for (int k = r + step; k >= 0 && k < static_cast<int>(m.rays.size()); k += step) {
    const Vec2 q = m.nodes[static_cast<std::size_t>(m.rays[static_cast<std::size_t>(k)].wall_node)];
    if (q == p) continue;
    along = q - p;
    break;
  }
  const std::size_t n = curve.points.size();
  const Vec2 leaving = curve.points.front() == p ? curve.points[1] - p : curve.points[n - 2] - p;
  const double c = dot(along, leaving) / (norm(along) * norm(leaving));
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

}  // namespace

PeriodicLayerEnds periodic_layer_ends(const std::vector<PeriodicTable>& tables, const Geometry& geometry,
                                      const std::vector<int>& walls, const CaseConfig::BoundaryLayer& b) {
  PeriodicLayerEnds out;
  for (const PeriodicTable& t : tables) {
    const CaseConfig::Periodic& p = *t.config;
    const int s = curve_named(geometry, p.source), i = curve_named(geometry, p.image);
    const Curve& source = geometry.curves[static_cast<std::size_t>(s)];
    const Curve& image = geometry.curves[static_cast<std::size_t>(i)];
    for (const Vec2 at : {source.points.front(), source.points.back()}) {
      const Vec2 mapped = t.transform.apply(at);
      const Vec2 there = dist(mapped, image.points.front()) <= dist(mapped, image.points.back()) ? image.points.front()
                                                                                                 : image.points.back();
      const int wall_here = curve_ending_at(geometry, &walls, at),
                wall_there = curve_ending_at(geometry, &walls, there);
      if (wall_here >= 0 && wall_there >= 0) {
        out.tied.push_back({at, there});
        out.table.push_back(&t);
        continue;
      }
      if (wall_here < 0 && wall_there < 0) continue;
      // The layers end on one side only: name the curve that meets the other side there.
      const Vec2 with = wall_here >= 0 ? at : there, without = wall_here >= 0 ? there : at;
      const int other = curve_ending_at(geometry, nullptr, without, wall_here >= 0 ? i : s);
      throw InputError(fmt::format(
          "{}: the layers of the [[boundary_layer]] at {} end on '{}' at ({:.9g}, {:.9g}) (wall '{}') but not on '{}' "
          "at its periodic image "
          "({:.9g}, {:.9g}){}; the walls at both ends of a periodic curve pair need layers from one "
          "[[boundary_layer]] table",
          table_head(p), b.curves_where, quote_input(wall_here >= 0 ? p.source : p.image), with.x, with.y,
          quote_input(geometry.curves[static_cast<std::size_t>(wall_here >= 0 ? wall_here : wall_there)].name),
          quote_input(wall_here >= 0 ? p.image : p.source), without.x, without.y,
          other >= 0 ? fmt::format(" (curve '{}' meets it there)",
                                   quote_input(geometry.curves[static_cast<std::size_t>(other)].name))
                     : std::string()));
    }
  }
  return out;
}

std::vector<PeriodicColumn> match_periodic_columns(LayerMesh& layers, const Geometry& geometry,
                                                   const PeriodicLayerEnds& ends, const CaseConfig::BoundaryLayer& b) {
  std::vector<PeriodicColumn> columns;
  for (std::size_t k = 0; k < ends.tied.size(); ++k) {
    const PeriodicTable& t = *ends.table[k];
    const CaseConfig::Periodic& p = *t.config;
    const int rs = end_ray_at(layers, ends.tied[k].a), ri = end_ray_at(layers, ends.tied[k].b);
    if (rs < 0 || ri < 0)
      throw Error(fmt::format("periodic layers: no end ray at ({}, {}) or ({}, {})", ends.tied[k].a.x, ends.tied[k].a.y,
                              ends.tied[k].b.x, ends.tied[k].b.y));
    const LayerRay& source = layers.rays[static_cast<std::size_t>(rs)];
    const LayerRay& image = layers.rays[static_cast<std::size_t>(ri)];
    if (source.nodes.size() != image.nodes.size())
      throw Error(fmt::format("periodic layers: the tied end columns at ({}, {}) and ({}, {}) have {} and {} nodes",
                              ends.tied[k].a.x, ends.tied[k].a.y, ends.tied[k].b.x, ends.tied[k].b.y,
                              source.nodes.size(), image.nodes.size()));
    double worst = 0.0;
    Vec2 where = ends.tied[k].b;
    for (std::size_t j = 1; j < source.nodes.size(); ++j) {
      const Vec2 mapped = t.transform.apply(layers.nodes[static_cast<std::size_t>(source.nodes[j])]);
      const Vec2 built = layers.nodes[static_cast<std::size_t>(image.nodes[j])];
      if (dist(mapped, built) > worst) worst = dist(mapped, built), where = built;
    }
    if (!(worst <= t.tolerance)) {
      const int s = curve_named(geometry, p.source), i = curve_named(geometry, p.image);
      throw InputError(fmt::format(
          "{}: the walls are not periodic: wall '{}' meets '{}' at ({:.9g}, {:.9g}) at {:.6g} deg, wall '{}' meets "
          "'{}' at ({:.9g}, {:.9g}) at {:.6g} deg; the layers of the [[boundary_layer]] at {} there are {:.3g} apart "
          "at ({:.9g}, {:.9g}), above "
          "the tolerance {:.3g} (1e-6 of the geometry's diagonal)",
          table_head(p), quote_input(geometry.curves[static_cast<std::size_t>(source.curve)].name),
          quote_input(p.source), ends.tied[k].a.x, ends.tied[k].a.y,
          meeting_angle(layers, rs, geometry.curves[static_cast<std::size_t>(s)]),
          quote_input(geometry.curves[static_cast<std::size_t>(image.curve)].name), quote_input(p.image),
          ends.tied[k].b.x, ends.tied[k].b.y, meeting_angle(layers, ri, geometry.curves[static_cast<std::size_t>(i)]),
          b.curves_where, worst, where.x, where.y, t.tolerance));
    }
    // The image column is the source's, transformed: the same bits on every run and in the pairs.
    for (std::size_t j = 1; j < source.nodes.size(); ++j)
      layers.nodes[static_cast<std::size_t>(image.nodes[j])] =
          t.transform.apply(layers.nodes[static_cast<std::size_t>(source.nodes[j])]);
    // Only a column along its curve lies on it (an end ray off the curve leaves the curve whole, its
    // wall node one of the core's pairs).
    const auto along = [&](const LayerRay& r, const std::string& name) {
      return r.slide_segment >= 0 &&
             geometry.curves[static_cast<std::size_t>(
                                 geometry.segments[static_cast<std::size_t>(r.slide_segment)].curve)]
                     .name == name;
    };
    if (!along(source, p.source) || !along(image, p.image)) continue;
    PeriodicColumn c{p.source, p.image, {}, {}};
    for (std::size_t j = 0; j < source.nodes.size(); ++j) {
      c.source_nodes.push_back(layers.nodes[static_cast<std::size_t>(source.nodes[j])]);
      c.image_nodes.push_back(layers.nodes[static_cast<std::size_t>(image.nodes[j])]);
    }
    columns.push_back(std::move(c));
  }
  return columns;
}

std::vector<PeriodicNodes> merged_periodic_pairs(const MixedMesh& merged, const std::vector<PeriodicColumn>& columns,
                                                 const MeshInputs& core_inputs) {
  const auto index_of = [&](const std::string& name) {
    const auto it = std::find(merged.curve_names.begin(), merged.curve_names.end(), name);
    if (it == merged.curve_names.end()) throw Error(fmt::format("periodic layers: curve '{}' not in the mesh", name));
    return static_cast<int>(it - merged.curve_names.begin());
  };
  std::vector<PeriodicNodes> out;
  for (const PeriodicNodes& core : core_inputs.periodic) {
    const std::string& source = core_inputs.geometry.curves[static_cast<std::size_t>(core.source_curve)].name;
    const std::string& image = core_inputs.geometry.curves[static_cast<std::size_t>(core.image_curve)].name;
    PeriodicNodes pair = core;
    pair.source_curve = index_of(source);
    pair.image_curve = index_of(image);
    for (const PeriodicColumn& c : columns) {
      if (c.source != source || c.image != image) continue;
      // The column below its top (the top is the core curve's end): in the curve's order, from the
      // wall up where the curve starts at the top, down to the wall where it ends there.
      const std::vector<Vec2> below_s(c.source_nodes.begin(), c.source_nodes.end() - 1);
      const std::vector<Vec2> below_i(c.image_nodes.begin(), c.image_nodes.end() - 1);
      if (pair.source.front() == c.source_nodes.back()) {
        pair.source.insert(pair.source.begin(), below_s.begin(), below_s.end());
        pair.image.insert(pair.image.begin(), below_i.begin(), below_i.end());
      } else if (pair.source.back() == c.source_nodes.back()) {
        pair.source.insert(pair.source.end(), below_s.rbegin(), below_s.rend());
        pair.image.insert(pair.image.end(), below_i.rbegin(), below_i.rend());
      } else {
        throw Error(fmt::format("periodic layers: the column's top ({}, {}) is not an end of the core's '{}'",
                                c.source_nodes.back().x, c.source_nodes.back().y, source));
      }
    }
    out.push_back(std::move(pair));
  }
  return out;
}

}  // namespace pdmesh
