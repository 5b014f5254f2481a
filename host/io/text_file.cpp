// Atomic text writes and the line scanner used by the mesh readers.
#include "io/text_file.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "core/atomic_file.hpp"
#include "core/errors.hpp"

namespace pdmesh {

void write_text_file(const std::filesystem::path& path, const std::string& content) {
  write_file_atomically(path, content);
}

std::string read_text_file(const std::filesystem::path& path, InputKind kind) { return read_input_file(path, kind); }

std::vector<std::string_view> split_tokens(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

LineScanner::LineScanner(std::string file_label, std::string content)
    : file_(std::move(file_label)), content_(std::move(content)) {
  skip_utf8_bom(content_);
}

bool LineScanner::next_line(std::string_view& line) {
  pending_ = {};  // line mode: whatever was left of the previous line is dropped
  if (pos_ >= content_.size()) return false;
  const std::size_t end = content_.find('\n', pos_);
  const std::size_t stop = end == std::string::npos ? content_.size() : end;
  line = std::string_view(content_).substr(pos_, stop - pos_);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  pos_ = end == std::string::npos ? content_.size() : end + 1;
  ++line_;
  return true;
}

std::string_view LineScanner::token(std::string_view what) {
  for (;;) {
    const std::size_t first = pending_.find_first_not_of(" \t\r");
    if (first != std::string_view::npos) {
      pending_.remove_prefix(first);
      const std::size_t stop = std::min(pending_.find_first_of(" \t\r"), pending_.size());
      const std::string_view tok = pending_.substr(0, stop);
      pending_.remove_prefix(stop);
      return tok;
    }
    if (!next_line(pending_)) fail(fmt::format("unexpected end of file, expected {}", what));
  }
}

std::string_view LineScanner::rest_of_line() {
  std::string_view rest = pending_;
  pending_ = {};
  const std::size_t first = rest.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  rest.remove_prefix(first);
  return rest.substr(0, rest.find_last_not_of(" \t\r") + 1);
}

std::string_view LineScanner::expect_line(std::string_view what, char comment) {
  pending_ = {};
  std::string_view line;
  while (next_line(line)) {
    const std::size_t first = line.find_first_not_of(" \t\r");  // '\r'-only is blank, as in split_tokens
    if (first == std::string_view::npos) continue;
    if (comment != '\0' && line[first] == comment) continue;
    return line;
  }
  fail(fmt::format("unexpected end of file, expected {}", what));
}

std::vector<std::string_view> LineScanner::expect_tokens(std::string_view what, char comment) {
  std::string_view line = expect_line(what, comment);
  if (comment != '\0') {
    const std::size_t c = line.find(comment);
    if (c != std::string_view::npos) line = line.substr(0, c);
  }
  return split_tokens(line);
}

void LineScanner::fail(std::string_view what) const { throw InputError(fmt::format("{}:{}: {}", file_, line_, what)); }

void LineScanner::fail(std::string_view what, std::string_view got) const {
  throw InputError(fmt::format("{}:{}: {} (got '{}')", file_, line_, what, quote_input(got)));
}

void LineScanner::check_count(long long count, std::size_t min_bytes_each, std::string_view what) const {
  if (count < 0) fail(fmt::format("negative {}", what), fmt::format("{}", count));
  const std::size_t left = pending_.size() + (content_.size() - std::min(pos_, content_.size()));
  check_count_fits(fmt::format("{}:{}", file_, line_), what, static_cast<std::uint64_t>(count), left, min_bytes_each);
}

long long LineScanner::to_int(std::string_view token, std::string_view what) const {
  long long v = 0;
  const auto [p, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || p != token.data() + token.size()) fail(fmt::format("expected an integer {}", what), token);
  return v;
}

double LineScanner::to_double(std::string_view token, std::string_view what) const {
  double v = 0.0;
  const auto [p, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || p != token.data() + token.size() || !std::isfinite(v)) {
    fail(fmt::format("expected a finite number {}", what), token);
  }
  return v;
}

long long LineScanner::to_index(std::string_view token, long long lo, long long hi, std::string_view what) const {
  const long long v = to_int(token, what);
  if (v < lo || v > hi) fail(fmt::format("{} {} is out of range [{}, {}]", what, v, lo, hi), token);
  return v;
}

}  // namespace pdmesh
