// Formats a QualitySummary as the thesis-style table and as quality.json (written atomically).
#include "io/quality_report.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

#include <fmt/format.h>

#include "core/g17.hpp"
#include "io/text_file.hpp"

namespace pdmesh {
namespace {

using Cell = std::function<std::string(const QualitySummary&)>;

struct Row {
  std::string name;  // first column, as in the thesis ("Included Angle", "(degrees)", ...)
  std::string sub;   // second column ("MIN", "Average", ...)
  Cell value;
};

Cell fixed(double QualitySummary::*field, int decimals) {
  return [field, decimals](const QualitySummary& s) { return fmt::format("{:.{}f}", s.*field, decimals); };
}

Cell spacing_cell(double SpacingConformance::*field) {
  return [field](const QualitySummary& s) {
    return s.has_spacing && s.spacing.edges > 0 ? fmt::format("{:.3f}", s.spacing.*field) : std::string("-");
  };
}

std::string histogram_label(const Histogram& h, std::size_t k, int decimals) {
  return fmt::format("[{:.{}f},{:.{}f})", h.edge(k), decimals, h.edge(k + 1), decimals);
}

// `cleanup`: some column comes from a cleaned mesh (its rows are shown, '-' in the other columns).
// `metric`: some column was measured in a metric field (its rows are shown, '-' in the other columns).
std::vector<Row> table_rows(const QualitySummary& first, const QualitySummary* cleanup, const QualitySummary* metric) {
  std::vector<Row> rows = {
      {"Number of Triangles", "", [](const QualitySummary& s) { return fmt::format("{}", s.triangles); }},
      {"Included Angle", "MIN", fixed(&QualitySummary::min_angle, 2)},
      {"(degrees)", "MAX", fixed(&QualitySummary::max_angle, 2)},
      {"Aspect ratio", "Average", fixed(&QualitySummary::aspect_ratio_avg, 3)},
      {"(1,inf)", "MAX", fixed(&QualitySummary::aspect_ratio_max, 3)},
      {"Skewness", "Average", fixed(&QualitySummary::skewness_avg, 3)},
      {"(1,inf)", "MAX", fixed(&QualitySummary::skewness_max, 3)},
      {"Weighted Condition Number", "Average", fixed(&QualitySummary::condition_number_avg, 3)},
      {"(1,inf)", "MAX", fixed(&QualitySummary::condition_number_max, 3)},
      {"Minimum Corner Jacobian", "", fixed(&QualitySummary::min_jacobian, 3)},
      {"", "", nullptr},  // separator: the thesis rows end here
      {"Number of Points", "", [](const QualitySummary& s) { return fmt::format("{}", s.points); }},
      {fmt::format("Min angle < {:g} deg", first.small_angle_deg), "count",
       [](const QualitySummary& s) { return fmt::format("{}", s.small_angle_triangles); }},
      {"", "share %", [](const QualitySummary& s) { return fmt::format("{:.2f}", 100.0 * s.small_angle_share); }},
      {"Edge length / q(midpoint)", "mean", spacing_cell(&SpacingConformance::mean)},
      {"", "std dev", spacing_cell(&SpacingConformance::stddev)},
      {"", "P05", spacing_cell(&SpacingConformance::p05)},
      {"", "P95", spacing_cell(&SpacingConformance::p95)},
  };
  // The cleanup rows (docs/cleanup.md), shown when a column comes from a cleaned mesh.
  auto cleanup_count = [](std::size_t CleanupEffect::*field) {
    return [field](const QualitySummary& s) {
      return s.has_cleanup ? fmt::format("{}", s.cleanup.*field) : std::string("-");
    };
  };
  auto cleanup_angle = [](double CleanupEffect::*field) {
    return [field](const QualitySummary& s) {
      return s.has_cleanup ? fmt::format("{:.2f}", s.cleanup.*field) : std::string("-");
    };
  };
  if (cleanup != nullptr) {
    rows.push_back({fmt::format("Cleanup: < {:g} deg", cleanup->cleanup.target_deg), "before",
                    cleanup_count(&CleanupEffect::below_before)});
    rows.push_back({"", "after", cleanup_count(&CleanupEffect::below_after)});
    rows.push_back({"Cleanup: min angle", "before", cleanup_angle(&CleanupEffect::min_angle_before)});
    rows.push_back({"", "after", cleanup_angle(&CleanupEffect::min_angle_after)});
    rows.push_back({"Cleanup: nodes", "inserted", cleanup_count(&CleanupEffect::inserted)});
    rows.push_back({"", "removed", cleanup_count(&CleanupEffect::removed)});
  }
  if (metric != nullptr) {
    // UGAWG's measures in the metric (docs/metric-fields.md, "Measures").
    auto m = [](auto f) {
      return [f](const QualitySummary& s) { return s.has_metric ? f(s.metric) : std::string("-"); };
    };
    rows.push_back({"Metric: edges in [0.71,1.41]", "%",
                    m([](const MetricQualitySummary& q) { return fmt::format("{:.2f}", q.window_percent); })});
    rows.push_back({"Metric: edge length", "MIN",
                    m([](const MetricQualitySummary& q) { return fmt::format("{:.3f}", q.length_min); })});
    rows.push_back({"", "MAX", m([](const MetricQualitySummary& q) { return fmt::format("{:.3f}", q.length_max); })});
    rows.push_back(
        {"Metric: quality Q", "MIN", m([](const MetricQualitySummary& q) { return fmt::format("{:.3f}", q.q_min); })});
    rows.push_back({"", "mean", m([](const MetricQualitySummary& q) { return fmt::format("{:.3f}", q.q_mean); })});
    rows.push_back(
        {"", "< 0.3 %", m([](const MetricQualitySummary& q) { return fmt::format("{:.2f}", q.q_below_0_3_percent); })});
    rows.push_back({"Metric: triangles / 4C/sqrt3", "",
                    m([](const MetricQualitySummary& q) { return fmt::format("{:.3f}", q.n_over_ideal); })});
    rows.push_back(
        {"", "4C/sqrt3", m([](const MetricQualitySummary& q) { return fmt::format("{:.1f}", q.ideal_triangles); })});
    for (std::size_t k = 0; k < kMetricQualityBins; ++k) {
      const std::string bin = k == 0                        ? "<0.1"
                              : k + 1 == kMetricQualityBins ? ">=0.9"
                                                            : fmt::format("[{:.1f},{:.1f})", k / 10.0, (k + 1) / 10.0);
      rows.push_back({k == 0 ? "Metric: Q histogram" : "", bin,
                      m([k](const MetricQualitySummary& q) { return fmt::format("{}", q.q_histogram[k]); })});
    }
  }
  const Histogram& ha = first.min_angle_histogram;
  for (std::size_t k = 0; k < ha.counts.size(); ++k) {
    rows.push_back({k == 0 ? "Min angle histogram" : "", histogram_label(ha, k, 0), [k](const QualitySummary& s) {
                      const auto& c = s.min_angle_histogram.counts;
                      return k < c.size() ? fmt::format("{}", c[k]) : std::string("-");
                    }});
  }
  const Histogram& hr = first.aspect_ratio_histogram;
  for (std::size_t k = 0; k < hr.counts.size(); ++k) {
    rows.push_back({k == 0 ? "Aspect ratio histogram" : "", histogram_label(hr, k, 1), [k](const QualitySummary& s) {
                      const auto& c = s.aspect_ratio_histogram.counts;
                      return k < c.size() ? fmt::format("{}", c[k]) : std::string("-");
                    }});
  }
  rows.push_back({hr.counts.empty() ? "Aspect ratio histogram" : "", fmt::format(">={:.1f}", hr.edge(hr.counts.size())),
                  [](const QualitySummary& s) { return fmt::format("{}", s.aspect_ratio_histogram.overflow); }});
  return rows;
}

// JSON number; JSON has no infinity or NaN, so those become null.
std::string num(double v) { return std::isfinite(v) ? fmt::format("{}", v) : std::string("null"); }

std::string histogram_json(const Histogram& h) {
  std::string counts;
  for (std::size_t k = 0; k < h.counts.size(); ++k) counts += fmt::format("{}{}", k ? ", " : "", h.counts[k]);
  return fmt::format("{{\"lo\": {}, \"width\": {}, \"counts\": [{}], \"overflow\": {}}}", num(h.lo), num(h.width),
                     counts, h.overflow);
}

// The members of a summary's per-triangle figures and spacing conformance, from "triangles" to
// "spacing_conformance", one per line at `indent`, without a comma after the last: the top level of
// quality.json and each entry of its "regions".
std::string figures_json(const QualitySummary& s, const std::string& indent) {
  std::string spacing = "null";
  if (s.has_spacing) {
    const auto& c = s.spacing;
    spacing = fmt::format(
        "{{\"edges\": {}, \"mean\": {}, \"stddev\": {}, \"p05\": {}, \"p95\": {}, \"min\": {}, \"max\": {}}}", c.edges,
        num(c.mean), num(c.stddev), num(c.p05), num(c.p95), num(c.min), num(c.max));
  }
  const std::string& i = indent;
  std::string out;
  out += fmt::format("{}\"triangles\": {},\n{}\"points\": {},\n", i, s.triangles, i, s.points);
  out += fmt::format("{}\"included_angle\": {{\"min\": {}, \"max\": {}}},\n", i, num(s.min_angle), num(s.max_angle));
  out += fmt::format("{}\"aspect_ratio\": {{\"average\": {}, \"max\": {}}},\n", i, num(s.aspect_ratio_avg),
                     num(s.aspect_ratio_max));
  out +=
      fmt::format("{}\"skewness\": {{\"average\": {}, \"max\": {}}},\n", i, num(s.skewness_avg), num(s.skewness_max));
  out += fmt::format("{}\"weighted_condition_number\": {{\"average\": {}, \"max\": {}}},\n", i,
                     num(s.condition_number_avg), num(s.condition_number_max));
  out += fmt::format("{}\"minimum_corner_jacobian\": {},\n", i, num(s.min_jacobian));
  out += fmt::format("{}\"small_angle\": {{\"threshold_deg\": {}, \"triangles\": {}, \"share\": {}}},\n", i,
                     num(s.small_angle_deg), s.small_angle_triangles, num(s.small_angle_share));
  out += fmt::format("{}\"histograms\": {{\n{}  \"min_angle\": {},\n{}  \"aspect_ratio\": {}\n{}}},\n", i, i,
                     histogram_json(s.min_angle_histogram), i, histogram_json(s.aspect_ratio_histogram), i);
  out += fmt::format("{}\"spacing_conformance\": {}", i, spacing);
  return out;
}

// quality.json's "regions" array (summary.regions), one object per region over several lines.
std::string regions_json(const std::vector<RegionQuality>& regions) {
  std::string out = "[\n";
  for (std::size_t k = 0; k < regions.size(); ++k) {
    const RegionQuality& r = regions[k];
    out += fmt::format("    {{\n      \"attribute\": {},\n      \"name\": {},\n{}\n    }}{}\n", num(r.attribute),
                       json_string(r.name), figures_json(r.quality, "      "), k + 1 < regions.size() ? "," : "");
  }
  return out + "  ]";
}

}  // namespace

std::string format_quality_table(const std::vector<std::pair<std::string, QualitySummary>>& columns) {
  if (columns.empty()) return {};
  const QualitySummary* cleanup = nullptr;
  for (const auto& column : columns)
    if (column.second.has_cleanup && cleanup == nullptr) cleanup = &column.second;
  const QualitySummary* metric = nullptr;
  for (const auto& column : columns)
    if (column.second.has_metric && metric == nullptr) metric = &column.second;
  const auto rows = table_rows(columns.front().second, cleanup, metric);
  std::size_t name_width = 0, sub_width = 0;
  for (const auto& r : rows) {
    name_width = std::max(name_width, r.name.size());
    sub_width = std::max(sub_width, r.sub.size());
  }
  std::vector<std::size_t> widths;
  for (const auto& [label, summary] : columns) {
    std::size_t w = std::max<std::size_t>(label.size(), 8);
    for (const auto& r : rows) {
      if (r.value) w = std::max(w, r.value(summary).size());
    }
    widths.push_back(w);
  }
  std::string out = fmt::format("{:<{}}  {:<{}}", "", name_width, "", sub_width);
  for (std::size_t c = 0; c < columns.size(); ++c) out += fmt::format("  {:>{}}", columns[c].first, widths[c]);
  out += '\n';
  std::size_t total = name_width + 2 + sub_width;
  for (auto w : widths) total += 2 + w;
  for (const auto& r : rows) {
    if (!r.value) {
      out += std::string(total, '-') + '\n';
      continue;
    }
    out += fmt::format("{:<{}}  {:<{}}", r.name, name_width, r.sub, sub_width);
    for (std::size_t c = 0; c < columns.size(); ++c)
      out += fmt::format("  {:>{}}", r.value(columns[c].second), widths[c]);
    out += '\n';
  }
  return out;
}

std::string format_quality_table(const QualitySummary& summary, const std::string& label) {
  return format_quality_table({{label, summary}});
}

std::string format_region_table(const QualitySummary& summary) {
  if (summary.regions.size() < 2) return {};
  // Columns: the table's rows above, one row per region; the name last, as it may be long.
  struct Column {
    std::string head;
    std::function<std::string(const QualitySummary&)> value;
  };
  std::vector<Column> columns = {
      {"triangles", [](const QualitySummary& s) { return fmt::format("{}", s.triangles); }},
      {"points", [](const QualitySummary& s) { return fmt::format("{}", s.points); }},
      {"angle MIN", fixed(&QualitySummary::min_angle, 2)},
      {"angle MAX", fixed(&QualitySummary::max_angle, 2)},
      {"AR avg", fixed(&QualitySummary::aspect_ratio_avg, 3)},
      {"AR MAX", fixed(&QualitySummary::aspect_ratio_max, 3)},
      {"skew avg", fixed(&QualitySummary::skewness_avg, 3)},
      {"skew MAX", fixed(&QualitySummary::skewness_max, 3)},
      {"K_W avg", fixed(&QualitySummary::condition_number_avg, 3)},
      {"K_W MAX", fixed(&QualitySummary::condition_number_max, 3)},
      {"Jacobian", fixed(&QualitySummary::min_jacobian, 3)},
      {fmt::format("<{:g}deg", summary.small_angle_deg),
       [](const QualitySummary& s) { return fmt::format("{}", s.small_angle_triangles); }},
  };
  if (summary.has_spacing) {
    columns.push_back({"h/q mean", spacing_cell(&SpacingConformance::mean)});
    columns.push_back({"h/q P05", spacing_cell(&SpacingConformance::p05)});
    columns.push_back({"h/q P95", spacing_cell(&SpacingConformance::p95)});
  }
  std::vector<std::vector<std::string>> cells;
  std::vector<std::size_t> widths;
  for (const Column& c : columns) widths.push_back(c.head.size());
  std::size_t attribute_width = std::string("attribute").size();
  for (const RegionQuality& r : summary.regions) {
    std::vector<std::string> row;
    for (std::size_t c = 0; c < columns.size(); ++c) {
      row.push_back(columns[c].value(r.quality));
      widths[c] = std::max(widths[c], row.back().size());
    }
    cells.push_back(std::move(row));
    attribute_width = std::max(attribute_width, fmt::format("{}", r.attribute).size());
  }
  std::string out =
      fmt::format("Per region ({} regions):\n{:>{}}", summary.regions.size(), "attribute", attribute_width);
  for (std::size_t c = 0; c < columns.size(); ++c) out += fmt::format("  {:>{}}", columns[c].head, widths[c]);
  out += "  region\n";
  for (std::size_t k = 0; k < summary.regions.size(); ++k) {
    out += fmt::format("{:>{}}", fmt::format("{}", summary.regions[k].attribute), attribute_width);
    for (std::size_t c = 0; c < columns.size(); ++c) out += fmt::format("  {:>{}}", cells[k][c], widths[c]);
    out += fmt::format("  {}\n", summary.regions[k].name);
  }
  return out;
}

std::string json_string(const std::string& text) {
  std::string out = "\"";
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    switch (ch) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\b':
        out += "\\b";
        break;
      case '\f':
        out += "\\f";
        break;
      default:
        if (c < 0x20 || c == 0x7f) {
          out += fmt::format("\\u{:04x}", c);
        } else {
          out += ch;  // UTF-8 bytes pass through unchanged
        }
    }
  }
  return out + "\"";
}

