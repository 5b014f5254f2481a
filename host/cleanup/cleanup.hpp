// The final cleanup after the last iteration (issue 12; docs/cleanup.md): repairs the triangles of
// the constrained Delaunay mesh whose smallest angle is below a target by hill-climbing node
// smoothing, Lawson flips and local topology operations (insertion at circumcentres and
// off-centres, edge collapse, edge split), each kept only when the worst angle it touches rises.
// Boundary nodes only slide along their own curve between their neighbours; critical (fixed) nodes
// never move; boundary nodes are never removed, and a boundary edge split puts its new node on the
// curve, so the boundary edges stay chords of their curves.
#pragma once
#include <cstddef>
#include <vector>

#include "geometry/geometry_tree.hpp"
#include "mesh/mesh.hpp"
#include "nodes/node_set.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

struct CleanupOptions {
  double min_angle = 30.0;  // target: triangles below this (degrees) are repaired
  int iterations = 16;      // outer iterations of {smoothing sweeps, topology pass} (JIGSAW's 16)
  double step_cap = 0.5;    // smoothing step <= step_cap x smallest adjacent inradius (optimesh)
  // Smoothing works on the vertices of triangles whose smallest angle is below this (degrees); above
  // the target so that the pass lifts the worst angles beyond it, as JIGSAW's optimiser does.
  // Defaults: min_angle + 20 and min_angle + 15 (at most 59), chosen from measurements on the thesis
  // cases (docs/cleanup.md); negative = the default.
  double smooth_below = -1.0;
  // The topology pass works on the triangles whose smallest angle is below this (degrees).
  double topology_below = -1.0;
  // The least gain of a sweep move (Smoother::set_sweep_gain): a rise of its star's smallest score
  // (sine of the smallest angle) above move_min_rise, or a drop of its mean aspect ratio above
  // move_aspect_drop. 0 and 0: any strict improvement counts.
  double move_min_rise = 0.0;
  double move_aspect_drop = 0.0;
  // Settling (0: off): the repairs end after an iteration (not the first) that made no topology
  // change, left the mesh's smallest angle where it was, lifted no triangle below the target (their
  // summed shortfall did not shrink) and lowered its mean aspect ratio by less than this. On a
  // settled lattice the sweeps go on moving tens of thousands of nodes per iteration for drops of
  // ~1e-6 each (docs/cleanup.md, "Settling").
  double settled_aspect_drop = 0.0;
  // Lifting climbs (Smoother::set_lift): a climb of a vertex of a triangle below the target +
  // lift_above (degrees; at most the topology limit) that no topology change could repair, or that no
  // topology pass will try again (above the target once the first trial budget is spent), is judged by
  // its star's smallest angle alone, so the mean aspect ratio may rise by what lifts it. Above the
  // target, so that the worst angles go on rising where the topology pass leaves them (docs/cleanup.md).
  bool lift = true;
  double lift_above = 4.0;
  bool topology = true;  // insertions, collapses and splits (off: smoothing and flips only)
  // Boundary edges may be split by a new node on their curve (off: the boundary nodes stay the
  // simulation's, they only slide).
  bool split_boundary = true;
  // Pairs of edits for a triangle below the target that no single edit repairs (docs/cleanup.md).
  bool compound = true;
  // Work bound of the topology passes: at most max(min_trials, trials_per_triangle x triangles)
  // trials in all, spent worst triangle first (the triangles below the target may spend a second
  // bound). A settled lattice needs far fewer (thesis cases: 0.07 to 0.7 per triangle); a mesh after
  // a few iterations would otherwise take several per triangle. Case keys cleanup.trials_per_triangle
  // and cleanup.min_trials.
  double trials_per_triangle = 0.5;
  double min_trials = 10000.0;
  // Sharp corners (EditableMesh::set_sharp_corners): a triangle that alone fills a domain corner
  // sharper than min_angle is scored by its other two angles, so the rows next to the corner can be
  // repaired. Off: every angle counts (pdmesh mesh's default); pdmesh smooth turns it on.
  bool sharp_corners = false;
  // Polishing sweeps after the repairs: every movable node (not only those of triangles below the
  // smoothing limit) proposes its ODT point and keeps it under the sweeps' rule (the star's smallest
  // score does not drop, its aspect-ratio sum does not rise, one of them strictly improves), until a
  // sweep moves nothing or this many sweeps. 0: none (pdmesh mesh's default).
  int polish = 0;
  // Sweeps in strips (cleanup/strip_sweeps.hpp): a mesh of at least kMinStrips x strip_vertices
  // vertices is cut into vertices / strip_vertices strips along x (at most kMaxStrips); with
  // small_strip_vertices > 0 a smaller one of at least kSmallStrips x small_strip_vertices vertices
  // into kSmallStrips strips, the fewest with which each colour has a strip for each of two threads.
  // Their sweeps run on up to `threads` threads (0: every hardware thread). The strips fix the order
  // of the moves, so the result is the same for any thread count; it differs from the serial sweeps'
  // (every vertex in ascending order), which smaller meshes keep (docs/cleanup.md, "Sweeps in
  // strips"). strip_vertices 0: serial sweeps always; small_strip_vertices 0 (the default, case key
  // cleanup.small_strip_vertices): serial sweeps below kMinStrips x strip_vertices.
  std::size_t strip_vertices = 25000;
  std::size_t small_strip_vertices = 0;
  std::size_t threads = 0;
  static constexpr std::size_t kMinStrips = 8;
  static constexpr int kMaxStrips = 64;
  static constexpr int kSmallStrips = 4;
  // Measure the whole mesh after every outer iteration (CleanupIteration's min_angle, aspect_mean): a
  // scan of every triangle per iteration, for bench_cleanup's per-iteration table; off in runs.
  bool measure_iterations = false;
};

