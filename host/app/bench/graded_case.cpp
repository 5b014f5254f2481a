// The generated graded benchmark case; see graded_case.hpp.
#include "app/bench/graded_case.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace pdmesh {
namespace {

// N h^2 = a + b h: the far field contributes a / h^2 (hexagonal packing at spacing ~h, lowered by
// the circle's pull on q), the graded region around the circle a count growing like 1 / h.
constexpr double kAreaTerm = 2529.7;
constexpr double kGradedTerm = 1694.4;

void add_polyline(std::vector<RawCurve>& raw, const std::string& name, Vec2 a, Vec2 b, int segments) {
  RawCurve c{name, {}, "generated", 0, {}};
  for (int i = 0; i <= segments; ++i) {
    const double t = static_cast<double>(i) / segments;
    c.points.push_back(i == segments ? b : Vec2{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
  }
  raw.push_back(std::move(c));
}

}  // namespace

double graded_case_node_estimate(double h_out) { return (kAreaTerm + kGradedTerm * h_out) / (h_out * h_out); }

double graded_case_spacing(std::size_t target) {
  // a / h^2 + b / h = T  <=>  T h^2 - b h - a = 0.
  const double t = static_cast<double>(std::max<std::size_t>(target, 1));
  return (kGradedTerm + std::sqrt(kGradedTerm * kGradedTerm + 4.0 * kAreaTerm * t)) / (2.0 * t);
}

Geometry graded_case_geometry(double h_out) {
  const double L = 10.0, h_in = h_out / 1000.0;
  const int side = std::max(1, static_cast<int>(std::lround(2.0 * L / h_out)));
  const int half = 128;
  const double r = 2.0 * half * h_in / (2.0 * M_PI);
  std::vector<RawCurve> raw;
  add_polyline(raw, "bottom", {-L, -L}, {L, -L}, side);
  add_polyline(raw, "right", {L, -L}, {L, L}, side);
  add_polyline(raw, "top", {L, L}, {-L, L}, side);
  add_polyline(raw, "left", {-L, L}, {-L, -L}, side);
  for (int k = 0; k < 2; ++k) {
    RawCurve c{k == 0 ? "circle_upper" : "circle_lower", {}, "generated", 0, {}};
    for (int i = 0; i <= half; ++i) {
      const double t = M_PI * (k + static_cast<double>(i) / half);
      Vec2 p{r * std::cos(t), r * std::sin(t)};
      if (i == 0) p = {k == 0 ? r : -r, 0.0};
      if (i == half) p = {k == 0 ? -r : r, 0.0};
      c.points.push_back(p);
    }
    raw.push_back(std::move(c));
  }
  return build_geometry(std::move(raw));
}

}  // namespace pdmesh
