// The spacing pipeline (docs/spacing.md): the gradation limit against Persson's closed form for a point
// source, its idempotence and gradient bound on the corner graph, the feature size on a slot and an
// annulus of known widths (and not at corners), curvature on a circle of known radius, scale, and the
// thesis' field untouched when everything is off.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "spacing/gradation.hpp"
#include "spacing/spacing_pipeline.hpp"
#include "seeded_random.hpp"

using namespace pdmesh;

namespace {

constexpr double kPi = 3.14159265358979323846;

using pdmesh_test::unit;

// A closed polyline through `corners`, each side cut into pieces of at most `step`.
RawCurve polygon(const std::vector<Vec2>& corners, double step, const std::string& name) {
  RawCurve c;
  c.name = name;
  c.file = "test";
  c.line = 1;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const Vec2 a = corners[i], b = corners[(i + 1) % corners.size()];
    const int n = std::max(1, static_cast<int>(std::ceil(dist(a, b) / step)));
    for (int k = 0; k < n; ++k) c.points.push_back(a + (static_cast<double>(k) / n) * (b - a));
  }
  c.points.push_back(corners.front());
  return c;
}

RawCurve circle(Vec2 centre, double r, int segments, const std::string& name, bool ccw = true) {
  RawCurve c;
  c.name = name;
  c.file = "test";
  c.line = 1;
  for (int k = 0; k <= segments; ++k) {
    const double a = 2.0 * kPi * (k % segments) / segments * (ccw ? 1.0 : -1.0);
    c.points.push_back({centre.x + r * std::cos(a), centre.y + r * std::sin(a)});
  }
  return c;
}

// The corner positions of an emitted quadtree (leaf_cell gives each leaf's box).
std::vector<Vec2> corner_positions(const BackgroundFieldData& d) {
  std::vector<Vec2> pos(d.corner_q.size());
  for (std::size_t l = 0; l < d.leaves(); ++l) {
    const int cell = d.leaf_cell[4 * l], level = d.leaf_cell[4 * l + 1];
    const double side = std::ldexp(d.root_size, -level);
    const double x0 = d.origin_x + d.root_size * (cell % d.grid) + side * d.leaf_cell[4 * l + 2];
    const double y0 = d.origin_y + d.root_size * (cell / d.grid) + side * d.leaf_cell[4 * l + 3];
    for (int k = 0; k < 4; ++k)
      pos[static_cast<std::size_t>(d.leaf_corner[4 * l + k])] = {x0 + side * (k & 1), y0 + side * (k >> 1)};
  }
  return pos;
}

// A geometry, its base field (an expression, or eq. 3.6 when the expression is empty) and the pipeline.
struct Field {
  Geometry geometry;
  std::unique_ptr<GeometryTree> tree;
  std::unique_ptr<SpacingField> base;
  std::unique_ptr<SpacingPipeline> pipeline;
  Field(std::vector<RawCurve> curves, const std::string& base_expression, const SpacingOptions& options)
      : geometry(build_geometry(std::move(curves))),
        tree(std::make_unique<GeometryTree>(geometry)),
        base(base_expression.empty() ? std::unique_ptr<SpacingField>(std::make_unique<BoundarySpacing>(*tree))
                                     : std::make_unique<ExpressionSpacing>(base_expression)),
        pipeline(std::make_unique<SpacingPipeline>(*base, *tree, options)) {}
  double at(Vec2 p) const { return pipeline->field().at(p); }
};

}  // namespace

