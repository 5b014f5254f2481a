// .poly reader (Triangle's planar straight line graph format): parses the vertex, segment and hole
// sections, then splits the segments into curves by boundary marker (see poly_reader.hpp).
#include "geometry/poly_reader.hpp"

#include <map>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "geometry/reader_text.hpp"

namespace pdmesh {
namespace {

struct PolyVertex {
  Vec2 p;
  int line = 0;
};

struct PolySegment {
  int a = 0, b = 0;  // 0-based vertex indices
  long long marker = 0;
  int line = 0;
};

// Walks the token lines in order, with messages that say which section is short.
class Cursor {
 public:
  Cursor(const std::string& path, const std::vector<detail::TokenLine>& lines) : path_(path), lines_(lines) {}

  const detail::TokenLine& next(const char* what) {
    if (pos_ >= lines_.size()) {
      const int last = lines_.empty() ? 0 : lines_.back().number;
      throw InputError(fmt::format("{}:{}: the file ends where {} was expected", path_, last, what));
    }
    return lines_[pos_++];
  }
  bool at_end() const { return pos_ >= lines_.size(); }

  // A section's count must fit in the lines left: one line per item.
  void check_count(const detail::TokenLine& header, long long count, const char* what) const {
    const std::size_t left = lines_.size() - pos_;
    if (static_cast<unsigned long long>(count) > left) {
      throw InputError(
          fmt::format("{}:{}: {} {} is more than the {} line{} left in the file (one per item): the count "
                      "is wrong or the file is truncated",
                      path_, header.number, what, count, left, left == 1 ? "" : "s"));
    }
  }

