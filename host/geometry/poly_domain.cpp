// Triangle's semantics for .poly files (see poly_domain.hpp and poly_reader.hpp): the faces of the
// segment graph (geometry/planar_faces), the domain among them, and the curves, points, regions and
// notes that follow.
#include "geometry/poly_domain.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <utility>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/predicates.hpp"
#include "geometry/geometry_detail.hpp"
#include "geometry/planar_faces.hpp"

namespace pdmesh::detail {
namespace {

enum class Kind { Boundary, Constraint, Dropped };

// The graph the faces are traced on: vertices merged where they coincide, segments without
// repeats, and the convex hull's edges when asked for.
struct Graph {
  std::vector<Vec2> points;               // distinct vertex positions
  std::vector<int> vertex_of;             // file vertex -> graph vertex
  std::vector<int> first_vertex;          // graph vertex -> first file vertex there
  std::vector<std::array<int, 2>> edges;  // graph vertex pairs
  std::vector<int> segment;               // per edge: the file segment, -1 for a hull edge
};

Graph make_graph(const std::string& path, int base, const std::vector<PolyVertex>& vertices,
                 const std::vector<PolySegment>& segments, std::vector<std::string>& notes) {
  Graph g;
  std::map<std::pair<double, double>, int> at;
  int merged = 0, merged_first = -1;
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    const auto [it, fresh] = at.emplace(std::pair{vertices[v].p.x, vertices[v].p.y}, static_cast<int>(g.points.size()));
    if (fresh) {
      g.points.push_back(vertices[v].p);
      g.first_vertex.push_back(static_cast<int>(v));
    } else if (merged++ == 0) {
      merged_first = static_cast<int>(v);
    }
    g.vertex_of.push_back(it->second);
  }
  if (merged > 0) {
    notes.push_back(
        fmt::format("{}:{}: {} vertex{} at the same point as an earlier one (the first: vertex {}) merged "
                    "with it, as Triangle does",
                    path, vertices[merged_first].line, merged, merged == 1 ? "" : "es", merged_first + base));
  }
  std::map<std::pair<int, int>, int> seen;
  int repeats = 0, repeat_first = -1;
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const int a = g.vertex_of[segments[s].a], b = g.vertex_of[segments[s].b];
    if (a == b) {
      throw InputError(fmt::format("{}:{}: segment {} joins vertices {} and {}, which are the same point {}", path,
                                   segments[s].line, s + base, segments[s].a + base, segments[s].b + base,
                                   format_point(g.points[a])));
    }
    if (!seen.emplace(std::pair{std::min(a, b), std::max(a, b)}, static_cast<int>(s)).second) {
      if (repeats++ == 0) repeat_first = static_cast<int>(s);
      continue;
    }
    g.edges.push_back({a, b});
    g.segment.push_back(static_cast<int>(s));
  }
  if (repeats > 0) {
    notes.push_back(fmt::format("{}:{}: {} segment{} repeating an earlier one (the first: segment {}) ignored", path,
                                segments[repeat_first].line, repeats, repeats == 1 ? "" : "s", repeat_first + base));
  }
  return g;
}

// The convex hull of all graph vertices, counter-clockwise, keeping vertices that lie on its edges.
std::vector<int> convex_hull(const std::vector<Vec2>& points) {
  std::vector<int> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int i, int j) {
    return points[i].x < points[j].x || (points[i].x == points[j].x && points[i].y < points[j].y);
  });
  std::vector<int> hull;
  auto chain = [&](auto begin, auto end) {
    const std::size_t floor = hull.size();
    for (auto it = begin; it != end; ++it) {
      while (hull.size() >= floor + 2 && orient2d(points[hull[hull.size() - 2]], points[hull.back()], points[*it]) < 0)
        hull.pop_back();
      hull.push_back(*it);
    }
    hull.pop_back();
  };
  chain(order.begin(), order.end());
  chain(order.rbegin(), order.rend());
  return hull;
}

void add_hull(const std::string& path, Graph& g) {
  const std::vector<int> hull = convex_hull(g.points);
  double twice = 0.0;
  for (std::size_t k = 0; k < hull.size(); ++k)
    twice += cross(g.points[hull[k]] - g.points[hull[0]], g.points[hull[(k + 1) % hull.size()]] - g.points[hull[0]]);
  if (hull.size() < 3 || !(twice > 0)) {
    throw InputError(
        fmt::format("{}: the convex hull of the vertices encloses no area (fewer than three vertices, or all on one "
                    "line): nothing to mesh",
                    path));
  }
  std::map<std::pair<int, int>, int> present;
  for (const auto& e : g.edges) present.emplace(std::pair{std::min(e[0], e[1]), std::max(e[0], e[1])}, 0);
  for (std::size_t k = 0; k < hull.size(); ++k) {
    const int a = hull[k], b = hull[(k + 1) % hull.size()];
    if (present.count({std::min(a, b), std::max(a, b)})) continue;
    g.edges.push_back({a, b});
    g.segment.push_back(-1);
  }
}

