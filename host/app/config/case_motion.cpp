// The [motion] section of a case file (docs/motion.md): the moving curves, the rotation and
// translation as expressions in t, the pivot, the step count, the warm iterations and the blending
// radius. Expressions are parsed here (a syntax error or an unknown name is the key's error); the
// curve names are checked against the geometry once it is read (app/pipeline/motion_pipeline.cpp).
#include <algorithm>
#include <fmt/ranges.h>

#include "app/config/case_reader.hpp"
#include "motion/rigid_motion.hpp"

namespace pdmesh::case_detail {

void read_motion_section(const Reader& r, const toml::table& root, CaseConfig& c) {
  const toml::node* section = root.get("motion");
  if (section == nullptr) return;
  const toml::table& t = *section->as_table();
  CaseConfig::Motion& m = c.motion;
  m.enabled = true;
  if (const toml::node* n = t.get("curves")) {
    m.curves = r.strings("motion.curves", *n);
    if (m.curves.empty()) r.fail("motion.curves", n, "motion.curves must name at least one curve");
    if (!c.geometry.curve_names.empty())
      for (const std::string& name : m.curves)
        if (std::find(c.geometry.curve_names.begin(), c.geometry.curve_names.end(), name) ==
            c.geometry.curve_names.end())
          r.fail("motion.curves", n,
                 fmt::format("motion.curves: unknown curve '{}' (geometry.curve_names: {})", quote_input(name),
                             fmt::join(c.geometry.curve_names, ", ")));
  } else if (!r.partial()) {
    r.fail("motion.curves", section, "motion.curves is required in [motion]");
  }
  const auto expression = [&](const std::string& key, const toml::node& n) {
    const std::string text = r.string(key, n);
    try {
      const TimeExpression e(text, key);
      for (double time : {0.0, 0.5, 1.0}) e(time);
    } catch (const InputError& e) {
      r.fail(key, &n, e.what());
    }
    return text;
  };
  if (const toml::node* n = t.get("rotate")) m.rotate = expression("motion.rotate", *n);
  if (const toml::node* n = t.get("translate")) {
    const toml::array& a = r.array("motion.translate", *n);
    if (a.size() != 2)
      r.fail("motion.translate", n,
             fmt::format("motion.translate must hold 2 expressions [x(t), y(t)], got {}", a.size()));
    for (std::size_t k = 0; k < 2; ++k) m.translate[k] = expression(fmt::format("motion.translate[{}]", k), *a.get(k));
  }
  if (const toml::node* n = t.get("pivot")) {
    const toml::array& a = r.array("motion.pivot", *n);
    if (a.size() != 2)
      r.fail("motion.pivot", n, fmt::format("motion.pivot must hold 2 numbers [x, y], got {}", a.size()));
    for (std::size_t k = 0; k < 2; ++k) m.pivot[k] = r.number(fmt::format("motion.pivot[{}]", k), *a.get(k));
  }
  if (const toml::node* n = t.get("steps")) {
    m.steps = r.integer("motion.steps", *n);
    if (m.steps < 1 || m.steps > 100000)
      r.fail("motion.steps", n, fmt::format("motion.steps must be in [1, 100000], got {}", m.steps));
  } else if (!r.partial()) {
    r.fail("motion.steps", section, "motion.steps is required in [motion]");
  }
  if (const toml::node* n = t.get("iterations")) {
    m.iterations = r.integer("motion.iterations", *n);
    if (m.iterations < 0 || m.iterations > 100000)
      r.fail("motion.iterations", n, fmt::format("motion.iterations must be in [0, 100000], got {}", m.iterations));
  }
  if (const toml::node* n = t.get("blend")) {
    m.blend = r.positive("motion.blend", *n);
    if (m.blend > 1000) r.fail("motion.blend", n, fmt::format("motion.blend must be at most 1000, got {}", m.blend));
  }
}

}  // namespace pdmesh::case_detail
