// Quality metrics against closed forms (thesis appendix), invariances, a hand-summarised
// two-triangle mesh, percentiles, the table and the JSON document.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "app/cli/quality_command.hpp"
#include "core/errors.hpp"
#include "io/mesh_formats.hpp"
#include "io/text_file.hpp"
#include "mesh/quality.hpp"
#include "mesh/quality_sum.hpp"
#include "io/quality_report.hpp"
#include "seeded_random.hpp"
#include "temp_files.hpp"

using namespace pdmesh;

namespace {

const double kSqrt2 = std::sqrt(2.0);
const double kSqrt3 = std::sqrt(3.0);

using pdmesh_test::unit;

// Closed form of K_W derived by hand: with W^-1 = [[1, -1/sqrt3], [0, 2/sqrt3]],
// ||A W^-1||^2 = (2/3)(l1^2 + l2^2 + l3^2) and |det(A W^-1)| = 4 area / sqrt3; for 2x2 M,
// ||M|| ||M^-1|| = ||M||^2 / |det M|, so K_W = (l1^2 + l2^2 + l3^2) / (4 sqrt3 area).
double k_closed_form(Vec2 a, Vec2 b, Vec2 c) {
  const double area = 0.5 * std::fabs(cross(b - a, c - a));
  return (norm2(b - a) + norm2(c - b) + norm2(a - c)) / (4.0 * kSqrt3 * area);
}

void check_same(const TriangleQuality& p, const TriangleQuality& q) {
  CHECK(p.min_angle == Approx(q.min_angle).epsilon(1e-9));
  CHECK(p.max_angle == Approx(q.max_angle).epsilon(1e-9));
  CHECK(p.aspect_ratio == Approx(q.aspect_ratio).epsilon(1e-9));
  CHECK(p.skewness == Approx(q.skewness).epsilon(1e-9));
  CHECK(p.condition_number == Approx(q.condition_number).epsilon(1e-9));
  CHECK(p.min_jacobian == Approx(q.min_jacobian).epsilon(1e-9).margin(1e-12));
}

// Equilateral triangle A B C above unit edge AB and right isosceles A D B below it
// (right angle at D, legs sqrt(1/2)); both counter-clockwise.
Mesh two_triangle_mesh() {
  Mesh m;
  m.points = {{0.0, 0.0}, {1.0, 0.0}, {0.5, kSqrt3 / 2.0}, {0.5, -0.5}};
  m.triangles = {{0, 1, 2}, {0, 3, 1}};
  return m;
}

}  // namespace

TEST_CASE("equilateral triangle has the ideal values", "[quality]") {
  const auto t = triangle_quality({0, 0}, {2, 0}, {1, kSqrt3});
  CHECK(t.min_angle == Approx(60.0));
  CHECK(t.max_angle == Approx(60.0));
  CHECK(t.aspect_ratio == Approx(1.0));
  CHECK(t.skewness == Approx(1.0));
  CHECK(t.condition_number == Approx(1.0));
  CHECK(t.min_jacobian == Approx(kSqrt3 / 2.0));
}

TEST_CASE("right isosceles triangle matches hand-computed values", "[quality]") {
  // Legs 1, hypotenuse sqrt2, area 1/2, half perimeter s = (2 + sqrt2)/2.
  // R = hypotenuse / 2 = sqrt2/2; r = area / s = 1/(2 + sqrt2) = (2 - sqrt2)/2;
  // R / (2r) = (sqrt2/2) / (2 - sqrt2) = (1 + sqrt2)/2 ~ 1.2071.
  // Skewness = sqrt2 / 1. K_W = (1 + 1 + 2) / (4 sqrt3 * 1/2) = 2/sqrt3 ~ 1.1547.
  // Corner Jacobians: sin 90 = 1 and sin 45 = sqrt2/2 twice, so the minimum is sqrt2/2.
  const auto t = triangle_quality({0, 0}, {1, 0}, {0, 1});
  CHECK(t.min_angle == Approx(45.0));
  CHECK(t.max_angle == Approx(90.0));
  CHECK(t.aspect_ratio == Approx((1.0 + kSqrt2) / 2.0));
  CHECK(t.skewness == Approx(kSqrt2));
  CHECK(t.condition_number == Approx(2.0 / kSqrt3));
  CHECK(t.min_jacobian == Approx(kSqrt2 / 2.0));
  CHECK(corner_jacobian({0, 0}, {1, 0}, {0, 1}) == Approx(1.0));
}