 private:
  const std::string& path_;
  const std::vector<detail::TokenLine>& lines_;
  std::size_t pos_ = 0;
};

void expect_tokens(const std::string& path, const detail::TokenLine& line, std::size_t want, const char* what) {
  if (line.tokens.size() != want) {
    throw InputError(fmt::format("{}:{}: {} should have {} value{}, found {}: '{}'", path, line.number, what, want,
                                 want == 1 ? "" : "s", line.tokens.size(),
                                 quote_input(fmt::format("{}", fmt::join(line.tokens, " ")))));
  }
}

std::vector<PolyVertex> read_vertices(const std::string& path, Cursor& cursor, int& base) {
  const detail::TokenLine& header = cursor.next("the vertex count line");
  expect_tokens(path, header, 4, "the vertex header '<vertices> <dimension> <attributes> <markers>'");
  const long long count = detail::parse_count(path, header.number, header.tokens[0], "vertex count");
  const long long dimension = detail::parse_count(path, header.number, header.tokens[1], "dimension");
  const long long attributes = detail::parse_count(path, header.number, header.tokens[2], "attribute count");
  const long long markers = detail::parse_count(path, header.number, header.tokens[3], "vertex marker count");
  if (count == 0) {
    throw InputError(
        fmt::format("{}:{}: vertex count 0 means the vertices are in a separate .node file, "
                    "which pdmesh does not support; put them in the .poly file",
                    path, header.number));
  }
  if (dimension != 2) {
    throw InputError(fmt::format("{}:{}: dimension '{}' is not supported; only 2-D geometry (2)", path, header.number,
                                 quote_input(header.tokens[1])));
  }
  if (attributes > 1000) {
    throw InputError(fmt::format("{}:{}: attribute count '{}' is implausibly large", path, header.number,
                                 quote_input(header.tokens[2])));
  }
  if (markers > 1) {
    throw InputError(fmt::format("{}:{}: vertex marker count '{}' must be 0 or 1", path, header.number,
                                 quote_input(header.tokens[3])));
  }
  cursor.check_count(header, count, "vertex count");
  std::vector<PolyVertex> vertices;
  vertices.reserve(static_cast<std::size_t>(count));
  for (long long k = 0; k < count; ++k) {
    const detail::TokenLine& row = cursor.next("a vertex line");
    expect_tokens(path, row, static_cast<std::size_t>(3 + attributes + markers), "a vertex line");
    const long long index = detail::parse_integer(path, row.number, row.tokens[0], "vertex index");
    if (k == 0) {
      if (index != 0 && index != 1) {
        throw InputError(fmt::format("{}:{}: the first vertex index '{}' must be 0 or 1", path, row.number,
                                     quote_input(row.tokens[0])));
      }
      base = static_cast<int>(index);
    }
    if (index != base + k) {
      throw InputError(fmt::format("{}:{}: vertex index '{}' is out of order; expected {}", path, row.number,
                                   quote_input(row.tokens[0]), base + k));
    }
    const double x = detail::parse_coordinate(path, row.number, row.tokens[1], "x coordinate");
    const double y = detail::parse_coordinate(path, row.number, row.tokens[2], "y coordinate");
    for (std::size_t t = 3; t < row.tokens.size(); ++t)
      detail::parse_coordinate(path, row.number, row.tokens[t], "attribute or marker");
    vertices.push_back({{x, y}, row.number});
  }
  return vertices;
}

std::vector<PolySegment> read_segments(const std::string& path, Cursor& cursor, int base, std::size_t nvertices) {
  const detail::TokenLine& header = cursor.next("the segment count line");
  expect_tokens(path, header, 2, "the segment header '<segments> <markers>'");
  const long long count = detail::parse_count(path, header.number, header.tokens[0], "segment count");
  const long long markers = detail::parse_count(path, header.number, header.tokens[1], "segment marker count");
  if (markers > 1) {
    throw InputError(fmt::format("{}:{}: segment marker count '{}' must be 0 or 1", path, header.number,
                                 quote_input(header.tokens[1])));
  }
  if (count == 0) throw InputError(fmt::format("{}:{}: the file has no segments", path, header.number));
  cursor.check_count(header, count, "segment count");
  std::vector<PolySegment> segments;
  segments.reserve(static_cast<std::size_t>(count));
  for (long long k = 0; k < count; ++k) {
    const detail::TokenLine& row = cursor.next("a segment line");
    expect_tokens(path, row, static_cast<std::size_t>(3 + markers), "a segment line");
    const long long index = detail::parse_integer(path, row.number, row.tokens[0], "segment index");
    if (index != base + k) {
      throw InputError(fmt::format("{}:{}: segment index '{}' is out of order; expected {}", path, row.number,
                                   quote_input(row.tokens[0]), base + k));
    }
    PolySegment seg;
    seg.line = row.number;
    int* ends[2] = {&seg.a, &seg.b};
    for (int e = 0; e < 2; ++e) {
      const long long v = detail::parse_integer(path, row.number, row.tokens[1 + e], "vertex index");
      if (v < base || v >= base + static_cast<long long>(nvertices)) {
        throw InputError(
            fmt::format("{}:{}: segment {} refers to vertex {}, which does not exist (vertices are "
                        "numbered {} to {})",
                        path, row.number, index, v, base, base + nvertices - 1));
      }
      *ends[e] = static_cast<int>(v - base);
    }
    if (seg.a == seg.b) {
      throw InputError(
          fmt::format("{}:{}: segment {} joins vertex {} to itself", path, row.number, index, seg.a + base));
    }
    if (markers == 1) seg.marker = detail::parse_integer(path, row.number, row.tokens[3], "boundary marker");
    segments.push_back(seg);
  }
  return segments;
}

std::vector<RawHolePoint> read_holes(const std::string& path, Cursor& cursor, int base) {
  const detail::TokenLine& header = cursor.next("the hole count line");
  expect_tokens(path, header, 1, "the hole header '<holes>'");
  const long long count = detail::parse_count(path, header.number, header.tokens[0], "hole count");
  cursor.check_count(header, count, "hole count");
  std::vector<RawHolePoint> holes;
  for (long long k = 0; k < count; ++k) {
    const detail::TokenLine& row = cursor.next("a hole line");
    expect_tokens(path, row, 3, "a hole line '<hole #> <x> <y>'");
    const long long index = detail::parse_integer(path, row.number, row.tokens[0], "hole index");
    if (index != base + k) {
      throw InputError(fmt::format("{}:{}: hole index '{}' is out of order; expected {}", path, row.number,
                                   quote_input(row.tokens[0]), base + k));
    }
    const double x = detail::parse_coordinate(path, row.number, row.tokens[1], "x coordinate");
    const double y = detail::parse_coordinate(path, row.number, row.tokens[2], "y coordinate");
    holes.push_back({{x, y}, path, row.number});
  }
  // A regional attribute section may follow; pdmesh has no use for it.
  return holes;
}

// Splits the segments of one marker into chains (see poly_reader.hpp). `ids` are indices into
// `segments`, in file order, so the result does not depend on anything but the file.
void chain_marker(const std::string& path, const std::vector<PolyVertex>& vertices,
                  const std::vector<PolySegment>& segments, const std::vector<int>& ids,
                  std::vector<RawCurve>& curves) {
  std::map<int, std::vector<int>> incident;  // vertex -> segment ids of this marker
  for (const int s : ids) {
    incident[segments[s].a].push_back(s);
    incident[segments[s].b].push_back(s);
  }
  std::map<int, bool> used;
  auto other = [&](int s, int v) { return segments[s].a == v ? segments[s].b : segments[s].a; };
  auto walk = [&](int start_vertex, int first_segment) {
    RawCurve curve;
    curve.file = path;
    curve.line = segments[first_segment].line;
    auto add = [&](int v) {
      curve.points.push_back(vertices[v].p);
      curve.lines.push_back(vertices[v].line);
    };
    add(start_vertex);
    int v = start_vertex;
    int s = first_segment;
    while (true) {
      used[s] = true;
      v = other(s, v);
      add(v);
      const auto& around = incident[v];
      if (around.size() != 2 || v == start_vertex) break;
      s = around[0] == s ? around[1] : around[0];
      if (used[s]) break;
    }
    curves.push_back(std::move(curve));
  };
  for (const int s : ids) {
    for (const int v : {segments[s].a, segments[s].b})
      if (!used[s] && incident[v].size() != 2) walk(v, s);
  }
  for (const int s : ids)
    if (!used[s]) walk(segments[s].a, s);  // what is left forms cycles: closed curves
}

}  // namespace

PolyFile read_poly_file(const std::string& path) {
  const std::vector<detail::TokenLine> lines = detail::read_token_lines(path);
  if (lines.empty()) throw InputError(fmt::format("{}: the file is empty or holds only comments", path));
  Cursor cursor(path, lines);
  int base = 0;
  const std::vector<PolyVertex> vertices = read_vertices(path, cursor, base);
  const std::vector<PolySegment> segments = read_segments(path, cursor, base, vertices.size());
  PolyFile result;
  result.holes = read_holes(path, cursor, base);

  // Markers in order of first appearance.
  std::vector<long long> order;
  std::map<long long, std::vector<int>> by_marker;
  for (int s = 0; s < static_cast<int>(segments.size()); ++s) {
    auto& ids = by_marker[segments[s].marker];
    if (ids.empty()) order.push_back(segments[s].marker);
    ids.push_back(s);
  }
  for (const long long marker : order) chain_marker(path, vertices, segments, by_marker[marker], result.curves);
  return result;
}

}  // namespace pdmesh
