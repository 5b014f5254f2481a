// Quality per region: a mesh with regional attributes (Mesh::region) measured region by region, each
// region's triangles by the same summary as the whole mesh, named as the mesh files name them.
#pragma once
#include "mesh/mesh.hpp"
#include "mesh/quality.hpp"

namespace pdmesh {

// Whether a mesh has regions: one attribute per triangle and either a nonzero attribute or a named one.
bool has_regions(const Mesh& mesh);

// Fills summary.regions for a mesh with regions (has_regions; otherwise leaves it empty): one entry per
// distinct attribute in ascending order, attribute 0 (outside every region) only where triangles have
// it, named by region_surfaces (io/mesh_io_common.hpp), measured by summarize_quality_of on the
// region's triangles with the options `summary` was made with (its small-angle threshold and histogram
// bins). When summary.has_spacing and `q` is given, each region's spacing conformance over the edges of
// its triangles (an edge between two regions counts in both).
void add_region_quality(const Mesh& mesh, QualitySummary& summary, const SpacingBatch& q = {});
void add_region_quality(const Mesh& mesh, QualitySummary& summary, const SpacingCallback& q);

}  // namespace pdmesh