TEST_CASE("clockwise triangle has negative Jacobian, degenerate one infinite ratios", "[quality]") {
  const auto cw = triangle_quality({0, 0}, {0, 1}, {1, 0});
  CHECK(cw.min_jacobian == Approx(-1.0));
  CHECK(cw.aspect_ratio == Approx((1.0 + kSqrt2) / 2.0));
  const auto flat = triangle_quality({0, 0}, {1, 0}, {2, 0});
  CHECK(std::isinf(flat.aspect_ratio));
  CHECK(std::isinf(flat.condition_number));
  CHECK(flat.min_angle == 0.0);
  CHECK(flat.max_angle == Approx(180.0));
  CHECK(flat.skewness == Approx(2.0));
}

TEST_CASE("weighted condition number is vertex independent and matches its closed form", "[quality]") {
  std::mt19937_64 rng(42);
  int tested = 0;
  for (int i = 0; i < 200; ++i) {
    const Vec2 a{unit(rng), unit(rng)}, b{unit(rng), unit(rng)}, c{unit(rng), unit(rng)};
    if (std::fabs(cross(b - a, c - a)) < 1e-3) continue;
    const double k = weighted_condition_number(a, b, c);
    CHECK(k >= 1.0 - 1e-12);
    CHECK(weighted_condition_number(b, c, a) == Approx(k).epsilon(1e-10));
    CHECK(weighted_condition_number(c, a, b) == Approx(k).epsilon(1e-10));
    CHECK(weighted_condition_number(a, c, b) == Approx(k).epsilon(1e-10));
    CHECK(k == Approx(k_closed_form(a, b, c)).epsilon(1e-10));
    ++tested;
  }
  CHECK(tested > 150);
}

TEST_CASE("metrics are invariant under rotation, scaling, translation and cyclic order", "[quality]") {
  std::mt19937_64 rng(7);
  for (int i = 0; i < 100; ++i) {
    Vec2 a{unit(rng), unit(rng)}, b{unit(rng), unit(rng)}, c{unit(rng), unit(rng)};
    if (std::fabs(cross(b - a, c - a)) < 1e-3) continue;
    if (cross(b - a, c - a) < 0) std::swap(b, c);
    const auto ref = triangle_quality(a, b, c);
    CHECK(ref.aspect_ratio >= 1.0 - 1e-12);
    CHECK(ref.skewness >= 1.0);
    CHECK(ref.min_jacobian > 0.0);
    CHECK(ref.min_angle <= 60.0 + 1e-9);
    check_same(triangle_quality(b, c, a), ref);
    check_same(triangle_quality(c, a, b), ref);
    const double th = 2.0 * 3.14159265358979 * unit(rng), s = 0.001 + 1000.0 * unit(rng);
    const Vec2 shift{unit(rng) * 100.0 - 50.0, unit(rng) * 100.0 - 50.0};
    auto map = [&](Vec2 p) {
      return Vec2{s * (std::cos(th) * p.x - std::sin(th) * p.y), s * (std::sin(th) * p.x + std::cos(th) * p.y)} + shift;
    };
    check_same(triangle_quality(map(a), map(b), map(c)), ref);
  }
}

TEST_CASE("triangle_shape gives triangle_quality's smallest angle and aspect ratio bit for bit", "[quality]") {
  std::mt19937_64 rng(11);
  int compared = 0;
  for (int i = 0; i < 1000; ++i) {
    const Vec2 a{unit(rng), unit(rng)}, b{unit(rng), unit(rng)}, c{unit(rng), unit(rng)};
    const TriangleQuality full = triangle_quality(a, b, c);
    const TriangleShape lean = triangle_shape(a, b, c);
    CHECK(lean.min_angle == full.min_angle);
    CHECK(lean.aspect_ratio == full.aspect_ratio);
    ++compared;
  }
  // Degenerate: the same infinite aspect ratio.
  const TriangleShape flat = triangle_shape({0.0, 0.0}, {1.0, 0.0}, {2.0, 0.0});
  CHECK(std::isinf(flat.aspect_ratio));
  CHECK(flat.aspect_ratio == triangle_quality({0.0, 0.0}, {1.0, 0.0}, {2.0, 0.0}).aspect_ratio);
  CHECK(compared == 1000);
}

