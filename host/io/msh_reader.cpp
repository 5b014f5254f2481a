// Gmsh MSH 4.1 / 2.2 ASCII reader.
// Format: https://gmsh.info/doc/texinfo/gmsh.html#MSH-file-format (section 10.1) and
// https://gmsh.info/doc/texinfo/gmsh.html#MSH-file-format-version-2-_0028Legacy_0029.
#include "io/msh_reader.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <limits>
#include <map>
#include <set>
#include <optional>
#include <unordered_map>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "io/mixed_mesh.hpp"
#include "io/text_file.hpp"

namespace pdmesh {
namespace {

// An element as read, resolved into point indices once all nodes are known.
struct RawElement {
  long long nodes[4] = {0, 0, 0, 0};
  int line = 0;
  long long physical = 0;  // 0 = none
  long long entity = 0;
};

// A $Periodic link as read: entity tags and node tags, resolved once all nodes are known.
struct RawPeriodic {
  long long dim = 0, entity = 0, master = 0;
  bool has_affine = false;
  std::array<double, 16> affine{};
  std::vector<std::array<long long, 2>> nodes;  // (node, master node)
  int line = 0;
};

// A $NodeData block as read: node tags and their values, resolved once all nodes are known.
struct RawView {
  int components = 1;
  std::string where;  // FILE:LINE of its $NodeData
  std::vector<long long> tags;
  std::vector<double> values;  // components per entry of tags
};

struct MshData {
  bool v41 = true;
  std::map<long long, std::string> line_names;         // dim-1 physical tag -> name
  std::map<long long, long long> curve_entity_phys;    // 4.1 curve entity -> first physical tag (0 none)
  std::map<long long, std::string> surface_names;      // dim-2 physical tag -> name
  std::map<long long, long long> surface_entity_phys;  // 4.1 surface entity -> first physical tag (0 none)
  SurfaceCells* cells = nullptr;                       // quads wanted (parse_msh's `cells`)
  std::unordered_map<long long, int> node_index;       // node tag -> point index
  std::vector<Vec2> points;
  std::vector<RawElement> lines, triangles, quads;
  std::map<int, std::size_t> skipped;  // element type -> count
  std::string off_plane;               // MeshReadReport::off_plane
  std::vector<long long> node_tags;    // per point, for messages about point data
  std::vector<RawPeriodic> periodic;   // $Periodic, resolved in assemble
  // Point data: the wanted $NodeData views by name (of several blocks of a name, the last: the latest
  // time step).
  MeshPointData* data = nullptr;
  std::map<std::string, RawView> views;
};

const char* element_name(int type) {
  switch (type) {
    case 3:
      return "quadrangle";
    case 4:
      return "tetrahedron";
    case 5:
      return "hexahedron";
    case 8:
      return "3-node line";
    case 9:
      return "6-node triangle";
    case 15:
      return "point";
    default:
      return "unsupported";
  }
}

void expect_end(LineScanner& s, std::string_view section) {
  const std::string want = fmt::format("$End{}", section);
  const auto tok = s.token(want);
  if (tok != want)
    s.fail(fmt::format("expected {} (a count in this section is wrong or the file is truncated)", want), tok);
}

// A count of items that take at least `min_bytes_each` bytes each in the file; refused when that
// many cannot fit in what is left of it (before anything is allocated by it).
std::size_t count(LineScanner& s, std::string_view what, std::size_t min_bytes_each = 2) {
  const long long n = s.to_int(s.token(what), what);
  if (n < 0) s.fail(fmt::format("negative {}", what), fmt::format("{}", n));
  s.check_count(n, min_bytes_each, what);
  return static_cast<std::size_t>(n);
}

void read_format(LineScanner& s, MshData& d) {
  const auto version = s.token("MSH version");
  if (version == "4.1") {
    d.v41 = true;
  } else if (version.size() >= 2 && version.substr(0, 2) == "2.") {
    d.v41 = false;
  } else {
    s.fail("unsupported MSH version (this reader reads 4.1 and 2.x ASCII)", version);
  }
  const auto type = s.token("file type");
  if (type != "0") s.fail("binary MSH files are not supported (file type must be 0)", type);
  s.token("data size");
  expect_end(s, "MeshFormat");
}

void read_physical_names(LineScanner& s, MshData& d) {
  const std::size_t n = count(s, "number of physical names");
  for (std::size_t i = 0; i < n; ++i) {
    const long long dim = s.to_int(s.token("physical dimension"), "physical dimension");
    const long long tag = s.to_int(s.token("physical tag"), "physical tag");
    std::string_view name = s.rest_of_line();
    if (name.size() < 2 || name.front() != '"' || name.back() != '"') s.fail("expected a quoted physical name", name);
    if (dim == 1) d.line_names[tag] = std::string(name.substr(1, name.size() - 2));
    if (dim == 2) d.surface_names[tag] = std::string(name.substr(1, name.size() - 2));
  }
  expect_end(s, "PhysicalNames");
}

// 4.1 $Entities: remember the physical tag of each curve entity.
void read_entities(LineScanner& s, MshData& d) {
  std::size_t counts[4];
  for (auto& c : counts) c = count(s, "number of entities");
  for (int dim = 0; dim < 4; ++dim) {
    for (std::size_t i = 0; i < counts[dim]; ++i) {
      const long long tag = s.to_int(s.token("entity tag"), "entity tag");
      for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) s.to_double(s.token("entity coordinate"), "entity coordinate");
      const std::size_t nphys = count(s, "number of physical tags");
      long long first = 0;
      for (std::size_t k = 0; k < nphys; ++k) {
        const long long p = s.to_int(s.token("physical tag"), "physical tag");
        if (k == 0) first = p;
      }
      if (dim == 1) d.curve_entity_phys[tag] = first;
      if (dim == 2) d.surface_entity_phys[tag] = first;
      if (dim > 0) {
        const std::size_t nb = count(s, "number of bounding entities");
        for (std::size_t k = 0; k < nb; ++k) s.to_int(s.token("bounding entity tag"), "bounding entity tag");
      }
    }
  }
  expect_end(s, "Entities");
}

void add_node(LineScanner& s, MshData& d, long long tag, double x, double y) {
  if (!d.node_index.emplace(tag, static_cast<int>(d.points.size())).second) {
    s.fail("duplicate node tag", fmt::format("{}", tag));
  }
  d.points.push_back({x, y});
  d.node_tags.push_back(tag);
}

// The first node off the plane z = 0, for MeshReadReport::off_plane.
void note_off_plane(const LineScanner& s, MshData& d, long long tag, double z) {
  if (z != 0.0 && d.off_plane.empty())
    d.off_plane = fmt::format("{}:{}: node {} has z = {}", s.file(), s.line(), tag, z);
}

void read_nodes(LineScanner& s, MshData& d) {
  if (!d.v41) {
    const std::size_t n = count(s, "number of nodes", 8);  // "1 0 0 0\n"
    for (std::size_t i = 0; i < n; ++i) {
      const long long tag = s.to_int(s.token("node tag"), "node tag");
      const double x = s.to_double(s.token("x"), "x");
      const double y = s.to_double(s.token("y"), "y");
      note_off_plane(s, d, tag, s.to_double(s.token("z"), "z"));
      add_node(s, d, tag, x, y);
    }
    expect_end(s, "Nodes");
    return;
  }
  const std::size_t blocks = count(s, "number of node blocks");
  const std::size_t total = count(s, "number of nodes", 8);  // a tag, then "0 0 0\n"
  s.token("minimum node tag");
  s.token("maximum node tag");
  std::size_t seen = 0;
  std::vector<long long> tags;
  for (std::size_t b = 0; b < blocks; ++b) {
    const long long dim = s.to_index(s.token("entity dimension"), 0, 3, "entity dimension");
    s.token("entity tag");
    const long long parametric = s.to_index(s.token("parametric flag"), 0, 1, "parametric flag");
    const std::size_t n = count(s, "number of nodes in block", 8);
    tags.resize(n);
    for (auto& t : tags) t = s.to_int(s.token("node tag"), "node tag");
    const long long extra = parametric ? dim : 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double x = s.to_double(s.token("x"), "x");
      const double y = s.to_double(s.token("y"), "y");
      note_off_plane(s, d, tags[i], s.to_double(s.token("z"), "z"));
      for (long long k = 0; k < extra; ++k) s.to_double(s.token("parametric coordinate"), "parametric coordinate");
      add_node(s, d, tags[i], x, y);
    }
    seen += n;
  }
  if (seen != total) s.fail(fmt::format("the node blocks hold {} nodes but the header says {}", seen, total));
  expect_end(s, "Nodes");
}

