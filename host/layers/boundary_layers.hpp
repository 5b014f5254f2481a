// Boundary layers for viscous flow: layered cells advanced from wall curves along smoothed normals
// (docs/boundary-layers.md). The input is the geometry and the wall curves (their polyline points,
// which are the boundary nodes of the thesis' rule); the output is the layer nodes and cells and the
// outer front, the boundary the particle core is to fill from.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/vec2.hpp"
#include "geometry/geometry.hpp"

namespace pdmesh {

struct LayerSettings {
  double first_height = 0.0;  // h1, the height of the wall cells
  double growth = 1.2;        // g > 1, the ratio of consecutive layer heights
  double thickness = 0.0;     // the layer's total height where nothing else limits it (or `layers`)
  int layers = 0;             // the number of layers where nothing else limits it (0: use thickness)
  // A wall vertex whose convex turn exceeds this (degrees) gets a fan of rays.
  double fan_angle_deg = 45.0;
  double fan_elements_per_pi = 5.0;  // a fan's elements: ceil(this x turn / pi), at least 2
  int smoothing_passes = 8;          // Laplacian passes over the normals (not at fans)
  // The largest angle (degrees) between a ray and the normals of its two wall segments; 0: none
  // beyond the smoothing's own limits. A thin wall cell whose side ray is tilted by a from its
  // segment's normal has an angle of 90 + a, and so has either half of its split (the pipeline
  // sets it with split quads). A convex vertex turning by more than twice this gets a fan (rays
  // along both segments' normals) and the smoothing keeps every other ray within this of both
  // normals. Must be in [0, 45).
  double max_ray_tilt_deg = 0.0;
  double max_jump = 1.3;  // largest thickness ratio between neighbouring wall nodes
  // Largest change of thickness per unit distance between neighbouring rays (their wall nodes'
  // distance plus the arc between their directions at the thinner one's height): the front's slope
  // against the wall, so that dense wall nodes do not let the front drop along the rays.
  double max_slope = 0.3;
  // A ray that meets another curve at distance L stops at gap_fraction x L (the front opposite
  // stops there too, leaving (1 - 2 gap_fraction) L to the core): a curve without layers where the
  // free layer reaches it, a wall of these layers up to the free thickness over gap_fraction. Rays
  // that cross stop at cross_fraction of the crossing distance.
  double gap_fraction = 0.4;
  double cross_fraction = 0.5;
  // Where fronts close in, a ray that meets a curve keeps at least core_room x its front edge
  // between its front and the facing one (the layer ends where the gap is narrower): a core strip
  // narrower than the edges it lies between holds only slivers. 0: no such limit (an anisotropic
  // core under a metric field, whose thin rows are what the metric asks for).
  double core_room = 1.0;
  bool split_quads = false;  // write each quad as 2 triangles (the diagonal with the smaller max angle)
  // Columns merge where the rays are dense for their layers' height: a ray's column ends at layer k
  // (its two neighbours close over it with three triangles) where the span between its neighbours'
  // nodes there is at most merge_span x the next layer's height, so that the front's node spacing
  // follows the last layer's height (the core's spacing there) instead of the wall's. 0: never.
  double merge_span = 1.2;
  // The wall is refined where the rays diverge: a wall segment whose rays' top nodes would be more
  // than split_span x the last layer's height apart is split into equal parts (nodes on the
  // segment) that are not (a leading edge's nose). 0: never.
  double split_span = 1.6;
};

// Throws InputError naming the setting and its value: h1 <= 0 or not finite, growth <= 1, neither
// or both of thickness and layers, first height above the thickness, bad fan or jump settings.
void check_layer_settings(const LayerSettings& settings);

// The spacing the isotropic core asks for at a point (the spacing field's q). Layers stop where the
// last layer's height reaches core_spacing / growth, so that the growth into the core is no larger
// than inside the layer. May be empty (no such limit).
using CoreSpacing = std::function<double(Vec2)>;

enum class LayerCellKind : unsigned char { Quad, Fan, Transition, Split };

struct LayerCell {
  std::array<int, 4> v{-1, -1, -1, -1};  // counter-clockwise node indices; v[3] = -1 for a triangle
  LayerCellKind kind = LayerCellKind::Quad;
  int curve = -1;  // the geometry curve of the wall node the cell grows from
  int layer = 0;   // 0 = on the wall
  bool triangle() const { return v[3] < 0; }
};

// One ray of nodes grown from a wall node (a fan corner has several rays from one wall node).
struct LayerRay {
  int wall_node = -1;           // index into LayerMesh::nodes
  int curve = -1;               // the geometry curve of the wall node (the one before it at a joint)
  Vec2 direction;               // unit
  double correction = 1.0;      // mean of direction . (normals of the adjacent wall segments)
  std::vector<int> nodes;       // nodes[0] = wall_node, then one per layer
  double thickness = 0.0;       // height of its top node over the wall (along the normal)
  double last_growth = 1.0;     // the last layer's height over the one below (the others: settings.growth)
  double free_thickness = 0.0;  // what it would have had with no collision
  bool fan = false;
  // Its column ends below the front (merge_span): its nodes stop at a layer where its neighbours'
  // columns close over it; `thickness` stays the height it would have had.
  bool merged = false;
  // At the end of an open chain: the geometry segment (of the curve that continues the boundary
  // there) that the ray runs along, so that the layer's side lies on that curve; -1 otherwise.
  int slide_segment = -1;
};

// The outer front of one wall chain: the boundary between the layer and the core. A closed chain's
// front is closed (the top nodes of the rays not merged); an open chain's front runs from its first wall node up the
// first ray, along the top nodes and down the last ray to its last wall node.
struct LayerFront {
  std::vector<int> nodes;
  bool closed = false;
};

struct LayerMesh {
  std::vector<Vec2> nodes;  // wall nodes first (nodes[i] for i < wall_nodes), then layer nodes
  int wall_nodes = 0;
  std::vector<LayerCell> cells;
  std::vector<LayerRay> rays;              // in chain order, chain after chain
  std::vector<int> chain_ray_begin;        // chain c's rays are [chain_ray_begin[c], chain_ray_begin[c+1])
  std::vector<std::uint8_t> chain_closed;  // per chain
  std::vector<LayerFront> fronts;          // one per chain
  std::vector<int> fan_sizes;              // elements per layer of each fan
  int repairs = 0;                         // rounds of shrinking that the final checks needed
};

// Two open chain ends whose end rays must have the same layers (the two ends of a periodic
// channel's wall, docs/geometry-input.md "Periodic curves"): the wall nodes they start from.
struct TiedEnds {
  Vec2 a, b;
};

// Advances layers from the named wall curves of `geometry` (indices into geometry.curves) into the
// domain. Curves that join end to end form one chain; a loop made only of wall curves is a closed
// chain. Every curve of the geometry stops the layers (gap_fraction). The end rays of each pair of
// `tied` ends get the smaller of their two thicknesses (so the same layer heights). Throws InputError
// for bad settings or an empty or out-of-range curve list; throws Error when no valid layer can be
// made or a tied wall node is not an open chain's end.
LayerMesh build_boundary_layers(const Geometry& geometry, const std::vector<int>& wall_curves,
                                const LayerSettings& settings, const CoreSpacing& core_spacing = {},
                                const std::vector<TiedEnds>& tied = {});

// The ray of `layers` that starts an open chain at wall node position p (its first or last ray), -1
// when no open chain ends there.
int end_ray_at(const LayerMesh& layers, Vec2 p);

// Fan elements per pi whose top edges match the core there: a fan of thickness t turning by theta
// has a top arc of theta t, and the core continuing its growth wants about growth x the last layer,
// (g - 1) t for a stack of growth g, so theta / (g - 1) elements; never fewer than `at_least` per pi.
double fan_elements_matching_core(double growth, double at_least = 5.0);

// The curve indices of the given names, a group's name (Geometry::groups) standing for every curve of
// the group; InputError naming an unknown one (and `what`, e.g. the key).
std::vector<int> curves_by_name(const Geometry& geometry, const std::vector<std::string>& names,
                                const std::string& what);

}  // namespace pdmesh