TEST_CASE("two-triangle mesh summary matches hand values", "[quality]") {
  const Mesh m = two_triangle_mesh();
  const auto s = summarize_quality(m);
  CHECK(s.triangles == 2);
  CHECK(s.points == 4);
  CHECK(s.min_angle == Approx(45.0));
  CHECK(s.max_angle == Approx(90.0));
  const double ar_right = (1.0 + kSqrt2) / 2.0, k_right = 2.0 / kSqrt3;
  CHECK(s.aspect_ratio_avg == Approx((1.0 + ar_right) / 2.0));
  CHECK(s.aspect_ratio_max == Approx(ar_right));
  CHECK(s.skewness_avg == Approx((1.0 + kSqrt2) / 2.0));
  CHECK(s.skewness_max == Approx(kSqrt2));
  CHECK(s.condition_number_avg == Approx((1.0 + k_right) / 2.0));
  CHECK(s.condition_number_max == Approx(k_right));
  CHECK(s.min_jacobian == Approx(kSqrt2 / 2.0));
  CHECK(s.small_angle_triangles == 0);
  CHECK(s.small_angle_share == 0.0);
  CHECK_FALSE(s.has_spacing);
  // Min angles 60 (last 5-degree bin, [55,60)) and 45 (bin [45,50) = index 9).
  REQUIRE(s.min_angle_histogram.counts.size() == 12);
  CHECK(s.min_angle_histogram.counts[11] == 1);
  CHECK(s.min_angle_histogram.counts[9] == 1);
  CHECK(s.min_angle_histogram.overflow == 0);
  // Aspect ratios 1 (bin [1.0,1.1)) and 1.2071 (bin [1.2,1.3)).
  REQUIRE(s.aspect_ratio_histogram.counts.size() == 10);
  CHECK(s.aspect_ratio_histogram.counts[0] == 1);
  CHECK(s.aspect_ratio_histogram.counts[2] == 1);
}

TEST_CASE("small-angle share counts triangles below the threshold", "[quality]") {
  Mesh m = two_triangle_mesh();
  m.points.push_back({3.0, 0.2});  // thin triangle B, E, C-ish: min angle well below 30
  m.triangles.push_back({1, 4, 2});
  const auto s = summarize_quality(m);
  CHECK(s.small_angle_triangles == 1);
  CHECK(s.small_angle_share == Approx(1.0 / 3.0));
  CHECK(s.min_angle < 30.0);
}

TEST_CASE("spacing conformance uses every unique edge once at its midpoint", "[quality]") {
  const Mesh m = two_triangle_mesh();
  // Unique edges: AB, BC, CA (length 1) and AD, DB (length sqrt(1/2)).
  // q = 1 below y = 0 (midpoints of AD and DB), 2 elsewhere (AB's midpoint has y = 0).
  const auto s = summarize_quality(m, [](Vec2 p) { return p.y < 0.0 ? 1.0 : 2.0; });
  REQUIRE(s.has_spacing);
  const double h = kSqrt2 / 2.0;  // ratios {h, h, 0.5, 0.5, 0.5}
  CHECK(s.spacing.edges == 5);
  const double mean = (2.0 * h + 1.5) / 5.0;
  CHECK(s.spacing.mean == Approx(mean));
  const double var = (2.0 * (h - mean) * (h - mean) + 3.0 * (0.5 - mean) * (0.5 - mean)) / 5.0;
  CHECK(s.spacing.stddev == Approx(std::sqrt(var)));
  // Sorted {0.5, 0.5, 0.5, h, h}: P05 at position 0.2 -> 0.5; P95 at position 3.8 -> h.
  CHECK(s.spacing.p05 == Approx(0.5));
  CHECK(s.spacing.p95 == Approx(h));
  CHECK(s.spacing.min == Approx(0.5));
  CHECK(s.spacing.max == Approx(h));
  CHECK_THROWS_AS(summarize_quality(m, [](Vec2) { return 0.0; }), InputError);
}

TEST_CASE("percentiles interpolate between closest ranks", "[quality]") {
  const std::vector<double> v = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
  CHECK(percentile_sorted(v, 0.05) == Approx(1.5));   // position 0.5
  CHECK(percentile_sorted(v, 0.95) == Approx(10.5));  // position 9.5
  CHECK(percentile_sorted(v, 0.5) == Approx(6.0));
  CHECK(percentile_sorted(v, 0.0) == 1.0);
  CHECK(percentile_sorted(v, 1.0) == 11.0);
  CHECK(percentile_sorted({4.0}, 0.95) == 4.0);
  CHECK(percentile_sorted({0.0, 10.0}, 0.05) == Approx(0.5));
}

