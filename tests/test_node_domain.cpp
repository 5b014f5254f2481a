// node_domain_area: the even-odd area enclosed by the boundary-node polygons.
#include <catch2/catch.hpp>

#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "nodes/node_domain.hpp"
#include "spacing/spacing_field.hpp"

using namespace pdmesh;

namespace {
// A closed square curve of side s centred at c with n points per side.
RawCurve square(double s, Vec2 c, int n, bool clockwise) {
  RawCurve r;
  std::vector<Vec2> corners = {
      {c.x - s / 2, c.y - s / 2}, {c.x + s / 2, c.y - s / 2}, {c.x + s / 2, c.y + s / 2}, {c.x - s / 2, c.y + s / 2}};
  if (clockwise) std::swap(corners[1], corners[3]);
  for (int side = 0; side < 4; ++side)
    for (int k = 0; k < n; ++k) {
      const double t = static_cast<double>(k) / n;
      r.points.push_back(corners[side] + t * (corners[(side + 1) % 4] - corners[side]));
    }
  r.points.push_back(corners[0]);
  r.file = "test";
  return r;
}
}  // namespace

TEST_CASE("node domain area equals the geometry area when nodes sit on the geometry points", "[nodes]") {
  for (bool clockwise : {false, true}) {
    Geometry g = build_geometry({square(4, {0, 0}, 4, false), square(2, {0.5, 0}, 3, clockwise)});
    GeometryTree tree(g);
    BoundarySpacing q(tree);
    NodeSet nodes = make_boundary_nodes(g, q);
    CHECK(node_domain_area(nodes, g) == Approx(12.0).epsilon(1e-14));
    CHECK(g.area == Approx(12.0).epsilon(1e-14));
  }
}

TEST_CASE("a node slid off a corner cuts the corner off the node domain", "[nodes]") {
  Geometry g = build_geometry({square(4, {0, 0}, 4, false)});
  GeometryTree tree(g);
  BoundarySpacing q(tree);
  NodeSet nodes = make_boundary_nodes(g, q);
  // The curve's points run (-2,-2), (-1,-2), ... along the sides; point 5 is (2,-1), point 6 is (2,0).
  // Sliding a node along a straight side keeps the polygon, and its area.
  const int n5 = nodes.curve_nodes[0][5];
  nodes.x[static_cast<std::size_t>(n5)] = {2, -1.5};
  CHECK(node_domain_area(nodes, g) == Approx(16.0).epsilon(1e-14));
  // Moving a node off the straight side inwards by 0.5 removes a triangle of base 2 and height 0.5.
  const int n6 = nodes.curve_nodes[0][6];  // the point (2, 0), between (2,-1.5) and (2, 1)
  nodes.x[static_cast<std::size_t>(n6)] = {1.5, 0};
  const double removed = 0.5 * 0.5 * (1.0 - (-1.5));
  CHECK(node_domain_area(nodes, g) == Approx(16.0 - removed).epsilon(1e-14));
}