// A maximal chain of edges of one kind and one marker, broken where `stop` says; cycles close.
struct Chainer {
  const Graph& g;
  const std::vector<PolyVertex>& vertices;
  const std::vector<PolySegment>& segments;
  const std::vector<int>& kept_degree;  // per graph vertex, over the edges that are not dropped

  int edge_line(int e) const {
    return g.segment[e] >= 0 ? segments[g.segment[e]].line : vertices[g.first_vertex[g.edges[e][0]]].line;
  }

  void chain(const std::vector<int>& ids, bool constraint, std::vector<RawCurve>& curves,
             const std::string& path) const {
    std::map<int, std::vector<int>> incident;
    for (const int e : ids) {
      incident[g.edges[e][0]].push_back(e);
      incident[g.edges[e][1]].push_back(e);
    }
    auto stop = [&](int v) { return incident[v].size() != 2 || kept_degree[v] != 2; };
    std::map<int, bool> used;
    auto other = [&](int e, int v) { return g.edges[e][0] == v ? g.edges[e][1] : g.edges[e][0]; };
    auto walk = [&](int start, int first) {
      RawCurve curve;
      curve.file = path;
      curve.line = edge_line(first);
      curve.constraint = constraint;
      auto add = [&](int v) {
        curve.points.push_back(g.points[v]);
        curve.lines.push_back(vertices[g.first_vertex[v]].line);
      };
      add(start);
      int v = start, e = first;
      while (true) {
        used[e] = true;
        v = other(e, v);
        add(v);
        if (stop(v) || v == start) break;
        const auto& around = incident[v];
        e = around[0] == e ? around[1] : around[0];
        if (used[e]) break;
      }
      curves.push_back(std::move(curve));
    };
    for (const int e : ids)
      for (const int v : g.edges[e])
        if (!used[e] && stop(v)) walk(v, e);
    for (const int e : ids)
      if (!used[e]) walk(g.edges[e][0], e);
  }
};

// Even-odd parity of each bounded face (the unbounded face is even), by crossing edges from face to
// face; meaningful when every vertex with edges has two (the graph is disjoint loops).
std::vector<int> face_parity(const PlanarFaces& faces) {
  std::vector<int> parity(faces.outer.size(), -1);
  bool changed = true;
  while (changed) {
    changed = false;
    for (const auto& s : faces.sides) {
      if (s[0] == s[1]) continue;
      const int p0 = s[0] < 0 ? 0 : parity[s[0]], p1 = s[1] < 0 ? 0 : parity[s[1]];
      if (p0 >= 0 && s[1] >= 0 && p1 < 0) parity[s[1]] = p0 ^ 1, changed = true;
      if (p1 >= 0 && s[0] >= 0 && p0 < 0) parity[s[0]] = p1 ^ 1, changed = true;
    }
  }
  return parity;
}

// The passes of apply_poly_semantics over one file's planar graph, run in this order by it: the
// domain (holes, the hull), the regions, the edges' kinds, the curves, the isolated vertices, and the
// notes on where the even-odd rule would differ.
class PolySemantics {
 public:
  PolySemantics(const std::string& path, int base, const std::vector<PolyVertex>& vertices,
                const std::vector<PolySegment>& segments, PolyFile& result)
      : path_(path),
        base_(base),
        vertices_(vertices),
        segments_(segments),
        result_(result),
        g_(make_graph(path, base, vertices, segments, result.notes)),
        input_edges_(g_.edges.size()),
        faces_(planar_faces(g_.points, g_.edges)) {}

  // The domain: every bounded face but those holding a hole point; the convex hull's with
  // geometry.hull (or automatically when the segments enclose nothing).
  void find_domain(PolyHull hull) {
    const bool enclosed = remove_holes(nullptr);
    use_hull_ = hull == PolyHull::On || (hull == PolyHull::Automatic && !enclosed);
    if (use_hull_) {
      if (hull == PolyHull::Automatic) {
        result_.notes.push_back(
            fmt::format("{}: the segments enclose no area outside the holes: meshing the convex hull of the "
                        "vertices, as Triangle's -c does (geometry.hull)",
                        path_));
      }
      add_hull(path_, g_);
      faces_ = planar_faces(g_.points, g_.edges);
    }
    if (!remove_holes(&result_.notes)) {
      throw InputError(
          fmt::format("{}: the segments enclose no area outside the holes{}: nothing to mesh{}", path_,
                      use_hull_ ? "" : " and geometry.hull is false",
                      result_.holes.empty()
                          ? ""
                          : fmt::format(" (is the hole point on line {} meant to be there?)", result_.holes[0].line)));
    }
  }