TEST_CASE("gradation: a point source in a large square gives min(q, q0 + g d)", "[spacing]") {
  SpacingOptions o;
  o.gradation = 0.2;
  const Vec2 y{37.3, 51.7};
  const double q0 = 0.01;
  o.points = {{y, q0}};
  const Field f({polygon({{0, 0}, {100, 0}, {100, 100}, {0, 100}}, 5.0, "square")}, "1", o);
  const BackgroundFieldData& d = f.pipeline->background().data();
  // The stated error of the limited field: the background tolerance (1e-2 relative, held to half that
  // at the test points), except in leaves that hold the cone's apex, whose kink bilinear interpolation
  // cannot follow: there within g times the leaf's side.
  std::mt19937_64 rng(42);
  std::size_t checked = 0, near_apex = 0;
  double worst = 0.0;
  for (int i = 0; i < 20000; ++i) {
    // Half the points within 1 of the source, where q changes fastest.
    const bool close = i % 2 == 0;
    const Vec2 p =
        close ? Vec2{y.x - 1 + 2 * unit(rng), y.y - 1 + 2 * unit(rng)} : Vec2{100 * unit(rng), 100 * unit(rng)};
    const double exact = std::min(1.0, q0 + 0.2 * dist(p, y));
    const double got = f.at(p);
    const Box leaf = background_leaf_box(d, p);
    const double err = std::fabs(got - exact);
    if (leaf.contains(y)) {
      ++near_apex;
      CHECK(err <= 0.2 * leaf.width());
    } else {
      worst = std::max(worst, err / exact);
      if (err > 1e-2 * exact) FAIL_CHECK("at (" << p.x << ", " << p.y << "): " << got << " against " << exact);
    }
    ++checked;
  }
  INFO("worst relative error away from the apex leaf " << worst << ", " << near_apex << " points in the apex leaf");
  CHECK(worst < 1e-2);
  // The value at the source itself is within the apex leaf's bound of q0.
  CHECK(f.at(y) <= q0 + 0.2 * background_leaf_box(d, y).width());
}

TEST_CASE("gradation: limiting twice changes nothing and the gradient bound holds on the corner graph", "[spacing]") {
  SpacingOptions o;
  o.gradation = 0.15;
  o.points = {{{2.2, 3.1}, 0.002}, {{7.9, 6.4}, 0.05}};
  const Field f({polygon({{0, 0}, {10, 0}, {10, 10}, {0, 10}}, 0.5, "square")}, "0.4 + 0.05*x", o);
  const BackgroundFieldData& d = f.pipeline->background().data();
  const std::vector<Vec2> pos = corner_positions(d);
  const GradationGraph graph(pos, d.leaf_corner);
  std::vector<double> again;
  std::vector<std::int32_t> source;
  graph.limit(0.15, d.corner_q, again, source);
  std::size_t changed = 0;
  for (std::size_t i = 0; i < again.size(); ++i)
    if (std::fabs(again[i] - d.corner_q[i]) > 1e-12 * d.corner_q[i]) ++changed;
  CHECK(changed == 0);
  // |q_i - q_j| <= g |x_i - x_j| along every leaf side and diagonal.
  std::size_t violations = 0;
  for (std::size_t l = 0; l < d.leaves(); ++l)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        const auto i = static_cast<std::size_t>(d.leaf_corner[4 * l + a]),
                   j = static_cast<std::size_t>(d.leaf_corner[4 * l + b]);
        if (std::fabs(d.corner_q[i] - d.corner_q[j]) > 0.15 * dist(pos[i], pos[j]) * (1 + 1e-12)) ++violations;
      }
  CHECK(violations == 0);
  // The pipeline applied to its own result: the same field within the background tolerance.
  SpacingOptions o2;
  o2.gradation = 0.15;
  const SpacingPipeline twice(f.pipeline->background(), *f.tree, o2);
  std::mt19937_64 rng(7);
  double worst = 0.0;
  for (int i = 0; i < 5000; ++i) {
    const Vec2 p{10 * unit(rng), 10 * unit(rng)};
    worst = std::max(worst, std::fabs(twice.field().at(p) - f.at(p)) / f.at(p));
  }
  CHECK(worst < 1e-2);
}

TEST_CASE("gradation: each corner gets the smallest cone, not an 8-neighbour path length", "[spacing]") {
  // Four corners of a unit square, one source: the diagonal corner is at distance sqrt(2), not 2.
  const GradationGraph graph({{0, 0}, {1, 0}, {0, 1}, {1, 1}}, {0, 1, 2, 3});
  std::vector<double> q;
  std::vector<std::int32_t> source;
  graph.limit(0.5, {0.1, 9, 9, 9}, q, source);
  CHECK(q[1] == Approx(0.6));
  CHECK(q[3] == Approx(0.1 + 0.5 * std::sqrt(2.0)));
  CHECK(source == std::vector<std::int32_t>{0, 0, 0, 0});
  graph.limit(0.0, {0.1, 9, 9, 9}, q, source);  // off
  CHECK(q == std::vector<double>{0.1, 9, 9, 9});
}