// One element: `nodes` is the rest of its line; type 1 and 2 are kept (and 3 when quads are wanted),
// the rest counted.
void add_element(LineScanner& s, MshData& d, int type, std::string_view nodes, long long physical, long long entity) {
  const std::size_t need = type == 1 ? 2 : type == 2 ? 3 : type == 3 && d.cells != nullptr ? 4 : 0;
  if (need == 0) {
    d.skipped[type]++;
    return;
  }
  const auto toks = split_tokens(nodes);
  if (toks.size() != need) {
    s.fail(fmt::format("element of type {} needs {} node tags, found {}", type, need, toks.size()), nodes);
  }
  RawElement e;
  e.line = s.line();
  e.physical = physical;
  e.entity = entity;
  for (std::size_t k = 0; k < need; ++k) e.nodes[k] = s.to_int(toks[k], "node tag");
  (type == 1 ? d.lines : type == 2 ? d.triangles : d.quads).push_back(e);
}

void read_elements(LineScanner& s, MshData& d) {
  if (!d.v41) {
    const std::size_t n = count(s, "number of elements", 8);  // "1 15 0 1\n"
    for (std::size_t i = 0; i < n; ++i) {
      s.to_int(s.token("element tag"), "element tag");
      const std::string_view rest = s.rest_of_line();
      const auto toks = split_tokens(rest);
      if (toks.size() < 2) s.fail("expected element type and number of tags", rest);
      const auto type = static_cast<int>(s.to_int(toks[0], "element type"));
      const long long ntags = s.to_int(toks[1], "number of tags");
      if (ntags < 0 || static_cast<std::size_t>(ntags) + 2 > toks.size()) s.fail("bad number of element tags", rest);
      const long long physical = ntags > 0 ? s.to_int(toks[2], "physical tag") : 0;
      const long long entity = ntags > 1 ? s.to_int(toks[3], "elementary tag") : 0;
      const std::size_t skip = static_cast<std::size_t>(ntags) + 2;
      // The node tags are the rest of the line after the type, count and tags.
      const std::string_view nodes = toks.size() > skip
                                         ? rest.substr(static_cast<std::size_t>(toks[skip].data() - rest.data()))
                                         : std::string_view();
      add_element(s, d, type, nodes, physical, entity);
    }
    expect_end(s, "Elements");
    return;
  }
  const std::size_t blocks = count(s, "number of element blocks");
  const std::size_t total = count(s, "number of elements", 4);  // "1 1\n"
  s.token("minimum element tag");
  s.token("maximum element tag");
  std::size_t seen = 0;
  for (std::size_t b = 0; b < blocks; ++b) {
    const long long dim = s.to_index(s.token("entity dimension"), 0, 3, "entity dimension");
    const long long entity = s.to_int(s.token("entity tag"), "entity tag");
    const auto type = static_cast<int>(s.to_int(s.token("element type"), "element type"));
    const std::size_t n = count(s, "number of elements in block", 4);
    long long physical = 0;
    if (dim == 1 || dim == 2) {
      const auto& phys = dim == 1 ? d.curve_entity_phys : d.surface_entity_phys;
      const auto it = phys.find(entity);
      physical = it == phys.end() ? 0 : it->second;
    }
    for (std::size_t i = 0; i < n; ++i) {
      s.to_int(s.token("element tag"), "element tag");
      add_element(s, d, type, s.rest_of_line(), physical, entity);
    }
    seen += n;
  }
  if (seen != total) s.fail(fmt::format("the element blocks hold {} elements but the header says {}", seen, total));
  expect_end(s, "Elements");
}

