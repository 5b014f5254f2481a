// The check of the closest-segment searches (GeometryTree, FeatureSize) against the
// brute-force oracle (geometry/brute_force_queries): the same segment, distance, point and parameter,
// bit for bit.
#pragma once
#include <catch2/catch.hpp>

#include <string>

#include "geometry/geometry_tree.hpp"

namespace pdmesh_test {

// `curve` names the curve the query was restricted to in the failure message; -1: all curves.
inline void require_same(const pdmesh::ClosestHit& got, const pdmesh::ClosestHit& brute, pdmesh::Vec2 p,
                         int curve = -1) {
  INFO("query (" << p.x << ", " << p.y << ")" << (curve >= 0 ? " curve " + std::to_string(curve) : std::string())
                 << ": segment " << got.segment << " at " << got.distance << ", brute force segment " << brute.segment
                 << " at " << brute.distance);
  REQUIRE(got.segment == brute.segment);
  REQUIRE(got.distance == brute.distance);
  REQUIRE(got.point == brute.point);
  REQUIRE(got.t == brute.t);
}

}  // namespace pdmesh_test