TEST_CASE("gradation: the sweep's start entries sort as std::sort sorts them", "[spacing]") {
  std::mt19937_64 rng(5);
  // Many equal values (the corner decides), zeros, tiny and huge values, infinity.
  const std::vector<double> pool = {
      0.0, 1e-300, 0.01, 0.25, 0.25 + 1e-16, 1.0, 3.5, 1e300, std::numeric_limits<double>::infinity()};
  for (int round = 0; round < 20; ++round) {
    std::vector<std::pair<double, std::int32_t>> entries;
    const int n = 1 + static_cast<int>(rng() % 5000);
    for (int i = 0; i < n; ++i)
      entries.push_back({rng() % 3 == 0 ? unit(rng) : pool[rng() % pool.size()], static_cast<std::int32_t>(i)});
    if (round == 5) entries[static_cast<std::size_t>(n) / 2].first = -0.0;  // std::sort's path
    if (round == 6) entries[0].first = -1.0;
    auto expected = entries;
    std::sort(expected.begin(), expected.end());
    detail::sort_gradation_entries(entries);
    REQUIRE(entries == expected);
  }
}

TEST_CASE("gradation: relimit from repeated seeds is relimit from each seed once", "[spacing]") {
  // A 6 x 6 grid of unit leaves, a few low values to spread; the seeds repeat as the corners of
  // neighbouring leaves do.
  std::vector<Vec2> pos;
  for (int y = 0; y <= 6; ++y)
    for (int x = 0; x <= 6; ++x) pos.push_back({static_cast<double>(x), static_cast<double>(y)});
  std::vector<std::int32_t> leaf_corner;
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 6; ++x)
      for (int k = 0; k < 4; ++k) leaf_corner.push_back((y + (k >> 1)) * 7 + x + (k & 1));
  const GradationGraph graph(pos, leaf_corner);
  std::vector<double> q0(pos.size(), 2.0);
  q0[8] = 0.1;
  q0[40] = 0.3;
  std::vector<double> base;
  std::vector<std::int32_t> base_source;
  graph.limit(0.3, q0, base, base_source);
  // Lower two corners afterwards (as a refinement's new corners would be) and sweep from them.
  std::vector<double> q0_new = q0;
  q0_new[20] = 0.05;
  q0_new[33] = 0.02;
  std::vector<double> q_once = base, q_repeated = base;
  std::vector<std::int32_t> s_once = base_source, s_repeated = base_source;
  for (const int c : {20, 33}) {
    q_once[static_cast<std::size_t>(c)] = q_repeated[static_cast<std::size_t>(c)] = q0_new[static_cast<std::size_t>(c)];
    s_once[static_cast<std::size_t>(c)] = s_repeated[static_cast<std::size_t>(c)] = c;
  }
  const std::vector<std::int32_t> once = {19, 20, 21, 26, 27, 32, 33, 34};
  std::vector<std::int32_t> repeated;
  for (int k = 0; k < 3; ++k) repeated.insert(repeated.end(), once.rbegin(), once.rend());
  graph.relimit(0.3, q0_new, q_once, s_once, once);
  graph.relimit(0.3, q0_new, q_repeated, s_repeated, repeated);
  CHECK(q_once == q_repeated);
  CHECK(s_once == s_repeated);
  CHECK(q_once[20] == 0.05);
  CHECK(q_once[13] == Approx(0.05 + 0.3));  // the neighbour below corner 20
  CHECK(s_once[13] == 20);
}