// The string tags of a $NodeData / $ElementData / $ElementNodeData section (the first is the view's
// name), then its real and integer tags. Leaves the scanner before the first value line.
struct DataHeader {
  std::string name;
  std::vector<long long> ints;  // time step, components, number of values, [partition]
};

DataHeader read_data_header(LineScanner& s, std::string_view section) {
  DataHeader h;
  const std::size_t strings = count(s, "number of string tags");
  for (std::size_t i = 0; i < strings; ++i) {
    std::string_view tag = s.expect_line("a string tag");
    tag = tag.substr(tag.find_first_not_of(" \t"));
    if (tag.size() >= 2 && tag.front() == '"' && tag.back() == '"') tag = tag.substr(1, tag.size() - 2);
    if (i == 0) h.name = std::string(tag);
  }
  const std::size_t reals = count(s, "number of real tags");
  for (std::size_t i = 0; i < reals; ++i) s.to_double(s.token("real tag"), "real tag");
  const std::size_t ints = count(s, "number of integer tags");
  for (std::size_t i = 0; i < ints; ++i) h.ints.push_back(s.to_int(s.token("integer tag"), "integer tag"));
  if (h.ints.size() < 3) {
    s.fail(fmt::format("{} needs 3 integer tags (time step, number of components, number of values)", section),
           fmt::format("{} integer tags", h.ints.size()));
  }
  // Gmsh writes 1, 3 or 9 components (scalar, vector, tensor).
  if (h.ints[1] < 1 || h.ints[1] > 9 || h.ints[2] < 0) {
    s.fail(fmt::format("bad {} integer tags (components must be 1 to 9, values >= 0)", section),
           fmt::format("{} {}", h.ints[1], h.ints[2]));
  }
  return h;
}

