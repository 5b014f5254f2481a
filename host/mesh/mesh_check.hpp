// Invariant checker for triangle meshes (after Triangle's checkmesh/checkdelaunay): topology,
// orientation, constrained Delaunay and boundary conformity, all with the exact predicates.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace pdmesh {

struct CheckReport {
  std::vector<std::string> problems;  // each names the triangle/edge indices and coordinates
  bool ok() const { return problems.empty(); }
  std::string summary() const;  // all problems, one per line ("ok" when none)
};

// Checks: indices in range, no degenerate or duplicate triangles; every edge used by one
// triangle (boundary) or two with opposite orientation (interior); Euler characteristic
// V - E + F = 2C - B (C components, B boundary loops); every triangle counter-clockwise
// (orient2d > 0); every interior edge that is not a boundary edge locally Delaunay (incircle <= 0);
// the mesh's boundary edges are exactly Mesh::boundary_edges; total area equals domain_area
// within 1e-9 relative when given. Reports at most 50 problems of each kind.
CheckReport check_mesh(const Mesh& mesh, std::optional<double> domain_area = std::nullopt);

}  // namespace pdmesh
