// Lifting climbs of the final cleanup (docs/cleanup.md, "Lifting climbs"): a node of a triangle below
// the target moves when that raises its star's smallest angle, even if the star's aspect-ratio sum
// rises, which the ordinary move rule refuses.
#include <catch2/catch.hpp>

#include <vector>

#include "cleanup/cleanup.hpp"
#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "mesh/mesh_check.hpp"
#include "mesh/quality.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "nodes/node_domain.hpp"
#include "spacing/spacing_field.hpp"

using namespace pdmesh;

TEST_CASE("a lifting climb raises a star's smallest angle that only an aspect-ratio rise can raise", "[cleanup]") {
  // The star of the interior node of clarky's worst triangle after the best preset's cleanup (39.48
  // degrees, far-field node at (19.687, 5.631) above the interior row; coordinates less (17, 5)): the
  // ring is fixed (every corner turns by more than 30 degrees), so only the centre node can move. The
  // position with the largest smallest angle (41.0 degrees) stretches the star's 50-56 degree
  // triangles and raises its aspect-ratio sum; without that rise the star reaches 39.56 at most.
  RawCurve ring;
  ring.name = "ring";
  ring.file = "test";
  ring.points = {{-0.4015, -0.3878}, {0.4167, -1.0575}, {1.7659, -0.9118}, {2.6866, 0.6306},
                 {0.8248, 1.4174},   {-0.3358, 0.7177}, {-0.4015, -0.3878}};
  const Geometry g = build_geometry({ring});
  const GeometryTree tree(g);
  const ExpressionSpacing spacing("10");
  NodeSet nodes = make_boundary_nodes(g, spacing);
  REQUIRE(nodes.size() == 6);
  REQUIRE(nodes.count(NodeKind::Fixed) == 6);
  nodes.add({0.7657, 0.0590}, 1.4, NodeKind::Interior, -1);
  const Mesh mesh = triangulate(nodes, {"ring"});
  REQUIRE(mesh.triangles.size() == 6);
  const QualitySummary before = summarize_quality(mesh);
  REQUIRE(before.min_angle < 39.5);

  CleanupOptions options;
  options.min_angle = 40.0;
  CleanupOptions plain = options;
  plain.lift = false;
  const QualitySummary without = summarize_quality(clean_mesh(mesh, nodes, tree, spacing, plain).mesh);
  CHECK(without.min_angle < 39.6);
  CHECK(without.aspect_ratio_avg <= before.aspect_ratio_avg);

  const CleanupResult lifted = clean_mesh(mesh, nodes, tree, spacing, options);
  const QualitySummary with = summarize_quality(lifted.mesh);
  const CheckReport check = check_mesh(lifted.mesh, node_domain_area(lifted.nodes, g));
  INFO(check.summary());
  CHECK(check.ok());
  CHECK(with.min_angle >= 40.0);
  CHECK(with.aspect_ratio_avg > without.aspect_ratio_avg);  // what the ordinary rule refuses
  CHECK(lifted.mesh.triangles.size() == 6);
}
