// The case keys of sizes as users state them and of the far field: spacing.size, the [[refine]]
// tables (spacing/refine_regions.hpp) and [farfield] (geometry/farfield.hpp), each value checked here
// with messages naming the key and the value.
#include <fmt/format.h>

#include "app/config/case_reader.hpp"

namespace pdmesh::case_detail {

namespace {

Vec2 read_point(const Reader& r, const std::string& key, const toml::node& n) {
  const toml::array& a = r.array(key, n);
  if (a.size() != 2) r.fail(key, &n, fmt::format("{} must be [x, y], got {} numbers", key, a.size()));
  return {r.number(key + "[0]", *a.get(0)), r.number(key + "[1]", *a.get(1))};
}

RefineRegion read_region(const Reader& r, const toml::table& t, const toml::node& table_node, std::size_t i) {
  const std::string base = fmt::format("refine[{}]", i);
  RefineRegion g;
  g.label = base;
  const auto key = [&](std::string_view k) { return fmt::format("{}.{}", base, k); };
  const auto required = [&](std::string_view k) -> const toml::node& {
    const toml::node* n = t.get(k);
    if (n == nullptr) r.fail(key(k), &table_node, fmt::format("{} is required", key(k)));
    return *n;
  };
  const toml::node& shape = required("shape");
  g.shape = choose<RegionShape>(r, key("shape"), shape,
                                {{"box", RegionShape::Box},
                                 {"disc", RegionShape::Disc},
                                 {"points", RegionShape::Points},
                                 {"polyline", RegionShape::Polyline},
                                 {"region", RegionShape::Subdomain}});
  const toml::node& size = required("size");
  g.size = r.number(key("size"), size);
  // Each shape's own keys; a key of another shape is a mistake worth naming.
  const bool boxed = g.shape == RegionShape::Box;
  const bool disc = g.shape == RegionShape::Disc;
  const bool listed = g.shape == RegionShape::Points || g.shape == RegionShape::Polyline;
  const bool subdomain = g.shape == RegionShape::Subdomain;
  for (const auto& [k, want] : {std::pair<const char*, bool>{"box", boxed},
                                {"centre", disc},
                                {"radius", !boxed && !subdomain},
                                {"points", listed},
                                {"region", subdomain},
                                {"point", subdomain}}) {
    const toml::node* n = t.get(k);
    if (n != nullptr && !want)
      r.fail(key(k), n, fmt::format("{} does not go with shape = \"{}\"", key(k), r.string(key("shape"), shape)));
  }
  const toml::node* checked = &size;
  if (subdomain) {
    // A regional attribute (a number), a region's name, or a point in the subdomain.
    const toml::node* region = t.get("region");
    const toml::node* point = t.get("point");
    if ((region == nullptr) == (point == nullptr))
      r.fail(key("region"), region != nullptr ? region : &table_node,
             fmt::format("{} takes one of region (a regional attribute or a region's name) and point ([x, y] in the "
                         "subdomain)",
                         base));
    if (region != nullptr && region->is_string()) {
      g.region_name = r.string(key("region"), *region);
      if (g.region_name.empty()) r.fail(key("region"), region, fmt::format("{} is an empty name", key("region")));
    } else if (region != nullptr) {
      g.attribute = r.number(key("region"), *region);
      if (g.size > 0.0) checked = region;
    } else {
      g.at = read_point(r, key("point"), *point);
      if (g.size > 0.0) checked = point;
    }
  } else if (boxed) {
    const toml::node& b = required("box");
    const toml::array& a = r.array(key("box"), b);
    if (a.size() != 4)
      r.fail(key("box"), &b, fmt::format("{} must be [x0, y0, x1, y1], got {} numbers", key("box"), a.size()));
    double w[4];
    for (std::size_t j = 0; j < 4; ++j) w[j] = r.number(fmt::format("{}[{}]", key("box"), j), *a.get(j));
    g.box.lo = {w[0], w[1]};
    g.box.hi = {w[2], w[3]};
    if (g.size > 0.0) checked = &b;
  } else {
    const toml::node& radius = required("radius");
    g.radius = r.number(key("radius"), radius);
    if (disc) {
      g.centre = read_point(r, key("centre"), required("centre"));
    } else {
      const toml::node& pts = required("points");
      const toml::array& a = r.array(key("points"), pts);
      for (std::size_t j = 0; j < a.size(); ++j)
        g.points.push_back(read_point(r, fmt::format("{}[{}]", key("points"), j), *a.get(j)));
      if (g.size > 0.0) checked = &pts;
    }
    if (g.size > 0.0 && !(g.radius > 0.0)) checked = &radius;
  }
  try {
    check_refine_region(g);
  } catch (const InputError& e) {
    r.fail(base, checked, e.what());
  }
  // A subdomain is found in the geometry later (spacing/refine_regions.hpp): its messages then name
  // the table's line.
  if (subdomain) g.label = fmt::format("{}: {}", r.where(base, &table_node.source()), base);
  return g;
}

}  // namespace

void read_size_sections(const Reader& r, const toml::table& root, CaseConfig& c) {
  const toml::node* size = find(root, "spacing", "size");
  if (size != nullptr) c.spacing.size = r.positive("spacing.size", *size);
  if (const toml::node* n = root.get("refine")) {
    c.spacing.regions.clear();
    if (n->is_table()) {
      c.spacing.regions.push_back(read_region(r, *n->as_table(), *n, 0));
    } else {
      const toml::array& a = r.array("refine", *n);
      for (std::size_t i = 0; i < a.size(); ++i)
        c.spacing.regions.push_back(read_region(r, *a.get(i)->as_table(), *a.get(i), i));
    }
  }
  if (const toml::node* s = find(root, "farfield", "shape")) {
    c.farfield.shape = choose<FarfieldShape>(r, "farfield.shape", *s,
                                             {{"circle", FarfieldShape::Circle}, {"box", FarfieldShape::Box}});
  }
  if (const toml::node* s = find(root, "farfield", "cavities")) {
    c.farfield.cavities = choose<FarfieldCavities>(
        r, "farfield.cavities", *s, {{"solid", FarfieldCavities::Solid}, {"mesh", FarfieldCavities::Mesh}});
  }
  const toml::node* far = find(root, "farfield", "size");
  if (far != nullptr) {
    c.farfield.size = r.positive("farfield.size", *far);
    // An option or setting names the far field itself ("--farfield circle:5"); a case file by its line.
    const std::string* option = r.override_label("farfield.size");
    c.farfield.label = option != nullptr ? *option
                                         : fmt::format("{}: farfield.size = {}",
                                                       r.where("farfield.size", &far->source()), c.farfield.size);
  }
  if (r.partial()) return;  // how the keys agree: the whole configuration decides
  if (find(root, "farfield", "shape") != nullptr && far == nullptr)
    r.fail("farfield.size", find(root, "farfield", "shape"),
           "farfield.size is required (the radius or half-width in multiples of the input's largest extent)");
  if (size != nullptr && c.spacing.field != SpacingKind::Boundary)
    r.fail("spacing.size", size,
           fmt::format("spacing.size is set but spacing.field is '{}' (a uniform size replaces eq. 3.6 only)",
                       spacing_kind_name(c.spacing.field)));
  if (!c.spacing.regions.empty() && c.spacing.metric())
    r.fail("refine", root.get("refine"),
           fmt::format("[[refine]] regions lower an isotropic field; spacing.field is '{}'",
                       spacing_kind_name(c.spacing.field)));
}

}  // namespace pdmesh::case_detail
