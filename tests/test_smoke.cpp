// Smoke tests of the core value types.
#include <catch2/catch.hpp>

#include "core/vec2.hpp"
#include "nodes/node_set.hpp"

using namespace pdmesh;

TEST_CASE("Vec2 arithmetic", "[core]") {
  Vec2 a{3, 4};
  CHECK(norm(a) == 5.0);
  CHECK(cross(Vec2{1, 0}, Vec2{0, 1}) == 1.0);
  CHECK(dot(a, Vec2{1, 1}) == 7.0);
}

TEST_CASE("NodeSet counts kinds", "[core]") {
  NodeSet n;
  n.add({0, 0}, 1, NodeKind::Fixed, 0);
  n.add({1, 0}, 1, NodeKind::Interior, -1);
  n.add({2, 0}, 1, NodeKind::Interior, -1);
  CHECK(n.count(NodeKind::Interior) == 2);
  CHECK(n.count(NodeKind::Boundary) == 0);
  CHECK(std::string(to_string(NodeKind::Fixed)) == "fixed");
}
