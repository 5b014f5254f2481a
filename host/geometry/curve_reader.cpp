// .crv/.dat reader: a point count N on its own line, then N lines `x y [z]`; repeated to the end.
#include "geometry/curve_reader.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "geometry/reader_text.hpp"

namespace pdmesh {

std::vector<RawCurve> read_curve_file(const std::string& path) {
  const std::vector<detail::TokenLine> lines = detail::read_token_lines(path);
  std::vector<RawCurve> curves;
  std::size_t i = 0;
  while (i < lines.size()) {
    const detail::TokenLine& header = lines[i];
    if (header.tokens.size() != 1) {
      throw InputError(fmt::format("{}:{}: expected a point count on its own line, found '{}'", path, header.number,
                                   quote_input(fmt::format("{}", fmt::join(header.tokens, " ")))));
    }
    const long long count = detail::parse_count(path, header.number, header.tokens[0], "point count");
    const std::size_t remaining = lines.size() - i - 1;
    if (static_cast<unsigned long long>(count) > remaining) {
      throw InputError(fmt::format("{}:{}: block of {} points is truncated: only {} line{} follow{}", path,
                                   header.number, count, remaining, remaining == 1 ? "" : "s",
                                   remaining == 1 ? "s" : ""));
    }
    RawCurve curve;
    curve.file = path;
    curve.line = count > 0 ? lines[i + 1].number : header.number;
    curve.points.reserve(static_cast<std::size_t>(count));
    curve.lines.reserve(static_cast<std::size_t>(count));
    for (long long k = 0; k < count; ++k) {
      const detail::TokenLine& row = lines[i + 1 + static_cast<std::size_t>(k)];
      if (row.tokens.size() == 1) {
        throw InputError(fmt::format(
            "{}:{}: expected point {} of {} as 'x y [z]', found '{}' (is the count {} at line {} too large?)", path,
            row.number, k + 1, count, quote_input(row.tokens[0]), count, header.number));
      }
      if (row.tokens.size() > 3) {
        throw InputError(
            fmt::format("{}:{}: extra text '{}' after point 'x y z'", path, row.number,
                        quote_input(fmt::format("{}", fmt::join(row.tokens.begin() + 3, row.tokens.end(), " ")))));
      }
      const double x = detail::parse_coordinate(path, row.number, row.tokens[0], "x coordinate");
      const double y = detail::parse_coordinate(path, row.number, row.tokens[1], "y coordinate");
      if (row.tokens.size() == 3) detail::parse_coordinate(path, row.number, row.tokens[2], "z coordinate");
      curve.points.push_back({x, y});
      curve.lines.push_back(row.number);
    }
    curves.push_back(std::move(curve));
    i += 1 + static_cast<std::size_t>(count);
  }
  if (curves.empty()) {
    throw InputError(fmt::format("{}: no curves found (the file is empty or holds only comments)", path));
  }
  return curves;
}

}  // namespace pdmesh
