// Checkpoint files: writer and strict reader; see checkpoint.hpp and docs/checkpoint.md.
#include "sim/checkpoint.hpp"

#include <algorithm>
#include <charconv>
#include <iterator>
#include <cmath>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "core/parallel.hpp"
#include "io/text_file.hpp"

namespace pdmesh {
namespace {

// Version 2 added population control (the population line and two history counts); version 1 files
// (a fixed node count) are still read.
constexpr const char* kHeader = "pdmesh-checkpoint 2";
constexpr const char* kHeaderV1 = "pdmesh-checkpoint 1";

// Hexadecimal floating point without the 0x prefix (std::to_chars): exact and locale-free.
std::string hex(double v) {
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v, std::chars_format::hex);
  return std::string(buffer, ec == std::errc() ? end : buffer);
}

// hex(v) appended to `out` without a temporary string (a checkpoint of millions of nodes is written
// when a run is stopped, while the user waits).
void append_hex(std::string& out, double v) {
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v, std::chars_format::hex);
  out.append(buffer, ec == std::errc() ? end : buffer);
}

double parse_hex(const LineScanner& in, std::string_view token, std::string_view what) {
  double v = 0.0;
  const auto [p, ec] = std::from_chars(token.data(), token.data() + token.size(), v, std::chars_format::hex);
  if (ec != std::errc() || p != token.data() + token.size() || !std::isfinite(v))
    in.fail(fmt::format("expected a finite hexadecimal number {}", what), token);
  return v;
}

// The next line's tokens, which must start with `keyword` and have `count` tokens (0: any).
std::vector<std::string_view> keyword_line(LineScanner& in, std::string_view keyword, std::size_t count,
                                           std::string_view what) {
  std::vector<std::string_view> t = in.expect_tokens(what);
  if (t.empty() || t[0] != keyword) in.fail(fmt::format("expected {}", what), t.empty() ? "" : t[0]);
  if (count != 0 && t.size() != count) in.fail(fmt::format("expected {} ({} fields)", what, count));
  return t;
}