void skip_to_end(LineScanner& s, std::string_view section) {
  const std::string end = fmt::format("$End{}", section.substr(1));
  std::string_view line;
  while (s.next_line(line)) {
    const auto toks = split_tokens(line);
    if (!toks.empty() && toks[0] == end) return;
  }
  s.fail(fmt::format("unexpected end of file, expected {}", end));
}

// $NodeData: lines "nodeTag value..." after the tags. Values may be NaN or infinite here: the
// caller decides what a valid value is and names the node.
void read_node_data(LineScanner& s, MshData& d) {
  const int line = s.line();
  const DataHeader h = read_data_header(s, "$NodeData");
  if (std::find(d.data->point_arrays.begin(), d.data->point_arrays.end(), h.name) == d.data->point_arrays.end()) {
    d.data->point_arrays.push_back(h.name);
  }
  if (h.name != d.data->wanted && !d.data->decodes(h.name)) {
    skip_to_end(s, "$NodeData");
    return;
  }
  RawView& v = d.views[h.name];
  v.components = static_cast<int>(h.ints[1]);
  v.where = fmt::format("{}:{}", s.file(), line);
  v.tags.clear();
  v.values.clear();
  s.check_count(h.ints[2], 2 + 2 * static_cast<std::size_t>(v.components), "number of values");
  for (long long i = 0; i < h.ints[2]; ++i) {
    v.tags.push_back(s.to_int(s.token("node tag"), "node tag"));
    for (int c = 0; c < v.components; ++c) {
      const std::string_view tok = s.token("node value");
      double x = 0.0;
      const auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), x);
      if (ec != std::errc() || p != tok.data() + tok.size())
        s.fail(fmt::format("expected a number as node value of $NodeData '{}'", quote_input(h.name)), tok);
      v.values.push_back(x);
    }
  }
  expect_end(s, "NodeData");
}

// View `name` (read_node_data's) as values per point: NaN, and `given` 0, at the points it skips.
PointDataArray view_values(const MshData& d, const std::string& name) {
  const RawView& v = d.views.at(name);
  PointDataArray a;
  a.name = name;
  a.components = v.components;
  a.where = v.where;
  const std::size_t n = d.points.size();
  const auto nc = static_cast<std::size_t>(v.components);
  a.values.assign(n * nc, std::numeric_limits<double>::quiet_NaN());
  a.given.assign(n, 0);
  for (std::size_t i = 0; i < v.tags.size(); ++i) {
    const auto it = d.node_index.find(v.tags[i]);
    if (it == d.node_index.end()) {
      throw InputError(fmt::format("{}: $NodeData '{}' gives a value for node {}, which is not in $Nodes", a.where,
                                   quote_input(a.name), v.tags[i]));
    }
    const auto p = static_cast<std::size_t>(it->second);
    std::copy_n(v.values.begin() + static_cast<long>(i * nc), nc, a.values.begin() + static_cast<long>(p * nc));
    a.given[p] = 1;
  }
  if (std::all_of(a.given.begin(), a.given.end(), [](std::uint8_t g) { return g != 0; })) a.given.clear();
  return a;
}