  // Regional attributes: the face holding each point; a later one for the same face wins, as in Triangle.
  void tag_regions(const std::vector<GeometryRegion>& regions) {
    std::map<int, std::size_t> region_of_face;
    for (const GeometryRegion& r : regions) {
      const int f = locate_face(faces_, g_.points, g_.edges, r.p);
      if (f == -2) {
        throw InputError(
            fmt::format("{}: region point {} lies on a segment, between two regions; move it inside the "
                        "region it tags",
                        where(r.file, r.line), format_point(r.p)));
      }
      if (!in_domain(f)) {
        result_.notes.push_back(fmt::format(
            "{}: region point {} lies outside the domain ({}): its attribute {} is unused", where(r.file, r.line),
            format_point(r.p), f < 0 ? "outside every loop" : "in a hole", r.attribute));
        continue;
      }
      const auto [it, fresh] = region_of_face.emplace(f, result_.regions.size());
      if (!fresh) {
        const GeometryRegion& earlier = result_.regions[it->second];
        result_.notes.push_back(
            fmt::format("{}: region point {} lies in the same region as the one on line {}: its "
                        "attribute {} replaces {}, as in Triangle",
                        where(r.file, r.line), format_point(r.p), earlier.line, r.attribute, earlier.attribute));
        result_.regions[it->second] = r;
      } else {
        result_.regions.push_back(r);
      }
    }
  }

  // Triangle's maximum areas (its -a): pdmesh sizes by spacing, so each such region's subdomain is
  // sized (spacing/refine_regions.hpp, max_area_regions); the note says how.
  void note_max_areas() {
    const auto capped = std::count_if(result_.regions.begin(), result_.regions.end(),
                                      [](const GeometryRegion& r) { return r.max_area > 0; });
    if (capped == 0) return;
    const auto first = std::find_if(result_.regions.begin(), result_.regions.end(),
                                    [](const GeometryRegion& r) { return r.max_area > 0; });
    result_.notes.push_back(fmt::format(
        "{}:{}: {} region{} give{} a maximum triangle area (the first: {}); each such subdomain is sized so that "
        "its largest triangles have about that area (the first: spacing {:.4g}), unless the spacing field is a metric",
        path_, first->line, capped, capped == 1 ? "" : "s", capped == 1 ? "s" : "", first->max_area,
        max_area_spacing(first->max_area)));
  }

  // Each edge's kind from the faces on its sides, and the vertices' degrees (input and kept edges).
  void classify_edges() {
    kind_.assign(g_.edges.size(), Kind::Dropped);
    kept_degree_.assign(g_.points.size(), 0);
    input_degree_.assign(g_.points.size(), 0);
    int dropped = 0, dropped_first = -1;
    for (std::size_t e = 0; e < g_.edges.size(); ++e) {
      const int sides = (in_domain(faces_.sides[e][0]) ? 1 : 0) + (in_domain(faces_.sides[e][1]) ? 1 : 0);
      kind_[e] = sides == 2 ? Kind::Constraint : sides == 1 ? Kind::Boundary : Kind::Dropped;
      if (e < input_edges_)
        for (const int v : g_.edges[e]) ++input_degree_[v];
      if (kind_[e] == Kind::Dropped) {
        if (dropped++ == 0) dropped_first = static_cast<int>(e);
        continue;
      }
      for (const int v : g_.edges[e]) ++kept_degree_[v];
    }
    if (dropped > 0) {
      result_.notes.push_back(
          fmt::format("{}:{}: {} segment{} outside the domain (in a hole or outside every loop; the "
                      "first: segment {}) dropped",
                      path_, segments_[g_.segment[dropped_first]].line, dropped, dropped == 1 ? "" : "s",
                      g_.segment[dropped_first] + base_));
    }
  }

  // Curves: boundaries by marker (in order of first appearance), the hull's edges, then constraints.
  void chain_curves() const {
    const Chainer chainer{g_, vertices_, segments_, kept_degree_};
    for (const Kind k : {Kind::Boundary, Kind::Constraint}) {
      std::vector<long long> order;
      std::map<long long, std::vector<int>> by_marker;
      std::vector<int> hull_edges;
      for (std::size_t e = 0; e < g_.edges.size(); ++e) {
        if (kind_[e] != k) continue;
        if (g_.segment[e] < 0) {
          hull_edges.push_back(static_cast<int>(e));
          continue;
        }
        auto& ids = by_marker[segments_[g_.segment[e]].marker];
        if (ids.empty()) order.push_back(segments_[g_.segment[e]].marker);
        ids.push_back(static_cast<int>(e));
      }
      for (const long long marker : order)
        chainer.chain(by_marker[marker], k == Kind::Constraint, result_.curves, path_);
      const std::size_t first_hull = result_.curves.size();
      chainer.chain(hull_edges, k == Kind::Constraint, result_.curves, path_);
      for (std::size_t c = first_hull; c < result_.curves.size(); ++c)
        result_.curves[c].name =
            result_.curves.size() - first_hull == 1 ? "hull" : fmt::format("hull{}", c - first_hull);
    }
  }

