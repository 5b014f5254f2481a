// The [[boundary_layer]] tables of a case file (docs/boundary-layers.md): each one's curves, first
// height (or y+ with the Reynolds number and reference length), growth, thickness or layer count and
// element kind, range-checked here; the curve names are checked against the geometry once it is read
// (app/pipeline/layer_pipeline.cpp), before anything is written.
#include <algorithm>
#include <cmath>
#include <fmt/ranges.h>

#include "app/config/case_reader.hpp"

namespace pdmesh {

double first_height_for_y_plus(double y_plus, double reynolds, double reference_length) {
  const double cf = 0.026 / std::pow(reynolds, 1.0 / 7.0);
  return y_plus * reference_length / (reynolds * std::sqrt(0.5 * cf));
}

}  // namespace pdmesh

namespace pdmesh::case_detail {

namespace {

const toml::node* get(const toml::table& t, std::string_view key) { return t.get(key); }

CaseConfig::BoundaryLayer read_layer_table(const Reader& r, const toml::table& t, const toml::node& table_node,
                                           const CaseConfig& c) {
  CaseConfig::BoundaryLayer b;
  const auto required = [&](std::string_view key) -> const toml::node& {
    const toml::node* n = get(t, key);
    if (n == nullptr)
      r.fail(fmt::format("boundary_layer.{}", key), &table_node, fmt::format("boundary_layer.{} is required", key));
    return *n;
  };
  const toml::node& curves = required("curves");
  b.curves = r.strings("boundary_layer.curves", curves);
  b.curves_where = r.where("boundary_layer.curves", &curves.source());
  if (b.curves.empty()) r.fail("boundary_layer.curves", &curves, "boundary_layer.curves must name at least one curve");
  // Names the case file gives are checked here; names from the geometry files once they are read.
  if (!c.geometry.curve_names.empty()) {
    for (const std::string& name : b.curves)
      if (std::find(c.geometry.curve_names.begin(), c.geometry.curve_names.end(), name) == c.geometry.curve_names.end())
        r.fail("boundary_layer.curves", &curves,
               fmt::format("boundary_layer.curves: unknown curve '{}' (geometry.curve_names: {})", quote_input(name),
                           fmt::join(c.geometry.curve_names, ", ")));
  }
  const toml::node* h = get(t, "first_height");
  const toml::node* yp = get(t, "y_plus");
  if ((h == nullptr) == (yp == nullptr))
    r.fail("boundary_layer.first_height", h ? h : &table_node,
           "boundary_layer: give exactly one of first_height and y_plus (with reynolds and reference_length)");
  if (h) {
    b.first_height = r.positive("boundary_layer.first_height", *h);
    for (const char* key : {"reynolds", "reference_length"})
      if (const toml::node* n = get(t, key))
        r.fail(fmt::format("boundary_layer.{}", key), n,
               fmt::format("boundary_layer.{} goes with y_plus, not with first_height", key));
  } else {
    b.y_plus = r.positive("boundary_layer.y_plus", *yp);
    b.reynolds = r.positive("boundary_layer.reynolds", required("reynolds"));
    b.reference_length = r.positive("boundary_layer.reference_length", required("reference_length"));
    if (b.reynolds < 1e3 || b.reynolds > 1e10)
      r.fail(
          "boundary_layer.reynolds", get(t, "reynolds"),
          fmt::format("boundary_layer.reynolds must be in [1e3, 1e10] (the flat-plate estimate), got {}", b.reynolds));
    b.first_height = first_height_for_y_plus(b.y_plus, b.reynolds, b.reference_length);
  }
  if (const toml::node* n = get(t, "growth")) {
    b.growth = r.number("boundary_layer.growth", *n);
    if (!(b.growth > 1.0 && b.growth <= 3.0))
      r.fail("boundary_layer.growth", n, fmt::format("boundary_layer.growth must be in (1, 3], got {}", b.growth));
  }
  const toml::node* thickness = get(t, "thickness");
  const toml::node* layers = get(t, "layers");
  if ((thickness == nullptr) == (layers == nullptr))
    r.fail("boundary_layer.thickness", thickness ? thickness : &table_node,
           "boundary_layer: give exactly one of thickness and layers");
  if (thickness) {
    b.thickness = r.positive("boundary_layer.thickness", *thickness);
    if (b.first_height > b.thickness)
      r.fail("boundary_layer.thickness", thickness,
             fmt::format("boundary_layer.first_height {} is above boundary_layer.thickness {}", b.first_height,
                         b.thickness));
  } else {
    const std::int64_t n = r.integer("boundary_layer.layers", *layers);
    if (n < 1 || n > 200)
      r.fail("boundary_layer.layers", layers, fmt::format("boundary_layer.layers must be in [1, 200], got {}", n));
    b.layers = static_cast<int>(n);
  }
  if (const toml::node* n = get(t, "elements"))
    b.quads = choose<bool>(r, "boundary_layer.elements", *n, {{"triangles", false}, {"quads", true}});
  return b;
}

}  // namespace

void read_boundary_layer_sections(const Reader& r, const toml::table& root, CaseConfig& c) {
  const toml::node* node = root.get("boundary_layer");
  if (node == nullptr) return;
  if (node->is_table()) {
    c.boundary_layers.push_back(read_layer_table(r, *node->as_table(), *node, c));
    return;
  }
  for (const toml::node& e : *node->as_array()) c.boundary_layers.push_back(read_layer_table(r, *e.as_table(), e, c));
  // One wall curve in two sections would get two layers.
  for (std::size_t i = 0; i < c.boundary_layers.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      for (const std::string& name : c.boundary_layers[i].curves)
        if (std::find(c.boundary_layers[j].curves.begin(), c.boundary_layers[j].curves.end(), name) !=
            c.boundary_layers[j].curves.end())
          r.fail(
              "boundary_layer.curves", node->as_array()->get(i),
              fmt::format("boundary_layer.curves: curve '{}' is in two [[boundary_layer]] tables", quote_input(name)));
}

}  // namespace pdmesh::case_detail