TEST_CASE("empty mesh gives an empty summary", "[quality]") {
  const auto s = summarize_quality(Mesh{});
  CHECK(s.triangles == 0);
  CHECK(s.aspect_ratio_avg == 0.0);
  CHECK_FALSE(format_quality_table(s).empty());
}

TEST_CASE("triangle referring to a missing point is an input error", "[quality]") {
  Mesh m = two_triangle_mesh();
  m.triangles.push_back({0, 1, 9});
  CHECK_THROWS_AS(summarize_quality(m), InputError);
}

TEST_CASE("quality table has the thesis rows with thesis precision", "[quality]") {
  const auto s = summarize_quality(two_triangle_mesh(), [](Vec2) { return 1.0; });
  const std::string t = format_quality_table({{"JP Str", s}, {"other", s}});
  for (const char* row : {"Number of Triangles", "Included Angle", "(degrees)", "Aspect ratio", "Skewness",
                          "Weighted Condition Number", "Minimum Corner Jacobian", "Min angle < 30 deg",
                          "Edge length / q(midpoint)", "Min angle histogram", "JP Str"}) {
    INFO(row);
    CHECK(t.find(row) != std::string::npos);
  }
  CHECK(t.find("45.00") != std::string::npos);  // angle MIN, 2 decimals
  CHECK(t.find("90.00") != std::string::npos);  // angle MAX
  CHECK(t.find("1.207") != std::string::npos);  // aspect ratio MAX, 3 decimals
  CHECK(t.find("1.414") != std::string::npos);  // skewness MAX
  CHECK(t.find("0.707") != std::string::npos);  // minimum corner Jacobian
}

TEST_CASE("json strings are escaped", "[quality]") {
  CHECK(json_string("a\"b\\c\n\x01") == "\"a\\\"b\\\\c\\n\\u0001\"");
  CHECK(json_string("plain é") == "\"plain é\"");
}

TEST_CASE("quality.json holds the documented keys and is written atomically", "[quality]") {
  Mesh m = two_triangle_mesh();
  m.points.push_back({2.0, 0.0});
  m.triangles.push_back({1, 4, 4});  // degenerate: non-finite maxima become null
  const auto s = summarize_quality(m, [](Vec2) { return 1.0; });
  const auto dir = pdmesh_test::fresh_path("quality_json");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto path = write_quality_json(s, dir, "dir/\"mesh\".msh");
  CHECK(path == dir / "quality.json");
  CHECK(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()) == 1);
  const std::string j = read_text_file(path);
  for (const char* key :
       {"\"format\": \"pdmesh-quality\"", "\"triangles\": 3", "\"points\": 5", "\"included_angle\"",
        "\"aspect_ratio\": {\"average\": null, \"max\": null}", "\"skewness\"", "\"weighted_condition_number\"",
        "\"minimum_corner_jacobian\": 0,", "\"small_angle\"", "\"histograms\"", "\"min_angle\"",
        "\"spacing_conformance\": {\"edges\":", "\"source\": \"dir/\\\"mesh\\\".msh\""}) {
    INFO(key);
    CHECK(j.find(key) != std::string::npos);
  }
  CHECK(j.find("inf") == std::string::npos);
  CHECK(j.find("nan") == std::string::npos);
  CHECK(j.find("\"cleanup\": null") != std::string::npos);  // not a cleaned mesh
  std::filesystem::remove_all(dir);
}

