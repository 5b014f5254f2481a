// Tests of curves whose every point is a fixed node (RawCurve::fixed_points, a boundary layer's
// front): every point critical, no boundary node between points under either placement rule.
#include <catch2/catch.hpp>

#include "geometry/geometry.hpp"
#include "init/boundary_placement.hpp"
#include "nodes/node_set.hpp"
#include "spacing/spacing_field.hpp"

using namespace pdmesh;

namespace {

class Constant final : public SpacingField {
 public:
  explicit Constant(double q) : q_(q) {}
  double at(Vec2) const override { return q_; }

 private:
  double q_;
};

// A square of side 4 (plain) around a square of side 1 (fixed points, 4 points per side).
std::vector<RawCurve> squares(bool fixed) {
  RawCurve outer{"outer", {{-2, -2}, {2, -2}, {2, 2}, {-2, 2}, {-2, -2}}, "memory", 1, {}};
  RawCurve inner{"front", {}, "memory", 1, {}, fixed};
  const Vec2 corners[] = {{-0.5, -0.5}, {-0.5, 0.5}, {0.5, 0.5}, {0.5, -0.5}};
  for (int side = 0; side < 4; ++side)
    for (int k = 0; k < 4; ++k) {
      const double t = k / 4.0;
      inner.points.push_back((1 - t) * corners[side] + t * corners[(side + 1) % 4]);
    }
  inner.points.push_back(inner.points.front());
  return {outer, inner};
}

}  // namespace

TEST_CASE("every point of a fixed-points curve is critical", "[geometry][layers]") {
  const Geometry fixed = build_geometry(squares(true));
  REQUIRE(fixed.curves[1].fixed_points);
  for (const auto c : fixed.curves[1].critical) CHECK(c == 1);
  const Geometry plain = build_geometry(squares(false));
  int critical = 0;
  for (const auto c : plain.curves[1].critical) critical += c;
  CHECK(critical == 5);  // the 4 corners and the closing point
}

TEST_CASE("boundary placement puts a fixed-points curve's nodes at its points only", "[init][layers]") {
  const Constant fine(0.02);  // 12 nodes per segment of the front, 200 per side of the outer square
  for (const BoundaryNodeRule rule : {BoundaryNodeRule::Spacing, BoundaryNodeRule::Input}) {
    const Geometry g = build_geometry(squares(true));
    const NodeSet nodes = place_boundary_nodes(g, fine, rule, nullptr);
    CHECK(nodes.curve_nodes[1].size() == 17);  // 16 points, the first repeated at the end
    for (const int n : nodes.curve_nodes[1]) CHECK(nodes.kind[static_cast<std::size_t>(n)] == NodeKind::Fixed);
    if (rule == BoundaryNodeRule::Spacing) CHECK(nodes.curve_nodes[0].size() > 700);
  }
  // Without the flag the spacing rule places nodes between the points.
  const Geometry plain = build_geometry(squares(false));
  CHECK(place_boundary_nodes(plain, fine, BoundaryNodeRule::Spacing, nullptr).curve_nodes[1].size() > 100);
}
