// The [[periodic]] tables of a case file (docs/geometry-input.md, "Periodic curves"): each one's two
// curve names and its transform (translate, rotate, or neither: inferred from the curves' ends). The
// names and the transform are checked against the geometry once it is read
// (app/pipeline/periodic_pipeline.cpp), before anything is written.
#include <algorithm>
#include <fmt/ranges.h>

#include "app/config/case_reader.hpp"

namespace pdmesh::case_detail {

namespace {

std::array<double, 2> pair_of_numbers(const Reader& r, const std::string& key, const toml::node& n) {
  const toml::array& a = r.array(key, n);
  if (a.size() != 2) r.fail(key, &n, fmt::format("{} must hold 2 numbers [x, y], got {}", key, a.size()));
  return {r.number(fmt::format("{}[0]", key), *a.get(0)), r.number(fmt::format("{}[1]", key), *a.get(1))};
}

CaseConfig::Periodic read_periodic_table(const Reader& r, const toml::table& t, const toml::node& table_node,
                                         const CaseConfig& c) {
  CaseConfig::Periodic p;
  p.where = r.where("periodic", &table_node.source());
  const toml::node* curves = t.get("curves");
  if (curves == nullptr) r.fail("periodic.curves", &table_node, "periodic.curves is required: [source, image]");
  const std::vector<std::string> names = r.strings("periodic.curves", *curves);
  if (names.size() != 2)
    r.fail("periodic.curves", curves,
           fmt::format("periodic.curves must name 2 curves [source, image], got {}", names.size()));
  p.source = names[0];
  p.image = names[1];
  if (p.source == p.image)
    r.fail("periodic.curves", curves,
           fmt::format("periodic.curves: curve '{}' cannot be periodic with itself", quote_input(p.source)));
  if (!c.geometry.curve_names.empty())
    for (const std::string& name : names)
      if (std::find(c.geometry.curve_names.begin(), c.geometry.curve_names.end(), name) == c.geometry.curve_names.end())
        r.fail("periodic.curves", curves,
               fmt::format("periodic.curves: unknown curve '{}' (geometry.curve_names: {})", quote_input(name),
                           fmt::join(c.geometry.curve_names, ", ")));
  const toml::node* translate = t.get("translate");
  const toml::node* rotate = t.get("rotate");
  if (translate != nullptr && rotate != nullptr)
    r.fail("periodic.rotate", rotate, "periodic: give at most one of translate and rotate");
  if (translate != nullptr) {
    p.kind = CaseConfig::Periodic::Kind::Translate;
    p.translate = pair_of_numbers(r, "periodic.translate", *translate);
  }
  if (rotate != nullptr) {
    if (!rotate->is_table()) r.wrong_type("periodic.rotate", *rotate, "a table {center = [x, y], angle_deg = a}");
    const toml::table& rt = *rotate->as_table();
    for (const auto& [k, v] : rt)
      if (k.str() != "center" && k.str() != "angle_deg")
        r.fail_at_key("periodic.rotate", k,
                      fmt::format("unknown key 'periodic.rotate.{}' (periodic.rotate holds center and angle_deg)",
                                  quote_input(std::string(k.str()))));
    const toml::node* center = rt.get("center");
    const toml::node* angle = rt.get("angle_deg");
    if (center == nullptr || angle == nullptr)
      r.fail("periodic.rotate", rotate, "periodic.rotate needs both center = [x, y] and angle_deg");
    p.kind = CaseConfig::Periodic::Kind::Rotate;
    p.center = pair_of_numbers(r, "periodic.rotate.center", *center);
    p.angle_deg = r.number("periodic.rotate.angle_deg", *angle);
    if (!(p.angle_deg != 0.0 && p.angle_deg > -360.0 && p.angle_deg < 360.0))
      r.fail("periodic.rotate.angle_deg", angle,
             fmt::format("periodic.rotate.angle_deg must be in (-360, 360) and not 0, got {}", p.angle_deg));
  }
  return p;
}

}  // namespace

void read_periodic_sections(const Reader& r, const toml::table& root, CaseConfig& c) {
  const toml::node* node = root.get("periodic");
  if (node == nullptr) return;
  if (node->is_table()) {
    c.periodic.push_back(read_periodic_table(r, *node->as_table(), *node, c));
  } else {
    for (const toml::node& e : *node->as_array()) c.periodic.push_back(read_periodic_table(r, *e.as_table(), e, c));
  }
  // A curve in two tables would be asked to carry two node sets (or the same one twice).
  for (std::size_t i = 0; i < c.periodic.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      for (const std::string& name : {c.periodic[i].source, c.periodic[i].image})
        if (name == c.periodic[j].source || name == c.periodic[j].image)
          throw InputError(
              fmt::format("{}: [[periodic]]: curve '{}' is in two tables (also at {}); a curve can be "
                          "in one periodic pair only",
                          c.periodic[i].where, quote_input(name), c.periodic[j].where));
}

}  // namespace pdmesh::case_detail