TEST_CASE("a cleaned mesh's summary reports the cleanup in quality.json and in the table", "[quality]") {
  QualitySummary s = summarize_quality(two_triangle_mesh());
  s.has_cleanup = true;
  s.cleanup.target_deg = 32.5;
  s.cleanup.below_before = 7;
  s.cleanup.below_after = 1;
  s.cleanup.min_angle_before = 21.25;
  s.cleanup.min_angle_after = 31.5;
  s.cleanup.inserted = 3;
  s.cleanup.removed = 2;
  const std::string j = quality_json(s, "m");
  CHECK(j.find("\"cleanup\": {\"target_deg\": 32.5, \"below_target\": {\"before\": 7, \"after\": 1}, "
               "\"min_angle\": {\"before\": 21.25, \"after\": 31.5}") != std::string::npos);
  CHECK(j.find("\"inserted\": 3, \"removed\": 2") != std::string::npos);
  const std::string table = format_quality_table({{"raw", summarize_quality(two_triangle_mesh())}, {"clean", s}});
  INFO(table);
  CHECK(table.find("Cleanup: < 32.5 deg        before            -         7\n") != std::string::npos);
  CHECK(table.find("Cleanup: min angle         before            -     21.25\n") != std::string::npos);
  CHECK(table.find("after             -     31.50\n") != std::string::npos);
  // Without a cleaned column there are no cleanup rows.
  CHECK(format_quality_table(summarize_quality(two_triangle_mesh())).find("Cleanup") == std::string::npos);
}

TEST_CASE("quality command reads a mesh file, prints the table and writes the JSON", "[quality]") {
  const auto dir = pdmesh_test::fresh_path("quality_command");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  // Unit square split along its diagonal; the geometry is the square as four one-segment curves,
  // so the boundary spacing (eq. 3.6, every closest segment has length 1) is q = 1 everywhere.
  Mesh m;
  m.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.curve_names = {"bottom", "right", "top", "left"};
  m.boundary_edges = {{0, 1, 0}, {1, 2, 1}, {2, 3, 2}, {3, 0, 3}};
  write_mesh(m, dir, "square", {"su2"});
  write_text_file(dir / "square.crv", "2\n0 0\n1 0\n2\n1 0\n1 1\n2\n1 1\n0 1\n2\n0 1\n0 0\n");
  write_text_file(dir / "case.toml",
                  "[geometry]\nfiles = [\"square.crv\"]\n[spacing]\nfield = \"expression\"\n"
                  "expression = \"2\"\n");
  std::ostringstream out, err;
  CHECK(run_quality((dir / "square.su2").string(), (dir / "square.crv").string(), dir.string(), out, err) == 0);
  CHECK(out.str().find("Number of Triangles") != std::string::npos);
  CHECK(out.str().find("square.su2") != std::string::npos);
  const std::string j = read_text_file(dir / "quality.json");
  const double mean = (4.0 + kSqrt2) / 5.0;  // edges 1, 1, 1, 1, sqrt2 over q = 1
  CHECK(j.find(fmt::format("\"mean\": {}", mean)) != std::string::npos);

  std::ostringstream out2, err2;
  run_quality((dir / "square.su2").string(), (dir / "case.toml").string(), std::string("-"), out2, err2);
  CHECK(out2.str().find(fmt::format("\"mean\": {}", mean / 2.0)) != std::string::npos);  // q = 2

  std::ostringstream out3, err3;
  run_quality((dir / "square.su2").string(), std::nullopt, (dir / "q.json").string(), out3, err3);
  CHECK(read_text_file(dir / "q.json").find("\"spacing_conformance\": null") != std::string::npos);
  CHECK_THROWS_AS(run_quality((dir / "nope.msh").string(), std::nullopt, std::nullopt, out3, err3), InputError);
  std::filesystem::remove_all(dir);
}

TEST_CASE("metric values by name are the per-triangle fields and unknown names are refused", "[quality]") {
  const Mesh m = two_triangle_mesh();
  const auto per = triangle_qualities(m);
  CHECK(metric_values(per, "min_angle") == std::vector<double>{per[0].min_angle, per[1].min_angle});
  CHECK(metric_values(per, "max_angle")[1] == Approx(90.0));
  CHECK(metric_values(per, "aspect_ratio")[0] == Approx(1.0));
  CHECK(metric_values(per, "skewness")[1] == per[1].skewness);
  CHECK(metric_values(per, "condition_number")[1] == per[1].condition_number);
  CHECK(metric_values(per, "min_jacobian")[0] == Approx(kSqrt3 / 2));
  CHECK_THROWS_AS(metric_values(per, "minangle"), InputError);
}

namespace {

// A jittered n x n grid of the unit square, two triangles per cell (counter-clockwise).
Mesh jittered_grid(int n) {
  std::mt19937_64 rng(42);
  Mesh m;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const bool side = i == 0 || j == 0 || i == n - 1 || j == n - 1;
      Vec2 p{i / (n - 1.0), j / (n - 1.0)};
      if (!side) p = p + Vec2{0.3 * (unit(rng) - 0.5) / n, 0.3 * (unit(rng) - 0.5) / n};
      m.points.push_back(p);
    }
  const auto id = [n](int i, int j) { return j * n + i; };
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

}  // namespace