TEST_CASE("feature size: a slot of width w gets k node spacings across, and corners are no gaps", "[spacing]") {
  // A 10 x 4 chamber with a slot 0.5 wide and 3 deep opening from its bottom edge.
  const double w = 0.5;
  const std::vector<Vec2> plate = {{0, 0},         {5 - w / 2, 0}, {5 - w / 2, -3}, {5 + w / 2, -3},
                                   {5 + w / 2, 0}, {10, 0},        {10, 4},         {0, 4}};
  const double k = GENERATE(2.0, 3.0);
  SpacingOptions o;
  o.rows_in_gap = k;
  const Field f({polygon(plate, 0.05, "plate")}, "1", o);
  INFO("k = " << k);
  // Across the slot, away from its ends: W = w everywhere, so q = w / k (at most the tolerance above).
  for (double y = -2.4; y <= -0.6; y += 0.2)
    for (double x = 5 - w / 2 + 0.01; x < 5 + w / 2; x += 0.06) {
      const double q = f.at({x, y});
      INFO("at (" << x << ", " << y << ")");
      CHECK(w / q >= k * (1 - 1e-2));
      CHECK(q >= (w / k) * (1 - 2e-2));
    }
  // The chamber is 4 wide: k <= 3 spacings of 1 fit, so q stays 1, also at its 90-degree corners and
  // beside the slot's mouth, where two sides meet at 270 degrees.
  for (const Vec2 p : {Vec2{0.05, 0.05}, Vec2{9.9, 3.95}, Vec2{1, 2}, Vec2{8, 0.5}, Vec2{3.5, 0.1}})
    CHECK(f.at(p) == Approx(1.0).epsilon(1e-3));
}

TEST_CASE("feature size: an annulus of width w gets k node spacings across", "[spacing]") {
  const double r1 = 1.0, r2 = 1.3;
  SpacingOptions o;
  o.rows_in_gap = 2;
  const Field f({circle({0, 0}, r2, 400, "outer"), circle({0, 0}, r1, 300, "inner", false)}, "1", o);
  for (int i = 0; i < 36; ++i) {
    const double a = 2 * kPi * i / 36;
    for (const double r : {r1 + 0.005, 1.15, r2 - 0.005}) {
      const double q = f.at({r * std::cos(a), r * std::sin(a)});
      INFO("r " << r << " angle " << a);
      CHECK((r2 - r1) / q >= 2 * (1 - 1e-2));
      CHECK(q >= 0.5 * (r2 - r1) * (1 - 3e-2));  // the polygons' chords make the gap a little narrower
    }
  }
}

TEST_CASE("curvature: q = R theta on a circle of known radius, growing by theta per unit distance", "[spacing]") {
  const double radius = 2.0, theta = 10.0 * kPi / 180.0;
  SpacingOptions o;
  o.curvature_angle = 10.0;
  const Field f(
      {polygon({{-10, -10}, {10, -10}, {10, 10}, {-10, 10}}, 1.0, "box"), circle({0, 0}, radius, 240, "hole", false)},
      "1", o);
  for (int i = 0; i < 24; ++i) {
    const double a = 2 * kPi * (i + 0.5) / 24;
    for (const double d : {0.0, 0.5, 2.0}) {
      const double r = radius + d;
      INFO("distance " << d << " angle " << a);
      CHECK(f.at({r * std::cos(a), r * std::sin(a)}) == Approx(theta * r).epsilon(1e-2));
    }
  }
  // The straight sides of the box show no curvature (their corners are critical points).
  CHECK(f.at({0, -9.9}) == Approx(1.0).epsilon(1e-3));
  CHECK(f.at({9.9, 9.9}) == Approx(1.0).epsilon(1e-3));
}

TEST_CASE("spacing pipeline: scale multiplies the field, and everything off is the base field itself", "[spacing]") {
  const std::vector<RawCurve> curves = {polygon({{0, 0}, {4, 0}, {4, 3}, {0, 3}}, 0.2, "box")};
  SpacingOptions off;
  const Field plain(curves, "0.1 + 0.02*x*y", off);
  CHECK(plain.pipeline->exact());
  CHECK(&plain.pipeline->field() == plain.base.get());
  SpacingOptions half;
  half.scale = 0.5;
  const Field scaled(curves, "0.1 + 0.02*x*y", half);
  CHECK_FALSE(scaled.pipeline->exact());
  std::mt19937_64 rng(3);
  for (int i = 0; i < 1000; ++i) {
    const Vec2 p{4 * unit(rng), 3 * unit(rng)};
    CHECK(scaled.at(p) == Approx(0.5 * plain.base->at(p)).epsilon(1e-2));
  }
}

