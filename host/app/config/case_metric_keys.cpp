// The [spacing] keys of the metric fields (spacing.field = "metric" or "hessian", docs/metric-fields.md):
// each value read and range-checked, then checked against spacing.field and the other keys. Every
// refusal names the key (its file, line and column, or its --set) and the value.
#include <algorithm>
#include <array>
#include <cmath>

#include "app/config/case_reader.hpp"
#include "core/input_file.hpp"

namespace pdmesh::case_detail {

namespace {

const std::array<const char*, 3> kSizeKeys = {"h1", "h2", "angle"};
const std::array<const char*, 3> kComponentKeys = {"m11", "m12", "m22"};
const std::array<const char*, 6> kHessianKeys = {"function", "complexity", "hmin", "hmax", "max_anisotropy", "norm"};

// The first of `keys` the [spacing] section sets, or null.
const char* first_given(const toml::table& root, const auto& keys) {
  for (const char* k : keys)
    if (find(root, "spacing", k) != nullptr) return k;
  return nullptr;
}

std::string expression(const Reader& r, const toml::node& n, const std::string& key) {
  const std::string v = r.string(key, n);
  if (v.find_first_not_of(" \t") == std::string::npos) r.fail(key, &n, fmt::format("{} must not be empty", key));
  return v;
}

}  // namespace

const char* spacing_kind_name(SpacingKind kind) {
  switch (kind) {
    case SpacingKind::Boundary:
      return "boundary";
    case SpacingKind::Expression:
      return "expression";
    case SpacingKind::Mesh:
      return "mesh";
    case SpacingKind::Metric:
      return "metric";
    case SpacingKind::Hessian:
      return "hessian";
  }
  return "boundary";
}

void read_metric_values(const Reader& r, const toml::table& root, CaseConfig& c) {
  auto& s = c.spacing;
  const std::array<std::pair<const char*, std::string*>, 7> strings = {{{"h1", &s.h1},
                                                                        {"h2", &s.h2},
                                                                        {"angle", &s.angle},
                                                                        {"m11", &s.m11},
                                                                        {"m12", &s.m12},
                                                                        {"m22", &s.m22},
                                                                        {"function", &s.function}}};
  for (const auto& [name, value] : strings) {
    if (const toml::node* n = find(root, "spacing", name)) *value = expression(r, *n, std::string("spacing.") + name);
  }
  if (const toml::node* n = find(root, "spacing", "sol")) {
    const std::string f = r.string("spacing.sol", *n);
    if (lower_extension(f) != ".sol")
      r.fail("spacing.sol", n, fmt::format("spacing.sol '{}' must be a Medit .sol file (ASCII)", quote_input(f)));
    s.sol = r.resolve("spacing.sol", f);
  }
  if (const toml::node* n = find(root, "spacing", "complexity")) s.complexity = r.positive("spacing.complexity", *n);
  if (const toml::node* n = find(root, "spacing", "hmin")) {
    s.hmin = r.number("spacing.hmin", *n);
    if (!(s.hmin >= 0.0)) r.fail("spacing.hmin", n, fmt::format("spacing.hmin must be >= 0, got {}", s.hmin));
  }
  if (const toml::node* n = find(root, "spacing", "hmax")) s.hmax = r.positive("spacing.hmax", *n);
  if (const toml::node* n = find(root, "spacing", "max_anisotropy")) {
    s.max_anisotropy = r.number("spacing.max_anisotropy", *n);
    if (!(s.max_anisotropy >= 1.0))
      r.fail("spacing.max_anisotropy", n, fmt::format("spacing.max_anisotropy must be >= 1, got {}", s.max_anisotropy));
  }
  if (const toml::node* n = find(root, "spacing", "norm")) {
    s.norm = r.number("spacing.norm", *n);
    if (!std::isfinite(s.norm) || !(s.norm >= 1.0))
      r.fail("spacing.norm", n, fmt::format("spacing.norm must be a finite number >= 1, got {}", s.norm));
  }
  if (const toml::node* n = find(root, "spacing", "metric_gradation")) {
    s.metric_gradation = r.number("spacing.metric_gradation", *n);
    if (!(s.metric_gradation == 0.0 || (s.metric_gradation > 1.0 && s.metric_gradation <= 100.0)))
      r.fail("spacing.metric_gradation", n,
             fmt::format("spacing.metric_gradation must be 0 (off) or in (1, 100], got {}", s.metric_gradation));
  }
  if (const toml::node* n = find(root, "spacing", "hessian_step")) {
    s.hessian_step = r.number("spacing.hessian_step", *n);
    if (!(s.hessian_step > 0.0 && s.hessian_step <= 0.1))
      r.fail("spacing.hessian_step", n,
             fmt::format("spacing.hessian_step must be in (0, 0.1], got {}", s.hessian_step));
  }
}

void check_metric_keys(const Reader& r, const toml::table& root, CaseConfig& c, const toml::node* file,
                       const toml::node* array) {
  auto& s = c.spacing;
  const char* name = spacing_kind_name(s.field);
  const auto node = [&root](const char* k) { return find(root, "spacing", k); };
  const auto refuse_unless = [&](bool allowed, const char* k) {
    if (!allowed && node(k) != nullptr)
      r.fail(std::string("spacing.") + k, node(k), fmt::format("spacing.{} is set but spacing.field is '{}'", k, name));
  };
  const bool metric = s.field == SpacingKind::Metric;
  const bool hessian = s.field == SpacingKind::Hessian;
  for (const char* k : kSizeKeys) refuse_unless(metric, k);
  for (const char* k : kComponentKeys) refuse_unless(metric, k);
  for (const char* k : kHessianKeys) refuse_unless(hessian, k);
  refuse_unless(metric, "sol");
  refuse_unless(metric || hessian, "metric_gradation");
  if (!c.spacing.arrays.empty() && !(hessian && file != nullptr))
    r.fail("spacing.array", array,
           fmt::format("spacing.array is a list, which only spacing.field = 'hessian' with spacing.file takes "
                       "(spacing.field is '{}'{})",
                       name, file == nullptr ? ", no spacing.file" : ""));
  refuse_unless(hessian && !s.function.empty(), "hessian_step");
  const bool medit = file != nullptr && lower_extension(s.file) == ".mesh";
  if (medit && !metric) {
    r.fail("spacing.file", file,
           fmt::format("spacing.file '{}' is a Medit .mesh, which holds metric data only (spacing.field = 'metric'); "
                       "spacing.field is '{}'",
                       quote_input(s.file.string()), name));
  }
  if (!metric && !hessian) return;

  if (metric) {
    const char* sizes = first_given(root, kSizeKeys);
    const char* components = first_given(root, kComponentKeys);
    if (sizes != nullptr && components != nullptr) {
      r.fail(std::string("spacing.") + components, node(components),
             fmt::format("spacing.{} and spacing.{} are both set: give the sizes (h1, h2, angle) or the components "
                         "(m11, m12, m22) of the metric, not both",
                         sizes, components));
    }
    if (file != nullptr && (sizes != nullptr || components != nullptr)) {
      const char* k = sizes != nullptr ? sizes : components;
      r.fail(std::string("spacing.") + k, node(k),
             fmt::format("spacing.{} and spacing.file are both set: give the metric by expressions or by a file, "
                         "not both",
                         k));
    }
    if (sizes != nullptr) {
      for (const char* k : {"h1", "h2"}) {
        if (node(k) == nullptr)
          r.fail(std::string("spacing.") + sizes, node(sizes),
                 fmt::format("spacing.field is 'metric' with sizes but spacing.{} is missing (h1, h2 and optionally "
                             "angle, in degrees)",
                             k));
      }
      if (s.angle.empty()) s.angle = std::string("0");  // a move: GCC 12 warns falsely (-Wrestrict) on = "0"
    } else if (components != nullptr) {
      for (const char* k : kComponentKeys) {
        if (node(k) == nullptr)
          r.fail(std::string("spacing.") + components, node(components),
                 fmt::format("spacing.field is 'metric' with components but spacing.{} is missing (m11, m12, m22)", k));
      }
    } else if (file == nullptr) {
      r.fail("spacing.field", node("field"),
             "spacing.field is 'metric' but no metric is given: set h1, h2 (and angle), or m11, m12, m22, or "
             "spacing.file (a .vtu/.msh with a 3-component array, or a Medit .mesh with its .sol)");
    }
    if (medit) {
      if (array != nullptr)
        r.fail("spacing.array", array,
               "spacing.array is set but spacing.file is a Medit .mesh (its metric is in the .sol)");
      if (s.sol.empty()) s.sol = fs::path(s.file).replace_extension(".sol");
    } else if (node("sol") != nullptr) {
      r.fail("spacing.sol", node("sol"), "spacing.sol is set but spacing.file is not a Medit .mesh");
    } else if (file != nullptr && array == nullptr) {
      s.array = "metric";
    }
  } else {
    const bool function = node("function") != nullptr;
    if (function && file != nullptr)
      r.fail("spacing.function", node("function"),
             "spacing.function and spacing.file are both set: give the function by an expression or as data, not both");
    if (!function && file == nullptr)
      r.fail("spacing.field", node("field"),
             "spacing.field is 'hessian' but spacing.function (an expression in x and y) or spacing.file (scalar data "
             "on a .vtu/.msh mesh) is missing");
    if (function && array != nullptr)
      r.fail("spacing.array", array,
             "spacing.array is set but the Hessian's function is an expression (spacing.function)");
    if (file != nullptr && array == nullptr) s.array = std::string("u");
    if (node("complexity") == nullptr)
      r.fail("spacing.field", node("field"),
             "spacing.field is 'hessian' but spacing.complexity (the metric's complexity C: the mesh has about "
             "4C/sqrt(3) triangles) is missing");
    if (!(s.hmax > s.hmin))
      r.fail(node("hmax") != nullptr ? "spacing.hmax" : "spacing.hmin",
             node("hmax") != nullptr ? node("hmax") : node("hmin"),
             fmt::format("spacing.hmax must be larger than spacing.hmin, got hmin {} and hmax {}", s.hmin, s.hmax));
  }
}

}  // namespace pdmesh::case_detail