TEST_CASE("the summary measured triangle by triangle is the per-triangle loop's, bit for bit", "[quality]") {
  const Mesh m = jittered_grid(40);
  const std::vector<TriangleQuality> q = triangle_qualities(m);
  const QualitySummary s = summarize_quality_of(m);
  // The figures as one loop over the per-triangle metrics computes them, in triangle order.
  double min_angle = HUGE_VAL, max_angle = -HUGE_VAL, ar = 0.0, skew = 0.0, k = 0.0, jac = HUGE_VAL, ar_max = 0.0;
  for (const TriangleQuality& t : q) {
    min_angle = std::min(min_angle, t.min_angle);
    max_angle = std::max(max_angle, t.max_angle);
    jac = std::min(jac, t.min_jacobian);
    ar_max = std::max(ar_max, t.aspect_ratio);
    ar += t.aspect_ratio;
    skew += t.skewness;
    k += t.condition_number;
  }
  const double n = static_cast<double>(q.size());
  CHECK(s.triangles == q.size());
  CHECK(s.min_angle == min_angle);
  CHECK(s.max_angle == max_angle);
  CHECK(s.min_jacobian == jac);
  CHECK(s.aspect_ratio_max == ar_max);
  CHECK(s.aspect_ratio_avg == ar / n);
  CHECK(s.skewness_avg == skew / n);
  CHECK(s.condition_number_avg == k / n);
  const QualitySummary whole = summarize_quality(q);
  CHECK(whole.min_angle_histogram.counts == s.min_angle_histogram.counts);
  CHECK(whole.aspect_ratio_histogram.counts == s.aspect_ratio_histogram.counts);
  // The values of one metric for a picture, without the per-triangle array.
  CHECK(mesh_metric_values(m, "skewness") == metric_values(q, "skewness"));
  CHECK_THROWS_AS(mesh_metric_values(m, "nope"), InputError);
  // No triangle: the empty summary.
  const QualitySummary none = summarize_quality_of(Mesh{});
  CHECK(none.triangles == 0);
  CHECK(none.min_angle == 0.0);
  CHECK(none.aspect_ratio_max == 0.0);
}

TEST_CASE("spacing conformance asks for q in batches and measures every edge as one batch would", "[quality]") {
  // 200 x 200 points: about 119k unique edges, two batches of midpoints and a partial third.
  const Mesh m = jittered_grid(200);
  std::size_t calls = 0, largest = 0;
  const auto q = [](Vec2 p) { return 0.004 + 0.002 * p.x * p.y; };
  const SpacingConformance c = spacing_conformance(m, [&](const std::vector<Vec2>& p, std::vector<double>& out) {
    ++calls;
    largest = std::max(largest, p.size());
    out.resize(p.size());
    for (std::size_t k = 0; k < p.size(); ++k) out[k] = q(p[k]);
  });
  CHECK(calls > 1);
  CHECK(largest <= (std::size_t{1} << 16));
  // Every unique edge's ratio, with its q asked for alone.
  std::vector<double> ratios;
  for (const auto& [i, j] : unique_edges(m))
    ratios.push_back(dist(m.points[static_cast<std::size_t>(i)], m.points[static_cast<std::size_t>(j)]) /
                     q(0.5 * (m.points[static_cast<std::size_t>(i)] + m.points[static_cast<std::size_t>(j)])));
  double sum = 0.0;
  for (double r : ratios) sum += r;
  CHECK(c.edges == ratios.size());
  CHECK(c.mean == sum / static_cast<double>(ratios.size()));
  CHECK(c.min == *std::min_element(ratios.begin(), ratios.end()));
  CHECK(c.max == *std::max_element(ratios.begin(), ratios.end()));
  // A bad q in a later batch is still named by its edge.
  const auto bad = [&](const std::vector<Vec2>& p, std::vector<double>& out) {
    out.assign(p.size(), 1.0);
    for (std::size_t k = 0; k < p.size(); ++k)
      if (p[k].x > 0.99 && p[k].y > 0.99) out[k] = -1.0;
  };
  CHECK_THROWS_AS(spacing_conformance(m, bad), InputError);
}