void assemble_point_data(MshData& d) {
  MeshPointData& out = *d.data;
  out.point_ids = d.node_tags;
  if (d.views.count(out.wanted) != 0) out.array = view_values(d, out.wanted);
  for (const std::string& name : out.point_arrays)
    if (out.decodes(name)) out.arrays.push_back(view_values(d, name));
}

// $Periodic: per link the dimension, the entity and its master, the affine transform (4.1: a count
// and that many values; 2.2: an optional line "Affine" and 16 values), the node pairs.
void read_periodic(LineScanner& s, MshData& d) {
  const std::size_t n = count(s, "number of periodic links", 8);
  for (std::size_t k = 0; k < n; ++k) {
    RawPeriodic p;
    p.line = s.line() + 1;
    p.dim = s.to_index(s.token("periodic entity dimension"), 0, 3, "periodic entity dimension");
    p.entity = s.to_int(s.token("periodic entity tag"), "periodic entity tag");
    p.master = s.to_int(s.token("periodic master entity tag"), "periodic master entity tag");
    std::string_view next = s.token("periodic affine transform or node count");
    std::size_t values = 0;
    if (d.v41) {
      values = static_cast<std::size_t>(s.to_index(next, 0, 16, "number of affine values"));
      next = {};
    } else if (next == "Affine") {
      values = 16;
      next = {};
    }
    if (values != 0 && values != 16) s.fail("an affine transform has 16 values", fmt::format("{}", values));
    for (std::size_t j = 0; j < values; ++j)
      p.affine[j] = s.to_double(s.token("affine transform value"), "affine transform value");
    p.has_affine = values == 16;
    const long long pairs =
        s.to_int(next.empty() ? s.token("number of periodic nodes") : next, "number of periodic nodes");
    if (pairs < 0) s.fail("negative number of periodic nodes", fmt::format("{}", pairs));
    s.check_count(pairs, 4, "number of periodic nodes");
    p.nodes.resize(static_cast<std::size_t>(pairs));
    for (auto& [node, master] : p.nodes) {
      node = s.to_int(s.token("periodic node tag"), "periodic node tag");
      master = s.to_int(s.token("periodic master node tag"), "periodic master node tag");
    }
    d.periodic.push_back(std::move(p));
  }
  expect_end(s, "Periodic");
}

int resolve(const MshData& d, const std::string& file, const RawElement& e, long long tag) {
  const auto it = d.node_index.find(tag);
  if (it == d.node_index.end())
    throw InputError(fmt::format("{}:{}: element refers to unknown node tag {}", file, e.line, tag));
  return it->second;
}

// The quads and the region flags of parse_msh's `cells`.
void assemble_cells(const std::string& file, const MshData& d, const Mesh& mesh, MeshReadReport& report) {
  SurfaceCells& out = *d.cells;
  long long region = 0;
  for (const auto& [tag, name] : d.surface_names)
    if (name == out.region && region == 0) region = tag;
  out.region_found = region != 0;
  const auto in_region = [&](const RawElement& e) { return std::uint8_t(region != 0 && e.physical == region); };
  out.triangle_in_region.clear();
  for (const auto& e : d.triangles) out.triangle_in_region.push_back(in_region(e));
  out.quads.clear();
  out.quad_in_region.clear();
  for (const auto& e : d.quads) {
    std::array<int, 4> q{};
    for (int k = 0; k < 4; ++k) q[static_cast<std::size_t>(k)] = resolve(d, file, e, e.nodes[k]);
    out.quads.push_back(q);
    out.quad_in_region.push_back(in_region(e));
  }
  orient_quads_ccw(mesh.points, out.quads, file, report);
}

