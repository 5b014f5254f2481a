// .poly reader (Triangle's planar straight line graph format): parses the vertex, segment, hole and
// regional attribute sections; geometry/poly_domain.cpp gives them Triangle's meaning.
#include "geometry/poly_reader.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "geometry/poly_domain.hpp"
#include "geometry/reader_text.hpp"

namespace pdmesh {
namespace {

using detail::PolySegment;
using detail::PolyVertex;

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
  return holes;
}

// The optional regional attribute section: '<regions>', then '<region #> <x> <y> <attribute>
// [<max area>]'. As in Triangle, a line without the max area uses its fourth value for both.
std::vector<GeometryRegion> read_regions(const std::string& path, Cursor& cursor, int base) {
  std::vector<GeometryRegion> regions;
  if (cursor.at_end()) return regions;
  const detail::TokenLine& header = cursor.next("the region count line");
  expect_tokens(path, header, 1, "the regional attribute header '<regions>'");
  const long long count = detail::parse_count(path, header.number, header.tokens[0], "region count");
  cursor.check_count(header, count, "region count");
  for (long long k = 0; k < count; ++k) {
    const detail::TokenLine& row = cursor.next("a region line");
    if (row.tokens.size() != 4)
      expect_tokens(path, row, 5, "a region line '<region #> <x> <y> <attribute> <max area>'");
    const long long index = detail::parse_integer(path, row.number, row.tokens[0], "region index");
    if (index != base + k) {
      throw InputError(fmt::format("{}:{}: region index '{}' is out of order; expected {}", path, row.number,
                                   quote_input(row.tokens[0]), base + k));
    }
    GeometryRegion r;
    r.p.x = detail::parse_coordinate(path, row.number, row.tokens[1], "x coordinate");
    r.p.y = detail::parse_coordinate(path, row.number, row.tokens[2], "y coordinate");
    r.attribute = detail::parse_coordinate(path, row.number, row.tokens[3], "regional attribute");
    r.max_area = detail::parse_coordinate(path, row.number, row.tokens.back(), "maximum area");
    r.file = path;
    r.line = row.number;
    regions.push_back(r);
  }
  if (!cursor.at_end()) {
    const detail::TokenLine& extra = cursor.next("nothing");
    throw InputError(fmt::format("{}:{}: unexpected text after the regional attributes: '{}'", path, extra.number,
                                 quote_input(fmt::format("{}", fmt::join(extra.tokens, " ")))));
  }
  return regions;
}

}  // namespace

PolyFile read_poly_file(const std::string& path, PolyHull hull) {
  const std::vector<detail::TokenLine> lines = detail::read_token_lines(path);
  if (lines.empty()) throw InputError(fmt::format("{}: the file is empty or holds only comments", path));
  Cursor cursor(path, lines);
  int base = 0;
  const std::vector<PolyVertex> vertices = read_vertices(path, cursor, base);
  const std::vector<PolySegment> segments = read_segments(path, cursor, base, vertices.size());
  PolyFile result;
  result.holes = read_holes(path, cursor, base);
  const std::vector<GeometryRegion> regions = read_regions(path, cursor, base);
  detail::apply_poly_semantics(path, base, vertices, segments, regions, hull, result);
  return result;
}

}  // namespace pdmesh
