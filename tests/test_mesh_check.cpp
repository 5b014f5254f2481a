// The mesh checker must accept valid meshes and name each kind of deliberate breakage.
#include <catch2/catch.hpp>
#include <string>

#include "mesh/mesh_check.hpp"
#include "mesh/triangulate_nodes.hpp"

using namespace pdmesh;

namespace {

// Kite A(0,0) B(1,-0.3) C(2,0) D(1,0.3). The diagonal B-D is Delaunay; A-C is not
// (D lies inside the circumcircle of A, B, C: centre (1, 1.5167), radius 1.8167).
Mesh kite(bool delaunay_diagonal) {
  Mesh m;
  m.points = {{0, 0}, {1, -0.3}, {2, 0}, {1, 0.3}};
  if (delaunay_diagonal) {
    m.triangles = {{0, 1, 3}, {1, 2, 3}};
  } else {
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
  }
  m.boundary_edges = {{0, 1, 0}, {1, 2, 0}, {2, 3, 0}, {3, 0, 0}};
  m.curve_names = {"kite"};
  return m;
}

bool mentions(const CheckReport& r, const std::string& what) {
  for (const auto& p : r.problems)
    if (p.find(what) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST_CASE("check_mesh accepts a valid mesh", "[mesh]") {
  const auto report = check_mesh(kite(true), 0.6);
  INFO(report.summary());
  CHECK(report.ok());
  CHECK(report.summary() == "ok");
}

TEST_CASE("check_mesh finds a non-Delaunay edge", "[mesh]") {
  const auto report = check_mesh(kite(false), 0.6);
  CHECK_FALSE(report.ok());
  CHECK((mentions(report, "is not Delaunay: 3 (1, 0.3) lies inside the circumcircle of triangle 0") ||
         mentions(report, "is not Delaunay: 1 (1, -0.3) lies inside the circumcircle of triangle 1")));
  INFO(report.summary());
  CHECK(report.problems.size() == 1);
}

TEST_CASE("check_mesh finds a flipped triangle", "[mesh]") {
  Mesh m = kite(true);
  m.triangles[1] = {1, 3, 2};  // clockwise
  const auto report = check_mesh(m, 0.6);
  CHECK(mentions(report, "orientation: triangle 1"));
  CHECK(mentions(report, "topology"));  // edge 1-3 now traversed twice in one direction
  CHECK(mentions(report, "area"));
}

TEST_CASE("check_mesh finds missing and extra boundary edges", "[mesh]") {
  Mesh m = kite(true);
  m.boundary_edges.pop_back();  // edge 3-0 is on the mesh boundary but not declared
  auto report = check_mesh(m, 0.6);
  CHECK(mentions(report, "is on the mesh boundary but is no boundary edge"));
  m = kite(true);
  m.triangles.pop_back();  // boundary edges 1-2 and 2-3 no longer in the mesh
  report = check_mesh(m, 0.6);
  CHECK(mentions(report, "boundary edge 1 of curve 0 from 1 (1, -0.3) to 2 (2, 0) is not in the mesh"));
  CHECK(mentions(report, "area"));
  m = kite(true);
  m.boundary_edges.push_back({1, 3, 0});  // an interior edge declared as boundary
  report = check_mesh(m, 0.6);
  CHECK(mentions(report, "has triangles 0 and 1 on both sides"));
}

TEST_CASE("check_mesh finds duplicate triangles, bad indices and wrong area", "[mesh]") {
  Mesh m = kite(true);
  m.triangles.push_back({3, 0, 1});
  auto report = check_mesh(m);
  CHECK(mentions(report, "duplicate: triangle 2"));
  CHECK(mentions(report, "shared by 3 triangles"));
  m = kite(true);
  m.triangles.push_back({0, 1, 7});
  report = check_mesh(m);
  CHECK(mentions(report, "index: triangle 2"));
  report = check_mesh(kite(true), 0.61);
  CHECK(mentions(report, "area: triangle areas sum to 0.6"));
  CHECK_FALSE(check_mesh(kite(true), 0.6 * (1 + 1e-7)).ok());
  CHECK(check_mesh(kite(true), 0.6 * (1 + 1e-12)).ok());
}

TEST_CASE("check_mesh Euler check sees a pinched (non-disk) mesh", "[mesh]") {
  // Two triangles touching at one vertex: V=5, E=6, F=2 -> 1; components 2, boundary loops
  // counted 1 (the two loops share vertex 2), so 2*2-1 = 3 != 1.
  Mesh m;
  m.points = {{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}};
  m.triangles = {{0, 1, 2}, {2, 3, 4}};
  m.boundary_edges = {{0, 1, 0}, {1, 2, 0}, {2, 0, 0}, {2, 3, 1}, {3, 4, 1}, {4, 2, 1}};
  const auto report = check_mesh(m);
  CHECK(mentions(report, "euler"));
}
