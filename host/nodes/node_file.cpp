// Node files: writer (%.17g, atomic) and a strict line-by-line reader with FILE:LINE messages.
#include "nodes/node_file.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fmt/format.h>
#include <optional>
#include <sstream>

#include "core/interrupt.hpp"
#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "core/g17.hpp"
#include "core/input_file.hpp"
#include "core/text_blocks.hpp"
#include "core/text_sink.hpp"

namespace pdmesh {

namespace {

constexpr const char* kHeader = "# pdmesh nodes v1";

bool has_space(const std::string& s) { return s.empty() || s.find_first_of(" \t\r\n") != std::string::npos; }

// Splits the text into numbered lines, skipping blank lines and '#' comments after the header.
class LineReader {
 public:
  LineReader(const std::string& text, std::string source) : in_(text), size_(text.size()), source_(std::move(source)) {}

  // The fields of the next non-blank, non-comment line; `what` names the expected content.
  std::vector<std::string> next(const char* what) {
    if (auto f = try_next()) return *f;
    ++line_;
    fail(fmt::format("unexpected end of file, expected {}", what));
  }

  // The next content line, or nothing at the end of the text.
  std::optional<std::vector<std::string>> try_next() {
    std::string line;
    while (std::getline(in_, line)) {
      ++line_;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      const auto first = line.find_first_not_of(" \t");
      if (first == std::string::npos || line[first] == '#') continue;
      std::istringstream fields(line);
      std::vector<std::string> out;
      for (std::string f; fields >> f;) out.push_back(f);
      return out;
    }
    return std::nullopt;
  }

  int line() const { return line_; }

  // Before allocating by `count`: it must fit in the unread text at `min_bytes_each` per item.
  void check_count(std::size_t count, std::size_t min_bytes_each, const char* what) {
    const std::streamoff at = in_.tellg();
    const std::size_t left = at < 0 ? 0 : size_ - static_cast<std::size_t>(at);
    check_count_fits(fmt::format("{}:{}", source_, line_), what, count, left, min_bytes_each);
  }

  std::string header() {
    std::string line;
    if (!std::getline(in_, line)) {
      line_ = 1;
      fail("empty file, expected the header '# pdmesh nodes v1'");
    }
    ++line_;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return line;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(fmt::format("{}:{}: {}", source_, line_, what));
  }

  long long integer(const std::string& s, const char* what, long long lo, long long hi) const {
    long long v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size()) {
      fail(fmt::format("{} '{}' is not an integer", what, quote_input(s)));
    }
    if (v < lo || v > hi) fail(fmt::format("{} {} is out of range [{}, {}]", what, v, lo, hi));
    return v;
  }

  double real(const std::string& s, const char* what) const {
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (end != s.c_str() + s.size() || s.empty()) fail(fmt::format("{} '{}' is not a number", what, quote_input(s)));
    if (!std::isfinite(v)) fail(fmt::format("{} '{}' is not finite", what, quote_input(s)));
    return v;
  }

  void expect_fields(const std::vector<std::string>& f, std::size_t n, const char* what) const {
    if (f.size() != n) fail(fmt::format("expected {} ({} fields), got {} fields", what, n, f.size()));
  }

 private:
  std::istringstream in_;
  std::size_t size_ = 0;
  std::string source_;
  int line_ = 0;
};

NodeKind kind_from(const LineReader& r, const std::string& s) {
  if (s == "fixed") return NodeKind::Fixed;
  if (s == "boundary") return NodeKind::Boundary;
  if (s == "interior") return NodeKind::Interior;
  r.fail(fmt::format("unknown node kind '{}' (expected fixed, boundary or interior)", quote_input(s)));
}

}  // namespace

namespace {

// The file's text, appended to `sink` in pieces.
void write_node_text(const NodeSet& nodes, const std::vector<std::string>& curve_names, TextSink& sink) {
  if (curve_names.size() != nodes.curve_nodes.size()) {
    throw InputError(
        fmt::format("node file: {} curve names for {} curves", curve_names.size(), nodes.curve_nodes.size()));
  }
  std::string& out = sink.text();
  fmt::format_to(std::back_inserter(out), "{}\n{}\n", kHeader, nodes.size());
  append_items(sink, nodes.size(), [&nodes](std::string& line, std::size_t i) {
    append_g17(line, nodes.x[i].x);
    line.push_back(' ');
    append_g17(line, nodes.x[i].y);
    fmt::format_to(std::back_inserter(line), " {} {} ", to_string(nodes.kind[i]),
                   nodes.kind[i] == NodeKind::Interior ? -1 : nodes.curve[i]);
    append_g17(line, nodes.q[i]);
    line.push_back('\n');
  });
  fmt::format_to(std::back_inserter(out), "curves {}\n", nodes.curve_nodes.size());
  for (std::size_t c = 0; c < nodes.curve_nodes.size(); ++c) {
    if (has_space(curve_names[c])) {
      throw InputError(
          fmt::format("node file: curve {} name '{}' is empty or contains white space", c, curve_names[c]));
    }
    fmt::format_to(std::back_inserter(out), "{} {}", curve_names[c], nodes.curve_nodes[c].size());
    for (int idx : nodes.curve_nodes[c]) {
      fmt::format_to(std::back_inserter(out), " {}", idx);
      sink.piece_done();
    }
    out.push_back('\n');
  }
}

}  // namespace

