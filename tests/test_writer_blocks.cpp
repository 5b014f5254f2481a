// Tests of the writers' text formatted on several threads (core/text_blocks.hpp, the VTU writer's
// binary pieces): the text is the one a loop on one thread writes, byte for byte.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "core/text_blocks.hpp"
#include "io/vtu_data.hpp"
#include "io/vtu_writer.hpp"
#include "mesh/quality.hpp"
#include "mesh_fixtures.hpp"

using namespace pdmesh;

namespace {

// A line per item whose length varies with the item, so that a block appended out of place or twice
// changes the text.
void item_line(std::string& out, std::size_t i) {
  out += std::to_string(i);
  out += ':';
  out += std::string(i % 7, 'x');
  out += std::to_string(i * i % 1009);
  out += '\n';
}

// An n x n grid of the unit square, its points jittered so that no two triangles have the same shape.
Mesh jittered_grid(int n) {
  return fixtures::grid_mesh_of(n, [n](int i, int j, bool side) {
    const double jx = side ? 0.0 : 0.2 * std::sin(1.7 * i + 3.1 * j), jy = side ? 0.0 : 0.2 * std::cos(2.3 * i - j);
    return Vec2{(i + jx) / (n - 1.0), (j + jy) / (n - 1.0)};
  });
}

// The base64 line of a binary DataArray as one encoder over its header and all its values writes it.
std::string one_encoder(const std::vector<double>& values) {
  std::string out;
  Base64Encoder encoder(out);
  const std::uint64_t bytes = values.size() * sizeof(double);
  encoder.put(&bytes, sizeof bytes);
  for (const double v : values) encoder.put(&v, sizeof v);
  encoder.finish();
  return out;
}

// The text between the opening tag of the DataArray named `name` and its closing tag, trimmed.
std::string array_text(const std::string& vtu, const std::string& name) {
  const std::size_t at = vtu.find("Name=\"" + name + "\"");
  REQUIRE(at != std::string::npos);
  const std::size_t begin = vtu.find('>', at) + 1, end = vtu.find("</DataArray>", begin);
  std::string text = vtu.substr(begin, end - begin);
  const auto first = text.find_first_not_of(" \n"), last = text.find_last_not_of(" \n");
  return text.substr(first, last - first + 1);
}

}  // namespace

TEST_CASE("items formatted in blocks on several threads give the text of one loop", "[writer]") {
  // Several rounds of blocks and a part block at the end; and the small cases.
  for (const std::size_t n :
       {std::size_t{0}, std::size_t{1}, std::size_t{4097}, 2 * kTextBlocksPerRound * kTextBlockItems + 123}) {
    std::string expected;
    for (std::size_t i = 0; i < n; ++i) item_line(expected, i);
    for (const std::size_t threads : {std::size_t{1}, std::size_t{2}, std::size_t{3}}) {
      TextSink sink;
      sink.text() = "head\n";
      append_items(sink, n, item_line, threads);
      INFO("n " << n << ", threads " << threads);
      CHECK(sink.take() == "head\n" + expected);
    }
  }
}

TEST_CASE("the VTU's binary arrays, encoded in pieces on several threads, are one encoder's text", "[writer][vtu]") {
  // 160 x 160 points (614,400 bytes of Points: x, y and 0, 8 bytes each) and 50,562 triangles
  // (404,496 bytes per metric): each of these arrays is more than one of the encoder's pieces.
  const Mesh m = jittered_grid(160);
  const std::string vtu = vtu_string(m);
  std::vector<double> points;
  for (const Vec2& p : m.points) points.insert(points.end(), {p.x, p.y, 0.0});
  REQUIRE(points.size() * sizeof(double) > 393216);
  CHECK(array_text(vtu, "Points") == one_encoder(points));
  CHECK(array_text(vtu, "q") == one_encoder(m.spacing));
  // The metrics as triangle_quality gives them, one triangle after another.
  std::vector<double> min_angle, condition;
  for (const auto& t : m.triangles) {
    const TriangleQuality q = triangle_quality(m.points[t[0]], m.points[t[1]], m.points[t[2]]);
    min_angle.push_back(q.min_angle);
    condition.push_back(q.condition_number);
  }
  REQUIRE(min_angle.size() * sizeof(double) > 393216);
  CHECK(array_text(vtu, "min_angle") == one_encoder(min_angle));
  CHECK(array_text(vtu, "condition_number") == one_encoder(condition));
  // An array shorter than a piece: its header and 9 points, padded once.
  CHECK(array_text(vtu_string(jittered_grid(3)), "Points").size() == (8 + 9 * 3 * 8 + 2) / 3 * 4);
}
