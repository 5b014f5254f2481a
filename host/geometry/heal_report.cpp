// heal_report_lines() and heal_json() (heal_report.hpp).
#include "geometry/heal_report.hpp"

#include <fmt/format.h>

namespace pdmesh {

namespace {

const char* size_word(HealKind kind) {
  switch (kind) {
    case HealKind::Merge:
      return "apart";
    case HealKind::Spike:
      return "degrees";
    case HealKind::InletClosed:
    case HealKind::InletOpened:
      return "wide";
    case HealKind::Island:
      return "in area";
    case HealKind::Joined:
      return "neck radius";
  }
  return "";
}

const char* json_kind(HealKind kind) {
  switch (kind) {
    case HealKind::Merge:
      return "merge";
    case HealKind::Spike:
      return "spike";
    case HealKind::InletClosed:
      return "inlet_closed";
    case HealKind::InletOpened:
      return "inlet_opened";
    case HealKind::Island:
      return "island";
    case HealKind::Joined:
      return "joined";
  }
  return "";
}

std::string escaped(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<int>(static_cast<unsigned char>(c)));
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string points_json(const std::vector<Vec2>& pts) {
  std::string out = "[";
  for (std::size_t k = 0; k < pts.size(); ++k)
    out += fmt::format("{}[{:.17g}, {:.17g}]", k ? ", " : "", pts[k].x, pts[k].y);
  return out + "]";
}

}  // namespace

std::vector<std::string> heal_report_lines(const HealResult& result) {
  std::vector<std::string> lines;
  for (int k = 0; k < kHealKinds; ++k) {
    const auto kind = static_cast<HealKind>(k);
    const HealChange* w = result.worst(kind);
    if (w == nullptr) continue;
    lines.push_back(
        fmt::format("healing: {} {} (worst: {:.4g} {}, local spacing {:.4g}, at ({:.10g}, {:.10g}), {}:{} curve {})",
                    result.count(kind), to_string(kind), w->size, size_word(kind), w->h, w->at.x, w->at.y, w->file,
                    w->line, w->curve));
  }
  return lines;
}

std::string heal_json(const HealResult& result) {
  std::string counts;
  for (int k = 0; k < kHealKinds; ++k) {
    const auto kind = static_cast<HealKind>(k);
    counts += fmt::format("{}\"{}\": {}", k ? ", " : "", json_kind(kind), result.count(kind));
  }
  std::string changes;
  for (std::size_t k = 0; k < result.changes.size(); ++k) {
    const HealChange& c = result.changes[k];
    changes += fmt::format(
        "{}\n    {{\"kind\": \"{}\", \"curve\": {}, \"file\": {}, \"line\": {}, \"at\": [{:.17g}, {:.17g}], "
        "\"size\": {:.17g}, \"h\": {:.17g}, \"removed\": {}, \"added\": {}}}",
        k ? "," : "", json_kind(c.kind), escaped(c.curve), escaped(c.file), c.line, c.at.x, c.at.y, c.size, c.h,
        points_json(c.removed), points_json(c.added));
  }
  return fmt::format("{{\"counts\": {{{}}}, \"changes\": [{}\n  ]}}", counts, changes);
}

}  // namespace pdmesh
