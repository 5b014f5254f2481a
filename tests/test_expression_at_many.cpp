// The fields that evaluate muParser expressions, in batches on several threads (each thread with a
// parser of its own, core/lease_pool.hpp): ExpressionMetricField, HessianMetricField (and its
// complexity scale, summed in row order), ExpressionSpacing, MetricSizeField and PointMetricField give
// at()'s values bit for bit, call after call, and a bad point's error names the expression.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "core/errors.hpp"
#include "error_message.hpp"
#include "spacing/fixed_point_metric.hpp"
#include "spacing/hessian.hpp"
#include "spacing/hessian_metric.hpp"
#include "spacing/metric_field.hpp"
#include "spacing/metric_size_field.hpp"
#include "spacing/spacing_field.hpp"

using namespace pdmesh;
using Catch::Matchers::Contains;
using pdmesh_test::error_message;

namespace {

// Enough points for several blocks of kExpressionPointsPerThread, spread over the unit square.
std::vector<Vec2> scattered(int n) {
  std::vector<Vec2> p;
  for (int k = 0; k < n; ++k) p.push_back({std::fmod(0.6180339887 * k, 1.0), std::fmod(0.7548776662 * k, 1.0)});
  return p;
}

void require_same(const MetricField& field, const std::vector<Vec2>& p, const std::vector<Metric>& out) {
  REQUIRE(out.size() == p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Metric m = field.at(p[i]);
    INFO("point " << i << " (" << p[i].x << ", " << p[i].y << ")");
    REQUIRE(out[i].m11 == m.m11);
    REQUIRE(out[i].m12 == m.m12);
    REQUIRE(out[i].m22 == m.m22);
  }
}

}  // namespace

TEST_CASE("ExpressionMetricField::at_many gives at()'s metrics bit for bit, call after call", "[metric_field]") {
  const auto sizes = ExpressionMetricField::from_sizes("0.1", "0.001 + 0.2*abs(y - 0.5 - 0.2*sin(6*x))", "30*x + 40*y");
  const auto components = ExpressionMetricField::from_components("100 + 50*x", "10*x*y", "400 + 30*y");
  std::vector<Vec2> p = scattered(5000);
  std::vector<Metric> out;
  std::vector<int> guesses;
  for (int call = 0; call < 2; ++call) {
    INFO("call " << call);
    sizes.at_many(p, out, guesses);
    REQUIRE(guesses.size() == p.size());
    require_same(sizes, p, out);
    components.at_many(p, out, guesses);
    require_same(components, p, out);
    for (Vec2& q : p) q = {q.x * 0.99 + 0.003, q.y * 0.98 + 0.01};
  }
  std::vector<Vec2> none;
  sizes.at_many(none, out, guesses);
  CHECK(out.empty());
}

TEST_CASE("HessianMetricField: at_many and the complexity scale as one thread computes them", "[hessian]") {
  HessianMetricOptions o;
  o.complexity = 4000.0;
  o.hmin = 1e-5;
  o.hmax = 0.3;
  const std::string u = "tanh(100*(y - 0.5 - 0.25*sin(2*pi*x)))";
  const Box box{{0.0, 0.0}, {1.0, 1.0}};
  const int grid = 96;
  const double step = 1e-5;
  const HessianMetricField field(u, box, o, step, grid);
  // The midpoint rule's sum, cell by cell in row order on this thread: the same bits as the field's.
  double total = 0.0;
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) {
      const Vec2 c{box.lo.x + (i + 0.5) / grid * box.width(), box.lo.y + (j + 0.5) / grid * box.height()};
      total += hessian_density(field.hessian(c), o);
    }
  CHECK(field.scale() == o.complexity / (total * box.width() * box.height() / (static_cast<double>(grid) * grid)));
  const std::vector<Vec2> p = scattered(3000);
  std::vector<Metric> out;
  std::vector<int> guesses;
  field.at_many(p, out, guesses);
  require_same(field, p, out);
  // A value that is not finite at some points of the batch: the error names the expression and a point.
  const HessianMetricField root("sqrt(y - 0.001)", Box{{0.0, 0.5}, {1.0, 1.0}}, o, 1e-3, 8);
  CHECK_THAT(error_message<InputError>([&] { root.at_many(p, out, guesses); }),
             Contains("'sqrt(y - 0.001)' at (") && Contains("finite"));
}

TEST_CASE("ExpressionSpacing and MetricSizeField: at_many gives at()'s sizes bit for bit", "[spacing]") {
  const ExpressionSpacing q("0.5 + 19.5*tanh(x/16)^2 + 0.1*sin(9*y)");
  const auto metric = ExpressionMetricField::from_sizes("0.01 + 0.2*x", "0.05 + 0.1*y*y", "45*x");
  const MetricSizeField size(metric);
  const std::vector<Vec2> p = scattered(4000);
  for (const SpacingField* field : {static_cast<const SpacingField*>(&q), static_cast<const SpacingField*>(&size)}) {
    std::vector<double> out;
    field->at_many(p, out);
    REQUIRE(out.size() == p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      INFO("point " << i);
      REQUIRE(out[i] == field->at(p[i]));
    }
  }
  const ExpressionSpacing negative("y - 0.5");
  std::vector<double> out;
  CHECK_THAT(error_message<InputError>([&] { negative.at_many(p, out); }),
             Contains("spacing expression 'y - 0.5' at (") && Contains("finite positive"));
  const auto bad = ExpressionMetricField::from_sizes("0.1", "y - 0.5", "0");
  const MetricSizeField bad_size(bad);
  CHECK_THAT(error_message<InputError>([&] { bad_size.at_many(p, out); }), Contains("h2 = 'y - 0.5'"));
}

TEST_CASE("PointMetricField::at_many: the given points' metrics, the field's elsewhere", "[metric_field]") {
  std::vector<Vec2> p = scattered(2000);
  const Metric given_a = metric_from_sizes(0.5, 0.25, 0.0), given_b = metric_from_sizes(0.125, 0.125, 0.0);
  std::vector<std::pair<Vec2, Metric>> given{{p[7], given_a}, {p[1500], given_b}};
  const PointMetricField field(
      std::make_unique<ExpressionMetricField>(ExpressionMetricField::from_sizes("0.01 + x", "0.02 + y", "10")), given);
  std::vector<Metric> out;
  std::vector<int> guesses;
  field.at_many(p, out, guesses);
  require_same(field, p, out);
  CHECK(out[7].m11 == given_a.m11);
  CHECK(out[1500].m22 == given_b.m22);
  CHECK(out[8].m11 != given_a.m11);
}