// Per triangle, its region's attribute (Mesh::region), from its 2-D physical group: a group named
// "region_<a>" (the writer's names) gives a, any other group its tag, none 0; a group with another
// name (not the writer's "domain") is a named region, its name in `names`. Empty when the triangles
// lie in one group that names no region (the writer's "domain", an unnamed Gmsh surface) or in none.
// A layered run's group named boundary_layer is the layer's (its cells are SurfaceCells'): the other
// groups decide as above whether there are regions (a layered file without them has none); where
// there are, the layer's triangles are one more region, attribute its tag, named boundary_layer.
std::vector<double> triangle_regions(const MshData& d, std::vector<RegionName>& names) {
  std::map<long long, double> attribute;  // physical tag -> attribute
  std::map<double, std::string> named;    // attribute -> a user's name
  std::set<long long> layer;              // the layer group's tag
  bool named_region = false;
  for (const auto& e : d.triangles) {
    if (attribute.count(e.physical) != 0 || layer.count(e.physical) != 0) continue;
    const auto name = d.surface_names.find(e.physical);
    if (name != d.surface_names.end() && name->second == kLayerRegion) {
      layer.insert(e.physical);
      continue;
    }
    const std::optional<double> a =
        name != d.surface_names.end() ? region_attribute(name->second) : std::optional<double>();
    const bool user_name =
        e.physical != 0 && !a && name != d.surface_names.end() && !name->second.empty() && name->second != kCoreRegion;
    named_region = named_region || a.has_value() || user_name;
    attribute[e.physical] = a ? *a : static_cast<double>(e.physical);
    if (user_name) named[attribute[e.physical]] = name->second;
  }
  if (attribute.size() < 2 && !named_region) return {};
  for (const long long tag : layer) {
    attribute[tag] = static_cast<double>(tag);
    named[static_cast<double>(tag)] = kLayerRegion;
  }
  for (const auto& [a, name] : named) names.push_back({a, name});
  std::vector<double> region;
  region.reserve(d.triangles.size());
  for (const auto& e : d.triangles) region.push_back(attribute[e.physical]);
  return region;
}

Mesh assemble(const std::string& file, MshData& d, MeshReadReport& report) {
  Mesh mesh;
  mesh.points = std::move(d.points);
  // Curve keys: physical groups first (named ones, then unnamed ones in use), then entities.
  std::map<std::pair<int, long long>, int> curve_of;  // (0 physical / 1 entity, tag) -> curve index
  for (const auto& [tag, name] : d.line_names) {
    curve_of[{0, tag}] = 0;
  }
  for (const auto& e : d.lines)
    curve_of[e.physical > 0 ? std::pair<int, long long>{0, e.physical} : std::pair<int, long long>{1, e.entity}] = 0;
  for (auto& [key, index] : curve_of) {
    index = static_cast<int>(mesh.curve_names.size());
    const auto named = key.first == 0 ? d.line_names.find(key.second) : d.line_names.end();
    mesh.curve_names.push_back(named != d.line_names.end() ? named->second
                               : key.first == 0            ? fmt::format("physical{}", key.second)
                                                           : fmt::format("entity{}", key.second));
    // A physical group keeps its tag: a solver's input refers to the group by it.
    if (key.first == 0 && key.second > 0) mesh.curve_groups.push_back({key.second, mesh.curve_names.back(), {index}});
  }
  for (const auto& e : d.lines) {
    const int c =
        curve_of[e.physical > 0 ? std::pair<int, long long>{0, e.physical} : std::pair<int, long long>{1, e.entity}];
    mesh.boundary_edges.push_back({resolve(d, file, e, e.nodes[0]), resolve(d, file, e, e.nodes[1]), c});
  }
  for (const auto& e : d.triangles) {
    mesh.triangles.push_back(
        {resolve(d, file, e, e.nodes[0]), resolve(d, file, e, e.nodes[1]), resolve(d, file, e, e.nodes[2])});
  }
  mesh.region = triangle_regions(d, mesh.region_names);
  // $Periodic: the curves' links, their entities resolved as the lines' (physical group, else entity).
  std::map<long long, long long> entity_phys;  // curve entity -> the physical tag of its lines
  for (const auto& e : d.lines) entity_phys.emplace(e.entity, e.physical);
  const auto curve_of_entity = [&](long long entity) {
    const auto it = entity_phys.find(entity);
    const auto key = it != entity_phys.end() && it->second > 0 ? std::pair<int, long long>{0, it->second}
                                                               : std::pair<int, long long>{1, entity};
    const auto c = curve_of.find(key);
    return c == curve_of.end() ? -1 : c->second;
  };
  std::size_t other_links = 0;
  for (const RawPeriodic& p : d.periodic) {
    if (p.dim != 1) {
      ++other_links;
      continue;
    }
    PeriodicLink link;
    link.curve = curve_of_entity(p.entity);
    link.source_curve = curve_of_entity(p.master);
    if (link.curve < 0 || link.source_curve < 0)
      throw InputError(fmt::format("{}:{}: $Periodic links curve entity {} to {}, one of which has no line elements",
                                   file, p.line, p.entity, p.master));
    link.affine = p.affine;
    link.max_mismatch = p.has_affine ? 0.0 : std::numeric_limits<double>::quiet_NaN();
    for (const auto& [node, master] : p.nodes) {
      const auto i = d.node_index.find(node), m = d.node_index.find(master);
      if (i == d.node_index.end() || m == d.node_index.end())
        throw InputError(fmt::format("{}:{}: $Periodic refers to unknown node tag {}", file, p.line,
                                     i == d.node_index.end() ? node : master));
      link.nodes.push_back({i->second, m->second});
      if (!p.has_affine) continue;
      const Vec2 q = mesh.points[static_cast<std::size_t>(m->second)];
      const Vec2 mapped{p.affine[0] * q.x + p.affine[1] * q.y + p.affine[3],
                        p.affine[4] * q.x + p.affine[5] * q.y + p.affine[7]};
      link.max_mismatch = std::max(link.max_mismatch, dist(mapped, mesh.points[static_cast<std::size_t>(i->second)]));
    }
    report.periodic.push_back(std::move(link));
  }
  if (other_links > 0)
    report.notes.push_back(fmt::format("{}: skipped {} $Periodic links of points or surfaces", file, other_links));
  for (const auto& [type, n] : d.skipped) {
    report.skipped_elements += n;
    report.notes.push_back(fmt::format("{}: skipped {} elements of type {} ({})", file, n, type, element_name(type)));
  }
  report.off_plane = std::move(d.off_plane);
  orient_triangles_ccw(mesh, report);
  if (d.cells != nullptr) assemble_cells(file, d, mesh, report);
  return mesh;
}

}  // namespace

