// Measures of a boundary layer (docs/boundary-layers.md): first height of the wall cells, growth
// along each ray and into the core, angles, fans, thickness jumps between neighbouring wall nodes.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "layers/boundary_layers.hpp"

namespace pdmesh {

struct LayerMeasures {
  int nodes = 0, cells = 0, quads = 0, triangles = 0;
  int wall_cells = 0;                   // cells with an edge on the wall
  double first_height_within_2pct = 0;  // share (0..1) of wall cells whose heights are all within +-2 %
  double first_height_max_error = 0;    // largest |height / h1 - 1| over the wall cells' apexes
  // Ratios of consecutive layer heights along every ray (inside), and with the core's spacing at
  // each top node over the last layer's height (the junction; none without a core spacing).
  double growth_median = 0, growth_p95 = 0, growth_max = 0;
  double junction_median = 0, junction_p95 = 0, junction_max = 0;
  double growth_with_junction_p95 = 0, growth_with_junction_max = 0;
  double max_angle_deg = 0;
  int angles_above_150 = 0;
  int inverted_cells = 0;  // cells with a corner whose orientation is not counter-clockwise (exact test)
  std::vector<int> fan_sizes;
  double max_thickness_jump = 1;      // largest thickness ratio of neighbouring wall nodes' rays
  std::vector<double> jump_by_curve;  // the same per geometry curve (1 where it has no neighbours)
  int max_layers = 0;
  double min_thickness = 0, max_thickness = 0;
};

// The angle measures of cells given by their corners (counter-clockwise; v[3] = -1 for a triangle):
// the counts by kind, the largest angle, the angles above 150 degrees and the inverted cells. One
// definition for the layers' measures below and for `pdmesh quality` on a mesh file with quads.
struct CellAngles {
  int cells = 0, quads = 0, triangles = 0;
  double max_angle_deg = 0;
  int angles_above_150 = 0;
  int inverted_cells = 0;  // cells with a corner whose orientation is not counter-clockwise (exact test)
};
void add_cell_angles(const std::vector<Vec2>& points, const std::array<int, 4>& v, CellAngles& out);

LayerMeasures measure_layers(const LayerMesh& mesh, double first_height, const CoreSpacing& core_spacing = {});

// The measures as aligned text lines (tools and reports); curve_names label jump_by_curve.
std::string format_layer_measures(const LayerMeasures& m, const std::vector<std::string>& curve_names = {});

}  // namespace pdmesh
