// Selig and Lednicer airfoil files (airfoil_reader.hpp). Both start with a name line; Selig then
// lists `x y` from the trailing edge over one surface around the leading edge and back, Lednicer has
// a line of two counts and then each surface from the leading edge to the trailing edge.
#include "geometry/airfoil_reader.hpp"

#include <charconv>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"

namespace pdmesh {

namespace {

// A number as from_chars reads it (a leading '+' allowed), without messages: for telling a name line
// or a count line from a point line.
bool as_number(const std::string& token, double& value) {
  const char* first = token.data();
  const char* last = first + token.size();
  if (first != last && *first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, last, value);
  return ec == std::errc() && ptr == last && std::isfinite(value);
}

bool all_numbers(const detail::TokenLine& line) {
  double v = 0.0;
  for (const std::string& t : line.tokens)
    if (!as_number(t, v)) return false;
  return true;
}

struct Row {
  Vec2 p;
  int line = 0;
};

Row read_point(const std::string& path, const detail::TokenLine& row) {
  if (row.tokens.size() != 2) {
    throw InputError(fmt::format("{}:{}: expected an airfoil point 'x y', found '{}'", path, row.number,
                                 quote_input(fmt::format("{}", fmt::join(row.tokens, " ")))));
  }
  return {{detail::parse_coordinate(path, row.number, row.tokens[0], "x coordinate"),
           detail::parse_coordinate(path, row.number, row.tokens[1], "y coordinate")},
          row.number};
}

// Lednicer's count line: two integral values >= 2 (written `61.` or `61`) whose sum is the number of
// point lines that follow. A Selig point line never satisfies all three.
bool lednicer_counts(const detail::TokenLine& line, std::size_t rows_after, long long& upper, long long& lower) {
  double a = 0.0, b = 0.0;
  if (line.tokens.size() != 2 || !as_number(line.tokens[0], a) || !as_number(line.tokens[1], b)) return false;
  if (a < 2 || b < 2 || a != std::floor(a) || b != std::floor(b) || a > 1e9 || b > 1e9) return false;
  upper = static_cast<long long>(a);
  lower = static_cast<long long>(b);
  return static_cast<std::size_t>(upper + lower) == rows_after;
}

RawCurve make_curve(const std::string& path, const char* name, const std::vector<Row>& rows, std::size_t from,
                    std::size_t to) {
  RawCurve c;
  c.name = name;
  c.file = path;
  for (std::size_t k = from; k <= to; ++k) {
    const Row& r = rows[k % rows.size()];
    c.points.push_back(r.p);
    c.lines.push_back(r.line);
  }
  c.line = c.lines.front();
  return c;
}

}  // namespace

bool is_count_format(const std::vector<detail::TokenLine>& lines) {
  return !lines.empty() && lines.front().tokens.size() == 1 && all_numbers(lines.front());
}

AirfoilFile read_airfoil_lines(const std::string& path, const std::vector<detail::TokenLine>& lines) {
  if (lines.empty()) {
    throw InputError(fmt::format("{}: no curves found (the file is empty or holds only comments)", path));
  }
  // The name line is optional: a file that starts with a point is Selig without a name.
  std::size_t i = all_numbers(lines.front()) ? 0 : 1;
  std::vector<Row> rows;  // Selig order: trailing edge, one surface, leading edge, other surface
  long long upper = 0, lower = 0;
  if (i < lines.size() && lednicer_counts(lines[i], lines.size() - i - 1, upper, lower)) {
    std::vector<Row> up, low;
    for (long long k = 0; k < upper; ++k) up.push_back(read_point(path, lines[i + 1 + static_cast<std::size_t>(k)]));
    for (long long k = 0; k < lower; ++k)
      low.push_back(read_point(path, lines[i + 1 + static_cast<std::size_t>(upper + k)]));
    rows.assign(up.rbegin(), up.rend());
    // Both surfaces start at the leading edge; it is one point of the loop.
    const std::size_t skip = low.front().p == up.front().p ? 1 : 0;
    rows.insert(rows.end(), low.begin() + static_cast<std::ptrdiff_t>(skip), low.end());
  } else {
    for (; i < lines.size(); ++i) rows.push_back(read_point(path, lines[i]));
  }

  AirfoilFile out;
  std::vector<Row> kept;
  std::vector<int> dropped;
  for (const Row& r : rows) {
    if (!kept.empty() && kept.back().p == r.p) {
      dropped.push_back(r.line);
    } else {
      kept.push_back(r);
    }
  }
  if (!dropped.empty()) {
    out.notes.push_back(fmt::format("{}: dropped {} repeated consecutive point{} (line{} {})", path, dropped.size(),
                                    dropped.size() == 1 ? "" : "s", dropped.size() == 1 ? "" : "s",
                                    fmt::join(dropped, ", ")));
  }
  // A sharp trailing edge repeats the first point at the end: the loop closes there.
  const bool sharp = kept.size() > 1 && kept.front().p == kept.back().p;
  if (sharp) kept.pop_back();
  const std::size_t n = kept.size();
  if (n < 3) {
    throw InputError(fmt::format("{}:{}: an airfoil needs at least 3 distinct points, found {}", path,
                                 rows.empty() ? lines.front().number : rows.front().line, n));
  }
  // The leading edge: the point farthest from the trailing edge's midpoint (first of equals), which
  // does not depend on the airfoil's orientation or chord.
  const Vec2 te_mid = (kept.front().p + kept.back().p) * 0.5;
  std::size_t le = 1;
  double far = -1.0;
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const Vec2 d = kept[k].p - te_mid;
    const double d2 = d.x * d.x + d.y * d.y;
    if (d2 > far) {
      far = d2;
      le = k;
    }
  }
  // Going over the upper surface first (x to the right, y up) runs counter-clockwise.
  double area2 = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2 a = kept[k].p, b = kept[(k + 1) % n].p;
    area2 += a.x * b.y - a.y * b.x;
  }
  const bool first_is_upper = area2 >= 0.0;
  RawCurve first = make_curve(path, first_is_upper ? "upper" : "lower", kept, 0, le);
  RawCurve second = make_curve(path, first_is_upper ? "lower" : "upper", kept, le, sharp ? n : n - 1);
  if (first_is_upper) {
    out.curves.push_back(std::move(first));
    out.curves.push_back(std::move(second));
  } else {
    out.curves.push_back(std::move(second));
    out.curves.push_back(std::move(first));
  }
  if (!sharp) out.curves.push_back(make_curve(path, "te", kept, n - 1, n));
  return out;
}

}  // namespace pdmesh