  // Isolated vertices: nodes of the mesh where they lie in the domain.
  void keep_isolated_vertices() {
    int kept = 0, outside = 0, outside_first = -1;
    for (std::size_t v = 0; v < g_.points.size(); ++v) {
      if (input_degree_[v] > 0 || kept_degree_[v] > 0) continue;
      const int f = locate_face(faces_, g_.points, g_.edges, g_.points[v]);
      const PolyVertex& pv = vertices_[g_.first_vertex[v]];
      if (in_domain(f)) {
        result_.points.push_back({pv.p, path_, pv.line});
        ++kept;
      } else if (outside++ == 0) {
        outside_first = g_.first_vertex[v];
      }
    }
    if (kept > 0) {
      result_.notes.push_back(fmt::format("{}: {} isolated vert{} (on no segment) inside the domain kept as mesh nodes",
                                          path_, kept, kept == 1 ? "ex" : "ices"));
    }
    if (outside > 0) {
      result_.notes.push_back(fmt::format(
          "{}:{}: {} isolated vert{} outside the domain or on a segment (the first: "
          "vertex {}) dropped",
          path_, vertices_[outside_first].line, outside, outside == 1 ? "ex" : "ices", outside_first + base_));
    }
  }

  // Where the even-odd rule of curve files would have read the file differently: loops around a
  // face it would have made a hole, which Triangle's rule (no hole point in it) keeps in the domain.
  void note_even_odd_differences() {
    const bool loops_only =
        !use_hull_ && std::all_of(input_degree_.begin(), input_degree_.end(), [](int d) { return d == 0 || d == 2; });
    if (!loops_only) return;
    const std::vector<int> parity = face_parity(faces_);
    for (std::size_t f = 0; f < faces_.outer.size(); ++f) {
      if (parity[f] != 0 || !inside_[f]) continue;
      const int v = *std::min_element(faces_.outer[f].begin(), faces_.outer[f].end(),
                                      [&](int a, int b) { return g_.first_vertex[a] < g_.first_vertex[b]; });
      const PolyVertex& pv = vertices_[g_.first_vertex[v]];
      result_.notes.push_back(fmt::format(
          "{}:{}: the face inside the loop through vertex {} is meshed as a subdomain, not a hole: no hole point "
          "lies in it (Triangle's rule for .poly files; the even-odd rule of curve files would make it a hole)",
          path_, pv.line, g_.first_vertex[v] + base_));
    }
  }

 private:
  // Marks the faces holding a hole point out of the domain (noting hole points outside every loop
  // when `notes` is given); whether any face is left.
  bool remove_holes(std::vector<std::string>* notes) {
    inside_.assign(faces_.outer.size(), 1);
    for (const RawHolePoint& h : result_.holes) {
      const int f = locate_face(faces_, g_.points, g_.edges, h.p);
      if (f == -2) {
        throw InputError(fmt::format("{}: hole point {} lies on a segment; it must lie inside the hole it makes",
                                     where(h.file, h.line), format_point(h.p)));
      }
      if (f >= 0) {
        inside_[f] = 0;
      } else if (notes != nullptr) {
        notes->push_back(fmt::format("{}: hole point {} lies outside every loop: it removes nothing",
                                     where(h.file, h.line), format_point(h.p)));
      }
    }
    return std::find(inside_.begin(), inside_.end(), 1) != inside_.end();
  }

  bool in_domain(int f) const { return f >= 0 && inside_[f]; }

  const std::string& path_;
  int base_;
  const std::vector<PolyVertex>& vertices_;
  const std::vector<PolySegment>& segments_;
  PolyFile& result_;
  Graph g_;
  std::size_t input_edges_;  // the file's segments; the hull's edges come after them
  PlanarFaces faces_;
  std::vector<std::uint8_t> inside_;  // per bounded face: in the domain
  bool use_hull_ = false;
  std::vector<Kind> kind_;
  std::vector<int> kept_degree_, input_degree_;
};

}  // namespace

void apply_poly_semantics(const std::string& path, int base, const std::vector<PolyVertex>& vertices,
                          const std::vector<PolySegment>& segments, const std::vector<GeometryRegion>& regions,
                          PolyHull hull, PolyFile& result) {
  PolySemantics passes(path, base, vertices, segments, result);
  passes.find_domain(hull);
  passes.tag_regions(regions);
  passes.note_max_areas();
  passes.classify_edges();
  passes.chain_curves();
  passes.keep_isolated_vertices();
  passes.note_even_odd_differences();
}

}  // namespace pdmesh::detail