Mesh parse_msh(const std::string& file_label, std::string content, MeshReadReport& report, MeshPointData* data,
               SurfaceCells* cells) {
  LineScanner s(file_label, std::move(content));
  MshData d;
  d.data = data;
  d.cells = cells;
  const auto first = s.token("$MeshFormat");
  if (first != "$MeshFormat") s.fail("an MSH file starts with $MeshFormat", first);
  read_format(s, d);
  std::string_view line;
  while (s.next_line(line)) {
    const auto toks = split_tokens(line);
    if (toks.empty()) continue;
    const std::string_view section = toks[0];
    if (section == "$PhysicalNames") {
      read_physical_names(s, d);
    } else if (section == "$Entities" && d.v41) {
      read_entities(s, d);
    } else if (section == "$Nodes") {
      read_nodes(s, d);
    } else if (section == "$Elements") {
      read_elements(s, d);
    } else if (section == "$Periodic") {
      read_periodic(s, d);
    } else if (section == "$NodeData" && d.data != nullptr) {
      read_node_data(s, d);
    } else if ((section == "$ElementData" || section == "$ElementNodeData") && d.data != nullptr) {
      const DataHeader h = read_data_header(s, section);
      d.data->other_arrays.push_back(fmt::format("{} ({})", quote_input(h.name),
                                                 section == "$ElementData" ? "element data" : "element node data"));
      skip_to_end(s, section);
    } else if (!section.empty() && section[0] == '$') {
      // A section we do not use ($PartitionedEntities, $NodeData, ...): skip to its end marker.
      const std::string end = fmt::format("$End{}", section.substr(1));
      std::string_view skip;
      bool closed = false;
      while (!closed && s.next_line(skip)) closed = !split_tokens(skip).empty() && split_tokens(skip)[0] == end;
      if (!closed) s.fail(fmt::format("unexpected end of file, expected {}", end));
    } else {
      s.fail("expected a section header starting with '$'", line);
    }
  }
  if (data != nullptr) assemble_point_data(d);
  return assemble(file_label, d, report);
}

Mesh read_msh(const std::filesystem::path& path, MeshReadReport& report, MeshPointData* data, SurfaceCells* cells) {
  return parse_msh(path.string(), read_text_file(path, InputKind::Mesh), report, data, cells);
}

}  // namespace pdmesh