std::string quality_json(const QualitySummary& s, const std::string& source, const std::string& healing,
                         const std::string& periodic, const std::string& trailing) {
  std::string out = "{\n";
  out += "  \"format\": \"pdmesh-quality\",\n  \"version\": 1,\n";
  out += fmt::format("  \"source\": {},\n", json_string(source));
  out += figures_json(s, "  ") + ",\n";
  std::string cleanup = "null";
  if (s.has_cleanup) {
    const CleanupEffect& e = s.cleanup;
    cleanup = fmt::format(
        "{{\"target_deg\": {}, \"below_target\": {{\"before\": {}, \"after\": {}}}, "
        "\"min_angle\": {{\"before\": {}, \"after\": {}}}, \"max_angle\": {{\"before\": {}, \"after\": {}}}, "
        "\"triangles_before\": {}, \"points_before\": {}, \"inserted\": {}, \"removed\": {}, \"moves\": {}}}",
        num(e.target_deg), e.below_before, e.below_after, num(e.min_angle_before), num(e.min_angle_after),
        num(e.max_angle_before), num(e.max_angle_after), e.triangles_before, e.points_before, e.inserted, e.removed,
        e.moves);
  }
  // Only for a mesh measured in a metric, so that every other quality.json stays as it was.
  if (s.has_metric) {
    const MetricQualitySummary& m = s.metric;
    std::string histogram;
    for (std::size_t k = 0; k < kMetricQualityBins; ++k)
      histogram += fmt::format("{}{}", k ? ", " : "", m.q_histogram[k]);
    out += fmt::format(
        "  \"metric\": {{\"edges\": {}, \"window\": [{}, {}], \"window_percent\": {}, \"length_min\": {}, "
        "\"length_max\": {}, \"q_min\": {}, \"q_mean\": {}, \"q_below_0_3_percent\": {}, \"q_histogram\": [{}], "
        "\"complexity\": {}, \"ideal_triangles\": {}, \"n_over_ideal\": {}}},\n",
        m.edges, num(kMetricWindowLo), num(kMetricWindowHi), num(m.window_percent), num(m.length_min),
        num(m.length_max), num(m.q_min), num(m.q_mean), num(m.q_below_0_3_percent), histogram, num(m.complexity),
        num(m.ideal_triangles), num(m.n_over_ideal));
  }
  // Only when healing changed the geometry, so that every other quality.json stays as it was.
  if (!healing.empty()) out += fmt::format("  \"healing\": {},\n", healing);
  // Only with [[periodic]] tables, so that other runs' files stay as they were.
  if (!periodic.empty()) out += fmt::format("  \"periodic\": {},\n", periodic);
  if (!s.constraints.empty()) {
    // Only with embedded constraints, so that other runs' files stay as they were.
    std::string list;
    for (const auto& [name, edges] : s.constraints)
      list += fmt::format("{}{{\"curve\": {}, \"edges\": {}}}", list.empty() ? "" : ", ", json_string(name), edges);
    out += fmt::format("  \"constraints\": [{}],\n", list);
  }
  // Only for a mesh with regions, so that every other quality.json stays as it was.
  if (!s.regions.empty()) out += fmt::format("  \"regions\": {},\n", regions_json(s.regions));
  // The caller's members follow "cleanup" on its line: `trailing` starts with the comma.
  out += fmt::format("  \"cleanup\": {}", cleanup);
  out += trailing.empty() ? "\n" : trailing;
  out += "}\n";
  return out;
}

std::filesystem::path write_quality_json(const QualitySummary& summary, const std::filesystem::path& dir,
                                         const std::string& source, const std::string& healing,
                                         const std::string& periodic, const std::string& trailing) {
  const auto path = dir / "quality.json";
  write_text_file(path, quality_json(summary, source, healing, periodic, trailing));
  return path;
}

std::string periodic_json(const std::vector<std::string>& curve_names, const std::vector<PeriodicLink>& links) {
  std::string out;
  for (const PeriodicLink& l : links) {
    out += fmt::format("{}{{\"source\": {}, \"image\": {}, \"pairs\": {}, \"max_mismatch\": ", out.empty() ? "" : ", ",
                       json_string(curve_names[static_cast<std::size_t>(l.source_curve)]),
                       json_string(curve_names[static_cast<std::size_t>(l.curve)]), l.nodes.size());
    if (std::isfinite(l.max_mismatch))
      append_g17(out, l.max_mismatch);
    else
      out += "null";  // a link read without an affine transform
    out += '}';
  }
  return links.empty() ? std::string() : "[" + out + "]";
}

}  // namespace pdmesh