std::string format_node_file(const NodeSet& nodes, const std::vector<std::string>& curve_names) {
  TextSink sink;
  write_node_text(nodes, curve_names, sink);
  return sink.take();
}

void write_node_file(const std::filesystem::path& path, const NodeSet& nodes,
                     const std::vector<std::string>& curve_names) {
  write_text_atomically(path, [&](TextSink& sink) { write_node_text(nodes, curve_names, sink); });
}

NodeFile parse_node_file(const std::string& text, const std::string& source_name) {
  // A UTF-8 byte-order mark, as some editors write it, is skipped.
  const bool bom = text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0;
  LineReader r(bom ? text.substr(3) : text, source_name);
  if (const std::string h = r.header(); h != kHeader) {
    r.fail(fmt::format("expected the header '{}', got '{}'", kHeader, quote_input(h)));
  }
  NodeFile file;
  NodeSet& nodes = file.nodes;
  auto f = r.next("the node count");
  r.expect_fields(f, 1, "the node count");
  const auto n = static_cast<std::size_t>(r.integer(f[0], "node count", 0, 1'000'000'000));
  r.check_count(n, 14, "node count");  // "0 0 fixed 0 0\n"
  nodes.x.reserve(n);
  nodes.q.reserve(n);
  nodes.kind.reserve(n);
  nodes.curve.reserve(n);
  std::vector<int> node_lines;
  for (std::size_t i = 0; i < n; ++i) {
    f = r.next("a node line 'x y kind curve q'");
    node_lines.push_back(r.line());
    r.expect_fields(f, 5, "a node line 'x y kind curve q'");
    const Vec2 p{r.real(f[0], "x"), r.real(f[1], "y")};
    const NodeKind kind = kind_from(r, f[2]);
    const int curve = static_cast<int>(r.integer(f[3], "curve", -1, 1'000'000'000));
    if ((kind == NodeKind::Interior) != (curve == -1)) {
      r.fail(fmt::format("node {}: {} {} node must have curve {}, got {}", i, kind == NodeKind::Interior ? "an" : "a",
                         to_string(kind), kind == NodeKind::Interior ? "-1" : ">= 0", curve));
    }
    nodes.add(p, r.real(f[4], "q"), kind, curve);
  }
  f = r.next("'curves C'");
  if (f.size() != 2 || f[0] != "curves") r.fail("expected 'curves C' after the node lines");
  const auto curves = static_cast<std::size_t>(r.integer(f[1], "curve count", 0, 1'000'000));
  r.check_count(curves, 4, "curve count");  // "c 0\n"
  for (std::size_t c = 0; c < curves; ++c) {
    f = r.next("a curve line 'name count idx...'");
    if (f.size() < 2) r.fail("expected a curve line 'name count idx...'");
    const auto count = static_cast<std::size_t>(r.integer(f[1], "curve node count", 0, 1'000'000'000));
    if (f.size() != count + 2) {
      r.fail(fmt::format("curve '{}' declares {} nodes but lists {}", quote_input(f[0]), count, f.size() - 2));
    }
    std::vector<int> idx(count);
    for (std::size_t k = 0; k < count; ++k) {
      idx[k] = static_cast<int>(r.integer(f[k + 2], "node index", 0, static_cast<long long>(n) - 1));
      if (nodes.kind[idx[k]] == NodeKind::Interior) {
        r.fail(fmt::format("curve '{}' lists interior node {}", quote_input(f[0]), idx[k]));
      }
    }
    file.curve_names.push_back(f[0]);
    nodes.curve_nodes.push_back(std::move(idx));
  }
  if (r.try_next()) r.fail("unexpected content after the last curve line");
  for (std::size_t i = 0; i < n; ++i) {
    if (nodes.curve[i] >= static_cast<int>(curves)) {
      throw InputError(fmt::format("{}:{}: node {} refers to curve {} but the file has {} curves", source_name,
                                   node_lines[i], i, nodes.curve[i], curves));
    }
  }
  return file;
}

NodeFile read_node_file(const std::filesystem::path& path) {
  return parse_node_file(read_input_file(path, InputKind::NodeFile), path.string());
}

}  // namespace pdmesh
