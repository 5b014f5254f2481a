// Checked text loading and number parsing for the geometry file readers (see reader_text.hpp).
#include "geometry/reader_text.hpp"

#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"

namespace pdmesh::detail {

namespace {

// Coordinates beyond this are almost surely garbage, and squaring them in distance computations
// would overflow a double.
constexpr double kLargestCoordinate = 1e150;

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

}  // namespace

std::vector<TokenLine> read_token_lines(const std::string& path) {
  std::string text = read_input_file(path, InputKind::Geometry);
  skip_utf8_bom(text);

  std::vector<TokenLine> lines;
  int number = 1;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    TokenLine line{number, {}};
    bool comment = false;
    std::string token;
    for (std::size_t i = start; i < end; ++i) {
      const unsigned char c = static_cast<unsigned char>(text[i]);
      if (c == '#') comment = true;
      if ((c < 0x20 && !is_space(static_cast<char>(c))) || c == 0x7f) {
        throw InputError(fmt::format("{}:{}: the file is not text (byte 0x{:02x} at column {})", path, number,
                                     static_cast<unsigned>(c), i - start + 1));
      }
      if (comment) continue;
      if (is_space(static_cast<char>(c))) {
        if (!token.empty()) line.tokens.push_back(std::move(token));
        token.clear();
      } else {
        token.push_back(static_cast<char>(c));
      }
    }
    if (!token.empty()) line.tokens.push_back(std::move(token));
    if (!line.tokens.empty()) lines.push_back(std::move(line));
    start = end + 1;
    ++number;
  }
  return lines;
}

double parse_coordinate(const std::string& file, int line, const std::string& token, const char* what) {
  const char* first = token.data();
  const char* last = token.data() + token.size();
  if (first != last && *first == '+') ++first;
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(first, last, value);
  if (ec == std::errc::result_out_of_range) {
    // from_chars says the same for a value too small for a double (1e-400) as for one too large:
    // strtod's result tells which (0 or a denormal when it underflows).
    if (std::fabs(std::strtod(token.c_str(), nullptr)) < DBL_MIN) {
      throw InputError(
          fmt::format("{}:{}: {} '{}' is too small for a double: it underflows to 0 or a denormal "
                      "(write 0, or a value of at least {:g})",
                      file, line, what, quote_input(token), DBL_MIN));
    }
    throw InputError(fmt::format("{}:{}: {} '{}' is too large (|value| must be <= {:g})", file, line, what,
                                 quote_input(token), kLargestCoordinate));
  }
  if (ec != std::errc() || ptr != last) {
    throw InputError(fmt::format("{}:{}: {} '{}' is not a number", file, line, what, quote_input(token)));
  }
  if (!std::isfinite(value)) {
    throw InputError(fmt::format("{}:{}: {} '{}' is not finite", file, line, what, quote_input(token)));
  }
  if (std::fabs(value) > kLargestCoordinate) {
    throw InputError(fmt::format("{}:{}: {} '{}' is too large (|value| must be <= {:g})", file, line, what,
                                 quote_input(token), kLargestCoordinate));
  }
  return value;
}

long long parse_count(const std::string& file, int line, const std::string& token, const char* what) {
  long long value = 0;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec == std::errc() && ptr == token.data() + token.size() && value < 0) {
    throw InputError(fmt::format("{}:{}: {} '{}' is negative", file, line, what, quote_input(token)));
  }
  if (ec != std::errc() || ptr != token.data() + token.size()) {
    throw InputError(fmt::format("{}:{}: {} '{}' is not a non-negative integer", file, line, what, quote_input(token)));
  }
  return value;
}

long long parse_integer(const std::string& file, int line, const std::string& token, const char* what) {
  long long value = 0;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || ptr != token.data() + token.size()) {
    throw InputError(fmt::format("{}:{}: {} '{}' is not an integer", file, line, what, quote_input(token)));
  }
  return value;
}

}  // namespace pdmesh::detail
