// The generated benchmark case of `pdmesh bench` (app/bench/graded_case): its initial distribution has
// the node count the fit promises, so "graded_1m" really has about a million nodes.
#include <catch2/catch.hpp>

#include <cmath>

#include "app/bench/graded_case.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "spacing/spacing_field.hpp"

namespace {

std::size_t initial_nodes(std::size_t target) {
  const pdmesh::Geometry geometry = pdmesh::graded_case_geometry(pdmesh::graded_case_spacing(target));
  const pdmesh::GeometryTree tree(geometry);
  const pdmesh::BoundarySpacing spacing(tree);
  return pdmesh::make_initial_distribution(tree, spacing, {}).nodes.size();
}

}  // namespace

TEST_CASE("bench graded case: spacing inverts the node estimate", "[bench]") {
  for (std::size_t target : {1UL, 999UL, 10'000UL, 1'000'000UL, 5'000'000UL}) {
    const double h = pdmesh::graded_case_spacing(target);
    REQUIRE(h > 0.0);
    CHECK(pdmesh::graded_case_node_estimate(h) == Approx(static_cast<double>(target)).epsilon(1e-9));
  }
  // Coarser spacing, fewer nodes.
  CHECK(pdmesh::graded_case_spacing(20'000) > pdmesh::graded_case_spacing(1'000'000));
}

TEST_CASE("bench graded case: the initial distribution has the requested node count", "[bench]") {
  // 1M nodes take a minute to place; the fit's terms are checked at two sizes where each dominates
  // differently (the 1/h term is ~10% of the count at 25k, ~6% at 60k, ~2% at 1M); below ~20k nodes the fit overshoots.
  for (std::size_t target : {25'000UL, 60'000UL}) {
    const std::size_t n = initial_nodes(target);
    INFO("target " << target << ", nodes " << n);
    CHECK(std::abs(static_cast<double>(n) / static_cast<double>(target) - 1.0) < 0.03);
  }
}