// One outer iteration (bench_cleanup --per-iteration prints them).
struct CleanupIteration {
  std::size_t moves = 0;        // accepted node moves
  std::size_t small_moves = 0;  // ... of which lowered their star's mean aspect ratio by < 1e-4
  double aspect_drop = 0.0;     // sum over the moves of the drop of their star's aspect-ratio sum
  double small_aspect_drop = 0.0;
  std::size_t topology = 0;  // topology changes made
  std::size_t stuck = 0;     // triangles newly stuck below the lifting level (lifting climbs; docs/cleanup.md)
  std::size_t trials = 0;    // topology trials made ...
  std::size_t trials_to_last_change = 0;  // ... up to and with the one that made the last change
  double last_change_angle = 0.0;         // the smallest angle (degrees) of the triangle it repaired
  double smoothing_seconds = 0.0, topology_seconds = 0.0;
  double min_angle = 0.0, aspect_mean = 0.0;  // after it (degrees; measure_iterations only) ...
  double deficit = 0.0;                       // ... and the summed shortfall of the triangles below the target (sines)
};

struct CleanupStats {
  std::size_t moves = 0;             // accepted node moves
  std::size_t polish_moves = 0;      // of which in the polishing sweeps
  int polish_sweeps = 0;             // polishing sweeps made
  std::size_t inserted = 0;          // nodes inserted at circumcentres / off-centres / edge midpoints
  std::size_t collapsed = 0;         // interior nodes removed by edge collapse
  std::size_t rejected = 0;          // triangles no topology operation could repair
  std::size_t trials = 0;            // topology trials (edit, relaxation, score, undo) made
  std::size_t compound_trials = 0;   // of which pairs of edits (docs/cleanup.md) ...
  std::size_t compound_applied = 0;  // ... and pairs applied
  int iterations_run = 0;
  bool settled = false;  // the iterations ended by CleanupOptions::settled_aspect_drop
  double seconds = 0.0;
  int strips = 0;                  // strips of the sweeps (0: serial sweeps)
  std::size_t strip_taken = 0;     // vertices of the sweeps' lists the strips took ...
  std::size_t strip_left = 0;      // ... and left to the serial pass (over all sweeps)
  double strip_seconds = 0.0;      // wall seconds in the strips' parallel loops
  double smoothing_seconds = 0.0;  // of which in the smoothing sweeps ...
  double topology_seconds = 0.0;   // ... and in the topology passes
  // Where the wall time went (the --timings notes cleanup_*_seconds): the editable mesh and the strips
  // before the first iteration; the strips' serial pass (of smoothing_seconds); the sweeps' and the
  // topology passes' lists of bad vertices and triangles with the kept scores (of smoothing_seconds and
  // topology_seconds); the final Lawson pass and the cleaned mesh and node set after the last iteration.
  double setup_seconds = 0.0;
  double strip_serial_seconds = 0.0;
  double list_seconds = 0.0;
  double finish_seconds = 0.0;
  std::vector<CleanupIteration> per_iteration;
};

struct CleanupResult {
  Mesh mesh;      // the cleaned mesh (original nodes first, in order, less removed ones; new ones after)
  NodeSet nodes;  // its nodes, with kinds and the curve chains (for the area of --check)
  CleanupStats stats;
};

// Cleans the triangulation `mesh` of `nodes` (triangulate()'s output for them). `tree` gives the
// curves boundary nodes slide on; `spacing` the size h for the topology decisions.
// Deterministic: the same input gives bit-identical output.
CleanupResult clean_mesh(const Mesh& mesh, const NodeSet& nodes, const GeometryTree& tree, const SpacingField& spacing,
                         const CleanupOptions& options);

}  // namespace pdmesh
