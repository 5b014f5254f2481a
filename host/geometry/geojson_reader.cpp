// GeoJSON reader (geojson_reader.hpp). The text is parsed twice: once into a DOM, once through SAX
// events with a counting input iterator that records the line where every object starts, keyed by
// its JSON pointer, so that messages can name the line of the feature they are about.
#include "geometry/geojson_reader.hpp"

#include <cmath>
#include <iterator>
#include <map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "core/progress_notes.hpp"
#include "geometry/gis_features.hpp"

namespace pdmesh {

namespace {

using json = nlohmann::json;

constexpr double kLargestCoordinate = 1e150;  // as for the text readers (reader_text.cpp)

// An input iterator over the text that tells how far the parser has read.
struct CountingIterator {
  using iterator_category = std::input_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;
  const char* p = nullptr;
  const char** furthest = nullptr;
  reference operator*() const { return *p; }
  CountingIterator& operator++() {
    ++p;
    if (p > *furthest) *furthest = p;
    return *this;
  }
  CountingIterator operator++(int) {
    CountingIterator old = *this;
    ++*this;
    return old;
  }
  bool operator==(const CountingIterator& o) const { return p == o.p; }
  bool operator!=(const CountingIterator& o) const { return p != o.p; }
};

// SAX handler recording the 1-based line of every object's '{' by its JSON pointer.
class LineRecorder : public nlohmann::json_sax<json> {
 public:
  LineRecorder(const char* begin, const char** furthest) : scanned_(begin), furthest_(furthest) {}
  std::map<std::string, int> lines;

  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override {
    value();
    lines[pointer()] = line_here();
    frames_.push_back({false, 0, {}});
    return true;
  }
  bool key(string_t& k) override {
    frames_.back().key = k;
    return true;
  }
  bool end_object() override {
    frames_.pop_back();
    return true;
  }
  bool start_array(std::size_t) override {
    value();
    frames_.push_back({true, -1, {}});
    return true;
  }
  bool end_array() override {
    frames_.pop_back();
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }

 private:
  struct Frame {
    bool array = false;
    long index = -1;
    std::string key;
  };
  bool value() {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
    return true;
  }
  std::string pointer() const {
    std::string s;
    for (const Frame& f : frames_) s += "/" + (f.array ? std::to_string(f.index) : f.key);
    return s;
  }
  // The line of the '{' the parser has just read; the text is scanned once, as the parser goes.
  int line_here() {
    for (; scanned_ + 1 < *furthest_; ++scanned_) line_ += *scanned_ == '\n' ? 1 : 0;
    return line_;
  }
  const char* scanned_;
  int line_ = 1;
  const char** furthest_;
  std::vector<Frame> frames_;
};

class Walker {
 public:
  Walker(const std::string& path, std::map<std::string, int> lines) : path_(path), lines_(std::move(lines)) {}
  RawGeometry out;

  void top(const json& j) {
    if (!j.is_object()) fail("", fmt::format("the top level is {}, not a GeoJSON object", j.type_name()));
    const std::string type = type_of(j, "");
    if (type == "FeatureCollection") {
      const json& features = member(j, "", "features");
      if (!features.is_array()) fail("", "'features' is not an array");
      for (std::size_t k = 0; k < features.size(); ++k) feature(features[k], fmt::format("/features/{}", k), k);
    } else if (type == "Feature") {
      feature(j, "", 0);
    } else {
      gis::FeatureSource src{path_, line_of(""), "", "the geometry"};
      geometry(j, "", src);
    }
  }

 private:
  int line_of(const std::string& ptr) const {
    auto it = lines_.find(ptr);
    return it == lines_.end() ? 1 : it->second;
  }
  [[noreturn]] void fail(const std::string& ptr, const std::string& what) const {
    throw InputError(fmt::format("{}:{}: {}", path_, line_of(ptr), what));
  }
  const json& member(const json& j, const std::string& ptr, const char* key) const {
    auto it = j.find(key);
    if (it == j.end()) fail(ptr, fmt::format("the object has no '{}' member", key));
    return *it;
  }
  std::string type_of(const json& j, const std::string& ptr) const {
    const json& t = member(j, ptr, "type");
    if (!t.is_string()) fail(ptr, fmt::format("'type' is {}, not a string", t.type_name()));
    return t.get<std::string>();
  }

  void feature(const json& f, const std::string& ptr, std::size_t index) {
    if (!f.is_object()) fail(ptr, fmt::format("feature {} is {}, not an object", index, f.type_name()));
    const std::string type = type_of(f, ptr);
    if (type != "Feature") fail(ptr, fmt::format("feature {} has type '{}', not 'Feature'", index, quote_input(type)));
    gis::FeatureSource src{path_, line_of(ptr), "", fmt::format("feature {}", index)};
    auto props = f.find("properties");
    if (props != f.end() && props->is_object()) {
      auto name = props->find("name");
      if (name != props->end() && name->is_string() && !name->get<std::string>().empty()) {
        src.name = gis::plain_name(name->get<std::string>());
        src.what = fmt::format("feature {} ('{}')", index, quote_input(name->get<std::string>()));
      }
    }
    const json& g = member(f, ptr, "geometry");
    if (g.is_null()) {
      progress_line_note(src, "has no geometry (null); skipped");
      return;
    }
    geometry(g, ptr + "/geometry", src);
  }

  static void progress_line_note(const gis::FeatureSource& src, const std::string& text);