std::size_t parse_count(const LineScanner& in, std::string_view token, std::string_view what) {
  return static_cast<std::size_t>(in.to_index(token, 0, 1'000'000'000, what));
}

// The sections of a checkpoint file, in the order they come; each reads its own lines and fails on the
// first thing malformed.

// The header line; true for a version 1 file.
bool parse_header(LineScanner& in) {
  std::string_view line = in.expect_line("the header line");
  const bool v1 = line == kHeaderV1;
  if (line != kHeader && !v1) in.fail(fmt::format("expected the header '{}'", kHeader), line);
  return v1;
}

// The case lines; returns the tokens of the line after them.
std::vector<std::string_view> parse_case_keys(LineScanner& in, Checkpoint& c) {
  std::vector<std::string_view> t = in.expect_tokens("a case line or iterations_done");
  while (!t.empty() && t[0] == "case") {
    if (t.size() < 2) in.fail("expected 'case KEY VALUE'");
    // The value is the rest of the line after the key (it may hold spaces).
    const std::size_t key_end = static_cast<std::size_t>(t[1].data() - t[0].data()) + t[1].size();
    const std::string_view whole(t[0].data(),
                                 static_cast<std::size_t>(t.back().data() + t.back().size() - t[0].data()));
    std::string value = key_end < whole.size() ? std::string(whole.substr(key_end + 1)) : std::string();
    c.case_keys.emplace_back(std::string(t[1]), std::move(value));
    t = in.expect_tokens("a case line or iterations_done");
  }
  return t;
}

// The driver's counters: iterations_done (its tokens `first` already read), dt_initial, time_step and,
// from version 2 on, population.
void parse_driver_state(LineScanner& in, const std::vector<std::string_view>& first, bool v1, SimState& s) {
  if (first.size() != 2 || first[0] != "iterations_done")
    in.fail("expected 'iterations_done N'", first.empty() ? "" : first[0]);
  s.iterations_done = static_cast<int>(in.to_index(first[1], 0, 2'000'000'000, "iterations_done"));
  std::vector<std::string_view> t = keyword_line(in, "dt_initial", 2, "'dt_initial DT'");
  s.dt_initial = parse_hex(in, t[1], "dt_initial");
  t = keyword_line(in, "time_step", 5, "'time_step DT PREVIOUS DECREASES INCREASES'");
  s.time_step.dt = parse_hex(in, t[1], "time step dt");
  if (t[2] != "none") s.time_step.previous = parse_hex(in, t[2], "previous maximum force");
  s.time_step.consecutive_decreases = static_cast<int>(in.to_index(t[3], 0, 1000, "consecutive decreases"));
  s.time_step.increases = static_cast<int>(in.to_index(t[4], 0, 1000, "increases"));
  if (v1) return;
  t = keyword_line(in, "population", 5, "'population NEXT INTERVAL LAST_EVENT LAST_CHANGE'");
  PopulationSchedule& p = s.population;
  p.next = static_cast<int>(in.to_index(t[1], 0, 2'000'000'000, "next population event"));
  p.interval = static_cast<int>(in.to_index(t[2], 0, 2'000'000'000, "population interval"));
  p.last_event = static_cast<int>(in.to_index(t[3], 0, s.iterations_done, "last population event"));
  p.last_change = static_cast<int>(in.to_index(t[4], 0, p.last_event, "last population change"));
}

// The node lines (position, spacing, kind, curve, tangent); returns the node count.
std::size_t parse_nodes(LineScanner& in, NodeSet& nodes, SimState& s) {
  std::vector<std::string_view> t = keyword_line(in, "nodes", 2, "'nodes N'");
  const std::size_t n = parse_count(in, t[1], "node count");
  in.check_count(static_cast<long long>(n), 14, "node count");  // "0 0 0 0 0 0 0\n"
  s.tangents.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    t = in.expect_tokens("a node line 'x y q kind curve tx ty'");
    if (t.size() != 7) in.fail("expected a node line 'x y q kind curve tx ty' (7 fields)");
    const Vec2 p{parse_hex(in, t[0], "x"), parse_hex(in, t[1], "y")};
    const double q = parse_hex(in, t[2], "q");
    const auto kind = static_cast<NodeKind>(in.to_index(t[3], 0, 2, "node kind"));
    const int curve = static_cast<int>(in.to_index(t[4], -1, 1'000'000'000, "curve"));
    nodes.add(p, q, kind, curve);
    s.tangents[i] = {parse_hex(in, t[5], "tangent x"), parse_hex(in, t[6], "tangent y")};
  }
  return n;
}

// The curve lines: each curve's nodes (indices below n) and their arc positions.
void parse_curves(LineScanner& in, std::size_t n, NodeSet& nodes, SimState& s) {
  const long long last_node = static_cast<long long>(n) - 1;
  std::vector<std::string_view> t = keyword_line(in, "curves", 2, "'curves C'");
  const std::size_t curves = parse_count(in, t[1], "curve count");
  in.check_count(static_cast<long long>(curves), 10, "curve count");  // "curve 0 0\n"
  nodes.curve_nodes.resize(curves);
  s.arcs.resize(curves);
  for (std::size_t k = 0; k < curves; ++k) {
    t = keyword_line(in, "curve", 0, "'curve K M NODE:ARC...'");
    if (t.size() < 3 || static_cast<std::size_t>(in.to_index(t[1], 0, 1'000'000'000, "curve index")) != k)
      in.fail(fmt::format("expected 'curve {} M NODE:ARC...'", k));
    const std::size_t m = parse_count(in, t[2], "curve node count");
    if (t.size() != 3 + m) in.fail(fmt::format("expected {} NODE:ARC pairs, got {}", m, t.size() - 3));
    for (std::size_t j = 0; j < m; ++j) {
      const std::string_view pair = t[3 + j];
      const std::size_t colon = pair.find(':');
      if (colon == std::string_view::npos) in.fail("expected NODE:ARC", pair);
      nodes.curve_nodes[k].push_back(static_cast<int>(in.to_index(pair.substr(0, colon), 0, last_node, "node")));
      s.arcs[k].push_back(parse_hex(in, pair.substr(colon + 1), "arc position"));
    }
  }
}

// The history rows, one per iteration done (version 1 rows lack the two population counts).
void parse_history(LineScanner& in, bool v1, SimState& s) {
  std::vector<std::string_view> t = keyword_line(in, "history", 2, "'history R'");
  const std::size_t rows = parse_count(in, t[1], "history row count");
  if (rows != static_cast<std::size_t>(s.iterations_done))
    in.fail(fmt::format("expected {} history rows (iterations_done)", s.iterations_done), t[1]);
  in.check_count(static_cast<long long>(rows), v1 ? 20 : 24, "history row count");  // "0 0 ... 0\n"
  s.history.reserve(rows);
  for (std::size_t r = 0; r < rows; ++r) {
    t = in.expect_tokens("a history row");
    const std::size_t fields = v1 ? 10 : 12;
    if (t.size() != fields) in.fail(fmt::format("expected a history row ({} fields)", fields));
    HistoryRow row;
    row.iteration = static_cast<int>(in.to_index(t[0], 1, 2'000'000'000, "iteration"));
    row.average_force = parse_hex(in, t[1], "average force");
    row.average_kinetic = parse_hex(in, t[2], "average kinetic energy");
    row.max_force = parse_hex(in, t[3], "maximum force");
    row.dt_gm = parse_hex(in, t[4], "dt_GM");
    std::size_t* counts[] = {&row.snapped,  &row.clamped,  &row.fixed,  &row.boundary,
                             &row.interior, &row.inserted, &row.removed};
    for (std::size_t f = 0; f + 5 < fields; ++f) *counts[f] = parse_count(in, t[5 + f], "history count");
    s.history.push_back(row);
  }
}

// The optional convergence section, its line `t` already read: the stopping rule's samples.
// Returns the tokens of the line after it.
std::vector<std::string_view> parse_convergence(LineScanner& in, const std::vector<std::string_view>& t, SimState& s) {
  if (t.size() != 2) in.fail("expected 'convergence N'");
  const std::size_t samples = parse_count(in, t[1], "convergence sample count");
  in.check_count(static_cast<long long>(samples), 6, "convergence sample count");  // "1 0 0\n"
  const auto value = [&in](std::string_view token, std::string_view what) {
    return token == "nan" ? std::nan("") : parse_hex(in, token, what);
  };
  int previous = 0;
  for (std::size_t k = 0; k < samples; ++k) {
    const std::vector<std::string_view> f = in.expect_tokens("a convergence sample 'ITERATION MIN_ANGLE ASPECT_RATIO'");
    if (f.size() != 3) in.fail("expected a convergence sample 'ITERATION MIN_ANGLE ASPECT_RATIO' (3 fields)");
    MeshSample m;
    m.iteration = static_cast<int>(in.to_index(f[0], previous + 1, s.iterations_done, "convergence sample iteration"));
    m.min_angle = value(f[1], "minimum angle");
    m.aspect_ratio = value(f[2], "aspect ratio");
    previous = m.iteration;
    s.convergence.push_back(m);
  }
  return in.expect_tokens("'momentum N' or 'end' (the file is truncated)");
}

// The optional momentum section, its line `t` already read: one carried move per node (n of them).
// Returns the tokens of the line after it.
std::vector<std::string_view> parse_momentum(LineScanner& in, const std::vector<std::string_view>& t, std::size_t n,
                                             SimState& s) {
  if (t.size() != 2) in.fail("expected 'momentum N'");
  const std::size_t count = parse_count(in, t[1], "momentum count");
  if (count != n) in.fail(fmt::format("expected momentum {} (one carried move per node)", n), t[1]);
  s.momentum.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::vector<std::string_view> f = in.expect_tokens("a carried move 'PX PY'");
    if (f.size() != 2) in.fail("expected a carried move 'PX PY' (2 fields)");
    s.momentum[i] = {parse_hex(in, f[0], "carried move x"), parse_hex(in, f[1], "carried move y")};
  }
  return in.expect_tokens("'end' (the file is truncated)");
}

// The end line `t`, and nothing after it: a second checkpoint appended, or anything else, means a
// damaged file.
void parse_end(LineScanner& in, const std::vector<std::string_view>& t) {
  if (t.size() != 1 || t[0] != "end") in.fail("expected 'end'", t.empty() ? "" : t[0]);
  for (std::string_view rest; in.next_line(rest);) {
    if (rest.find_first_not_of(" \t\r") != std::string_view::npos) in.fail("unexpected content after 'end'", rest);
  }
}

// The writer's sections.

// The node lines, in blocks formatted on several threads (a stopped run writes its checkpoint while
// the user waits), joined in order: the same text as one loop.
void append_node_lines(std::string& out, const NodeSet& nodes, const SimState& s) {
  const InterruptShield shield;  // written whole, also when a stop request comes meanwhile
  constexpr std::size_t kBlock = 1 << 15;
  std::vector<std::string> blocks((nodes.size() + kBlock - 1) / kBlock);
  parallel_for(
      blocks.size(),
      [&](std::size_t b) {
        std::string& text = blocks[b];
        const std::size_t end = std::min(nodes.size(), (b + 1) * kBlock);
        text.reserve(110 * (end - b * kBlock));
        for (std::size_t i = b * kBlock; i < end; ++i) {
          const Vec2 t = i < s.tangents.size() ? s.tangents[i] : Vec2{};
          append_hex(text, nodes.x[i].x);
          text += ' ';
          append_hex(text, nodes.x[i].y);
          text += ' ';
          append_hex(text, nodes.q[i]);
          fmt::format_to(std::back_inserter(text), " {} {} ", static_cast<int>(nodes.kind[i]), nodes.curve[i]);
          append_hex(text, t.x);
          text += ' ';
          append_hex(text, t.y);
          text += '\n';
        }
      },
      1);
  std::size_t total = out.size();
  for (const std::string& text : blocks) total += text.size();
  out.reserve(total + 64 * nodes.size());  // and the curve lines
  for (const std::string& text : blocks) out += text;
}

// The curve lines: each curve's nodes with their arc positions.
void append_curve_lines(std::string& out, const NodeSet& nodes, const SimState& s) {
  out += fmt::format("curves {}\n", nodes.curve_nodes.size());
  for (std::size_t k = 0; k < nodes.curve_nodes.size(); ++k) {
    const std::vector<int>& list = nodes.curve_nodes[k];
    out += fmt::format("curve {} {}", k, list.size());
    for (std::size_t j = 0; j < list.size(); ++j) {
      fmt::format_to(std::back_inserter(out), " {}:", list[j]);
      append_hex(out, k < s.arcs.size() && j < s.arcs[k].size() ? s.arcs[k][j] : 0.0);
    }
    out += '\n';
  }
}

// The history rows, then the convergence and momentum sections when there is something in them.
void append_history(std::string& out, const SimState& s) {
  out += fmt::format("history {}\n", s.history.size());
  for (const HistoryRow& r : s.history)
    out += fmt::format("{} {} {} {} {} {} {} {} {} {} {} {}\n", r.iteration, hex(r.average_force),
                       hex(r.average_kinetic), hex(r.max_force), hex(r.dt_gm), r.snapped, r.clamped, r.fixed,
                       r.boundary, r.interior, r.inserted, r.removed);
  // The stopping rule's measurements (sim/convergence.hpp); a file without this section has none.
  if (!s.convergence.empty()) {
    out += fmt::format("convergence {}\n", s.convergence.size());
    const auto value = [](double v) { return std::isnan(v) ? std::string("nan") : hex(v); };
    for (const MeshSample& m : s.convergence)
      out += fmt::format("{} {} {}\n", m.iteration, value(m.min_angle), value(m.aspect_ratio));
  }
  // Heavy-ball momentum's carried moves (simulation.momentum > 0 only); a file without it has none.
  if (!s.momentum.empty()) {
    out += fmt::format("momentum {}\n", s.momentum.size());
    for (const Vec2& p : s.momentum) out += fmt::format("{} {}\n", hex(p.x), hex(p.y));
  }
}

}  // namespace

std::string format_checkpoint(const Checkpoint& c) {
  const NodeSet& nodes = c.nodes;
  const SimState& s = c.state;
  std::string out = fmt::format("{}\n", kHeader);
  for (const auto& [key, value] : c.case_keys) {
    if (key.empty() || key.find_first_of(" \t\r\n") != std::string::npos ||
        value.find_first_of("\r\n") != std::string::npos)
      throw InputError(
          fmt::format("checkpoint case key '{}' = '{}' has white space in the key or a line break", key, value));
    out += fmt::format("case {} {}\n", key, value);
  }
  out += fmt::format("iterations_done {}\n", s.iterations_done);
  out += fmt::format("dt_initial {}\n", hex(s.dt_initial));
  out += fmt::format("time_step {} {} {} {}\n", hex(s.time_step.dt),
                     s.time_step.previous ? hex(*s.time_step.previous) : std::string("none"),
                     s.time_step.consecutive_decreases, s.time_step.increases);
  out += fmt::format("population {} {} {} {}\n", s.population.next, s.population.interval, s.population.last_event,
                     s.population.last_change);
  out += fmt::format("nodes {}\n", nodes.size());
  append_node_lines(out, nodes, s);
  append_curve_lines(out, nodes, s);
  append_history(out, s);
  out += "end\n";
  return out;
}

void write_checkpoint(const std::filesystem::path& path, const Checkpoint& checkpoint) {
  write_text_file(path, format_checkpoint(checkpoint));
}

Checkpoint parse_checkpoint(const std::string& text, const std::string& source_name) {
  LineScanner in(source_name, text);
  Checkpoint c;
  SimState& s = c.state;
  const bool v1 = parse_header(in);
  parse_driver_state(in, parse_case_keys(in, c), v1, s);
  const std::size_t n = parse_nodes(in, c.nodes, s);
  parse_curves(in, n, c.nodes, s);
  parse_history(in, v1, s);
  std::vector<std::string_view> t = in.expect_tokens("'convergence N', 'momentum N' or 'end' (the file is truncated)");
  if (!t.empty() && t[0] == "convergence") t = parse_convergence(in, t, s);
  if (!t.empty() && t[0] == "momentum") t = parse_momentum(in, t, n, s);
  parse_end(in, t);
  return c;
}

Checkpoint read_checkpoint(const std::filesystem::path& path) {
  return parse_checkpoint(read_text_file(path, InputKind::Checkpoint), path.string());
}

}  // namespace pdmesh