TEST_CASE("spacing pipeline: invalid options are input errors naming the key", "[spacing]") {
  const Geometry g = build_geometry({polygon({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 0.5, "box")});
  const GeometryTree tree(g);
  const ExpressionSpacing base("0.1");
  auto bad = [&](auto change, const char* text) {
    SpacingOptions o;
    change(o);
    CHECK_THROWS_AS(SpacingPipeline(base, tree, o), InputError);
    CHECK_THROWS_WITH(SpacingPipeline(base, tree, o), Catch::Matchers::Contains(text));
  };
  bad([](SpacingOptions& o) { o.scale = 0; }, "spacing.scale = 0");
  bad([](SpacingOptions& o) { o.gradation = -0.1; }, "spacing.gradation = -0.1");
  bad([](SpacingOptions& o) { o.rows_in_gap = 0.5; }, "spacing.rows_in_gap = 0.5");
  bad([](SpacingOptions& o) { o.curvature_angle = 120; }, "spacing.curvature_angle = 120");
  bad([](SpacingOptions& o) { o.points = {{{0.5, 0.5}, 0.01}}; }, "need spacing.gradation > 0");
}

TEST_CASE("input boundary floor: q rises back to the input spacing next to coarse segments", "[spacing]") {
  // A 10 x 10 box of 1-long segments with a fine hole (radius 0.2, 0.01-long segments) 1.3 above its
  // bottom wall. The gradation limit alone lowers q at the wall below the hole to 0.01 + 0.2 x 1.3.
  const std::vector<RawCurve> curves = {polygon({{0, 0}, {10, 0}, {10, 10}, {0, 10}}, 1.0, "box"),
                                        circle({5, 1.5}, 0.2, 126, "hole", false)};
  SpacingOptions o;
  o.gradation = 0.2;
  const Field limited(curves, "", o);
  o.input_boundary_floor = 1.0;
  const Field floored(curves, "", o);
  const double d = 1.3;
  CHECK(limited.at({5, 0}) == Approx(0.01 + 0.2 * d).epsilon(2e-2));
  // With the floor: at most the hole's own segments plus 0.5 per unit distance from them, at most
  // the wall's segments; the hole itself keeps its spacing; far walls keep theirs.
  CHECK(floored.at({5, 0}) == Approx(0.01 + 0.5 * d).epsilon(2e-2));
  CHECK(floored.at({5, 1.3}) == Approx(0.01).epsilon(5e-2));
  CHECK(floored.at({2, 10}) == Approx(1.0).epsilon(1e-2));
  CHECK(floored.at({0, 6.5}) == Approx(1.0).epsilon(1e-2));
  // Inside, no lower than the limited field; the floor falls off at 0.5 per unit distance, so beyond
  // 2 (plus a leaf) from the walls the two fields are the same.
  std::mt19937_64 rng(11);
  std::size_t far = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec2 p{10 * unit(rng), 10 * unit(rng)};
    CHECK(floored.at(p) >= limited.at(p) * (1 - 1e-2));
    if (std::min({p.x, p.y, 10 - p.x, 10 - p.y}) > 3.0) {
      ++far;
      CHECK(floored.at(p) == Approx(limited.at(p)).epsilon(1e-2));
    }
  }
  CHECK(far > 200);
  // Boundary nodes placed by the field (final_floor false): the sources keep their floor, the final
  // field does not, so the wall below the hole keeps the limited value.
  o.final_floor = false;
  const Field sources_only(curves, "", o);
  CHECK(sources_only.at({5, 0}) == Approx(limited.at({5, 0})).epsilon(1e-3));
  CHECK(sources_only.at({5, 0}) < 0.5 * floored.at({5, 0}));
}