  Vec2 position(const json& p, const std::string& ptr, const gis::FeatureSource& src) const {
    if (!p.is_array() || p.size() < 2 || p.size() > 3 || !p[0].is_number() || !p[1].is_number() ||
        (p.size() == 3 && !p[2].is_number())) {
      fail(ptr, fmt::format("{}: a position must be an array of 2 or 3 numbers, found '{}'", src.what,
                            quote_input(p.dump())));
    }
    const Vec2 v{p[0].get<double>(), p[1].get<double>()};
    if (!(std::fabs(v.x) <= kLargestCoordinate && std::fabs(v.y) <= kLargestCoordinate)) {
      fail(ptr, fmt::format("{}: position {} is too large (|value| must be <= {:g})", src.what, quote_input(p.dump()),
                            kLargestCoordinate));
    }
    return v;
  }
  std::vector<Vec2> positions(const json& a, const std::string& ptr, const gis::FeatureSource& src) const {
    if (!a.is_array()) fail(ptr, fmt::format("{}: expected an array of positions, found {}", src.what, a.type_name()));
    std::vector<Vec2> pts;
    pts.reserve(a.size());
    for (const json& p : a) pts.push_back(position(p, ptr, src));
    return pts;
  }
  std::vector<std::vector<Vec2>> rings(const json& a, const std::string& ptr, const gis::FeatureSource& src) const {
    if (!a.is_array() || a.empty())
      fail(ptr, fmt::format("{}: a polygon needs an array of rings, found '{}'", src.what, quote_input(a.dump())));
    std::vector<std::vector<Vec2>> out;
    for (const json& r : a) out.push_back(positions(r, ptr, src));
    return out;
  }
  const json& array_member(const json& g, const std::string& ptr, const char* key, const gis::FeatureSource& src) {
    const json& a = member(g, ptr, key);
    if (!a.is_array()) fail(ptr, fmt::format("{}: '{}' is {}, not an array", src.what, key, a.type_name()));
    return a;
  }

  void geometry(const json& g, const std::string& ptr, const gis::FeatureSource& src) {
    if (!g.is_object()) fail(ptr, fmt::format("{}: the geometry is {}, not an object", src.what, g.type_name()));
    const std::string type = type_of(g, ptr);
    if (type == "GeometryCollection") {
      const json& all = array_member(g, ptr, "geometries", src);
      for (std::size_t k = 0; k < all.size(); ++k) geometry(all[k], fmt::format("{}/geometries/{}", ptr, k), src);
      return;
    }
    const bool known = type == "Point" || type == "MultiPoint" || type == "LineString" || type == "MultiLineString" ||
                       type == "Polygon" || type == "MultiPolygon";
    if (!known) {
      fail(ptr, fmt::format("{}: unknown GeoJSON geometry type '{}' (expected Point, MultiPoint, LineString, "
                            "MultiLineString, Polygon, MultiPolygon or GeometryCollection)",
                            src.what, quote_input(type)));
    }
    const json& c = member(g, ptr, "coordinates");
    if (type == "Point") {
      gis::add_point(out, src, position(c, ptr, src));
    } else if (type == "MultiPoint") {
      for (const Vec2& p : positions(c, ptr, src)) gis::add_point(out, src, p);
    } else if (type == "LineString") {
      gis::add_line(out, src, 0, positions(c, ptr, src));
    } else if (type == "MultiLineString") {
      if (!c.is_array()) fail(ptr, fmt::format("{}: expected an array of lines, found {}", src.what, c.type_name()));
      for (std::size_t k = 0; k < c.size(); ++k)
        gis::add_line(out, src, c.size() > 1 ? static_cast<int>(k + 1) : 0, positions(c[k], ptr, src));
    } else if (type == "Polygon") {
      gis::add_polygon(out, src, 0, rings(c, ptr, src));
    } else {
      if (!c.is_array()) fail(ptr, fmt::format("{}: expected an array of polygons, found {}", src.what, c.type_name()));
      for (std::size_t k = 0; k < c.size(); ++k)
        gis::add_polygon(out, src, c.size() > 1 ? static_cast<int>(k + 1) : 0, rings(c[k], ptr, src));
    }
  }

  std::string path_;
  std::map<std::string, int> lines_;
};

void Walker::progress_line_note(const gis::FeatureSource& src, const std::string& text) {
  progress_line(fmt::format("geometry: {}:{}: {} {}", src.file, src.line, src.what, text));
}

// nlohmann's message without its "[json.exception...] parse error at line L, column C: " prefix
// (the line and column are given again from the byte offset, in the file:line:column form).
std::string parser_message(const std::string& what) {
  const std::size_t at = what.find(": ", what.find("column"));
  return at == std::string::npos ? what : what.substr(at + 2);
}

}  // namespace

RawGeometry read_geojson_text(const std::string& path, const std::string& text) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::parse_error& e) {
    // e.byte: 1-based offset of the character where the parser stopped.
    const std::size_t end = std::min<std::size_t>(e.byte == 0 ? 0 : e.byte - 1, text.size());
    int line = 1;
    std::size_t line_start = 0;
    for (std::size_t k = 0; k < end; ++k) {
      if (text[k] == '\n') {
        ++line;
        line_start = k + 1;
      }
    }
    throw InputError(fmt::format("{}:{}:{}: malformed JSON: {}", path, line, end - line_start + 1,
                                 quote_input(parser_message(e.what()))));
  }
  const char* furthest = text.data();
  LineRecorder recorder(text.data(), &furthest);
  CountingIterator first{text.data(), &furthest};
  CountingIterator last{text.data() + text.size(), &furthest};
  json::sax_parse(first, last, &recorder);
  Walker walker(path, std::move(recorder.lines));
  walker.top(doc);
  gis::finish(walker.out, path, 0, 0);
  return std::move(walker.out);
}

RawGeometry read_geojson_file(const std::string& path) {
  std::string text = read_input_file(path, InputKind::Geometry);
  skip_utf8_bom(text);
  return read_geojson_text(path, text);
}

}  // namespace pdmesh
