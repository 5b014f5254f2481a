// Triangle .node/.ele/.poly reader.
// Format: https://www.cs.cmu.edu/~quake/triangle.node.html, triangle.ele.html, triangle.poly.html.
#include "io/triangle_reader.hpp"

#include <algorithm>
#include <map>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "io/text_file.hpp"

namespace pdmesh {
namespace {

constexpr std::string_view kKindComment = "# pdmesh: attribute 1 = node kind";
constexpr std::string_view kCurveComment = "# pdmesh curve ";

// "# pdmesh curve MARKER NAME" lines of a .poly file.
std::map<long long, std::string> curve_comments(const std::string& poly) {
  std::map<long long, std::string> names;
  LineScanner s("", poly);
  std::string_view line;
  while (s.next_line(line)) {
    if (line.substr(0, kCurveComment.size()) != kCurveComment) continue;
    std::string_view rest = line.substr(kCurveComment.size());
    const auto space = rest.find(' ');
    if (space == std::string_view::npos) continue;
    long long marker = 0;
    try {
      marker = s.to_int(rest.substr(0, space), "marker");
    } catch (const InputError&) {
      continue;  // not ours: an ordinary comment
    }
    names[marker] = std::string(rest.substr(space + 1));
  }
  return names;
}

}  // namespace

Mesh parse_triangle(const std::string& node_label, std::string node, const std::string& ele_label, std::string ele,
                    const std::string& poly_label, std::string poly, MeshReadReport& report) {
  Mesh mesh;
  const bool kinds = node.find(kKindComment) != std::string::npos;
  long long base = 1;
  {
    LineScanner s(node_label, std::move(node));
    const auto head = s.expect_tokens("the .node header", '#');
    if (head.size() < 2) s.fail("the .node header needs at least a point count and a dimension");
    const long long n = s.to_int(head[0], "point count");
    if (n < 0) s.fail("negative point count", head[0]);
    if (s.to_int(head[1], "dimension") != 2) s.fail("only dimension 2 is supported", head[1]);
    const long long nattr = head.size() > 2 ? s.to_int(head[2], "attribute count") : 0;
    const long long nbm = head.size() > 3 ? s.to_int(head[3], "boundary marker count") : 0;
    if (nattr < 0 || nbm < 0 || nbm > 1) s.fail("bad attribute or boundary marker count");
    s.check_count(n, static_cast<std::size_t>(2 * (3 + std::min(nattr, 1000LL) + nbm)), "point count");
    mesh.points.reserve(static_cast<std::size_t>(n));
    for (long long i = 0; i < n; ++i) {
      const auto t = s.expect_tokens("a point", '#');
      if (static_cast<long long>(t.size()) < 3 + nattr + nbm) {
        s.fail(fmt::format("a point needs {} fields", 3 + nattr + nbm), fmt::format("{} fields", t.size()));
      }
      const long long index = s.to_int(t[0], "point index");
      if (i == 0) {
        if (index != 0 && index != 1) s.fail("the first point index must be 0 or 1", t[0]);
        base = index;
      } else if (index != base + i) {
        s.fail(fmt::format("point indices must be consecutive: expected {}", base + i), t[0]);
      }
      mesh.points.push_back({s.to_double(t[1], "x"), s.to_double(t[2], "y")});
      if (kinds && nattr >= 1) {
        mesh.kind.push_back(static_cast<NodeKind>(s.to_index(t[3], 0, 2, "node kind")));
      }
    }
  }
  const auto n = static_cast<long long>(mesh.points.size());
  {
    LineScanner s(ele_label, std::move(ele));
    const auto head = s.expect_tokens("the .ele header", '#');
    if (head.size() < 2) s.fail("the .ele header needs a triangle count and nodes per triangle");
    const long long count = s.to_int(head[0], "triangle count");
    const long long per = s.to_int(head[1], "nodes per triangle");
    if (count < 0) s.fail("negative triangle count", head[0]);
    if (per != 3 && per != 6) s.fail("nodes per triangle must be 3 or 6", head[1]);
    s.check_count(count, static_cast<std::size_t>(2 * (1 + per)), "triangle count");
    // The first triangle attribute is the region's (triangle -A writes it, and so does pdmesh).
    const long long attributes = head.size() > 2 ? s.to_int(head[2], "attribute count") : 0;
    if (attributes < 0) s.fail("negative attribute count", head[2]);
    mesh.triangles.reserve(static_cast<std::size_t>(count));
    for (long long i = 0; i < count; ++i) {
      const auto t = s.expect_tokens("a triangle", '#');
      if (static_cast<long long>(t.size()) < 1 + per) s.fail(fmt::format("a triangle needs {} fields", 1 + per));
      std::array<int, 3> tri{};
      for (int k = 0; k < 3; ++k) {
        tri[static_cast<std::size_t>(k)] =
            static_cast<int>(s.to_index(t[static_cast<std::size_t>(1 + k)], base, base + n - 1, "point index") - base);
      }
      mesh.triangles.push_back(tri);
      if (attributes > 0) {
        if (static_cast<long long>(t.size()) < 2 + per) s.fail(fmt::format("a triangle needs {} fields", 2 + per));
        mesh.region.push_back(s.to_double(t[static_cast<std::size_t>(1 + per)], "for a triangle attribute"));
      }
    }
  }
  if (!poly.empty()) {
    const auto names = curve_comments(poly);
    LineScanner s(poly_label, std::move(poly));
    const auto head = s.expect_tokens("the .poly header", '#');
    if (head.empty()) s.fail("empty .poly header");
    const long long inline_points = s.to_int(head[0], "point count");
    if (inline_points < 0) s.fail("negative point count", head[0]);
    s.check_count(inline_points, 2, "point count");
    for (long long i = 0; i < inline_points; ++i) s.expect_line("a point", '#');  // the .node points are used
    const auto seg = s.expect_tokens("the segment header", '#');
    if (seg.empty()) s.fail("missing segment count");
    const long long count = s.to_int(seg[0], "segment count");
    const bool markers = seg.size() > 1 && s.to_int(seg[1], "boundary marker count") > 0;
    if (count < 0) s.fail("negative segment count", seg[0]);
    s.check_count(count, markers ? 8 : 6, "segment count");
    std::map<long long, int> curve_of;  // marker -> curve index
    for (const auto& [marker, name] : names) curve_of[marker] = 0;
    std::vector<std::array<long long, 3>> segments;
    for (long long i = 0; i < count; ++i) {
      const auto t = s.expect_tokens("a segment", '#');
      if (t.size() < (markers ? 4u : 3u)) s.fail("a segment needs an index, two points and a marker");
      const long long a = s.to_index(t[1], base, base + n - 1, "point index") - base;
      const long long b = s.to_index(t[2], base, base + n - 1, "point index") - base;
      const long long marker = markers ? s.to_int(t[3], "boundary marker") : 1;
      curve_of[marker] = 0;
      segments.push_back({a, b, marker});
    }
    for (auto& [marker, index] : curve_of) {
      index = static_cast<int>(mesh.curve_names.size());
      const auto it = names.find(marker);
      mesh.curve_names.push_back(it != names.end() ? it->second : fmt::format("marker{}", marker));
    }
    for (const auto& sgt : segments) {
      mesh.boundary_edges.push_back({static_cast<int>(sgt[0]), static_cast<int>(sgt[1]), curve_of[sgt[2]]});
    }
  }
  orient_triangles_ccw(mesh, report);
  return mesh;
}

Mesh read_triangle(const std::filesystem::path& ele_path, MeshReadReport& report) {
  auto node_path = ele_path, poly_path = ele_path;
  node_path.replace_extension(".node");
  poly_path.replace_extension(".poly");
  std::string poly;
  if (std::filesystem::exists(poly_path)) poly = read_text_file(poly_path, InputKind::Mesh);
  return parse_triangle(node_path.string(), read_text_file(node_path, InputKind::Mesh), ele_path.string(),
                        read_text_file(ele_path, InputKind::Mesh), poly_path.string(), std::move(poly), report);
}

}  // namespace pdmesh
