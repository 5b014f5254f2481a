// Mesh quality metrics exactly as the thesis appendix defines them ("Overview of mesh quality
// metrics": included angle, aspect ratio R/(2r), skewness, weighted condition number, corner
// Jacobian), per triangle and summarised over a mesh, plus histograms and spacing conformance.
#pragma once
#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "mesh/metric_quality.hpp"
#include "core/vec2.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// The metrics of one triangle. Degenerate triangles (zero area) get +infinity for the
// unbounded ratios; an inverted (clockwise) triangle gets a negative min_jacobian.
struct TriangleQuality {
  double min_angle = 0.0;         // smallest included angle, degrees
  double max_angle = 0.0;         // largest included angle, degrees
  double aspect_ratio = 0.0;      // R / (2 r); 1 for equilateral
  double skewness = 0.0;          // longest edge / shortest edge; 1 for equilateral
  double condition_number = 0.0;  // weighted condition number K_W; 1 for equilateral
  double min_jacobian = 0.0;      // smallest corner Jacobian (sine of the corner angle); sqrt(3)/2 equilateral
};

// Weighted condition number K_W = ||A W^-1|| ||W A^-1|| / 2 (Frobenius norms) with
// A = [u v], u = b - a, v = c - a and W = [[1, 1/2], [0, sqrt(3)/2]], computed from vertex a
// as the appendix writes it. The value does not depend on the vertex (tests check this).
double weighted_condition_number(Vec2 a, Vec2 b, Vec2 c);

// Corner Jacobian at `corner`: (u/|u|) x (v/|v|) with u = next - corner, v = prev - corner.
// For a counter-clockwise triangle (corner, next, prev) it is the sine of the corner angle.
double corner_jacobian(Vec2 corner, Vec2 next, Vec2 prev);

// All metrics of triangle (a, b, c); a, b, c in counter-clockwise order for positive Jacobians.
TriangleQuality triangle_quality(Vec2 a, Vec2 b, Vec2 c);

// The two metrics the stopping rule follows (sim/convergence.hpp), without the others' cost: equal
// to triangle_quality's min_angle and aspect_ratio bit for bit.
struct TriangleShape {
  double min_angle = 0.0;     // degrees
  double aspect_ratio = 0.0;  // R / (2 r)
};
TriangleShape triangle_shape(Vec2 a, Vec2 b, Vec2 c);

// Per-triangle metrics of a whole mesh, in triangle order.
std::vector<TriangleQuality> triangle_qualities(const Mesh& mesh);

// The per-triangle values of one metric by name (min_angle, max_angle, aspect_ratio, skewness,
// condition_number, min_jacobian), for colouring mesh pictures. Throws InputError for other names.
std::vector<double> metric_values(const std::vector<TriangleQuality>& q, const std::string& metric);

// Fixed-width bins [lo + k*width, lo + (k+1)*width) for k < bins; values below lo count in the
// first bin and values at or above the last edge count in `overflow` (shown as ">= edge").
struct Histogram {
  double lo = 0.0;
  double width = 1.0;
  std::vector<std::size_t> counts;
  std::size_t overflow = 0;
  void add(double value);
  double edge(std::size_t k) const { return lo + width * static_cast<double>(k); }
};

// Edge length / q(edge midpoint) over every unique mesh edge.
struct SpacingConformance {
  std::size_t edges = 0;
  double mean = 0.0;
  double stddev = 0.0;  // population standard deviation
  double p05 = 0.0;     // 5th percentile
  double p95 = 0.0;     // 95th percentile
  double min = 0.0;
  double max = 0.0;
};

struct QualityOptions {
  double small_angle_deg = 30.0;  // triangles whose min angle is below this count as "small angle"
  double angle_bin_width = 5.0;   // min-angle histogram: bins of this width from 0 up to 60 degrees
  double aspect_bin_width = 0.1;  // aspect-ratio histogram: bins from 1 ...
  int aspect_bins = 10;           // ... this many, then an overflow bin
};

// What the final cleanup (docs/cleanup.md) did to a mesh: triangles below its target angle and the
// smallest angle before and after, and the nodes it added and removed.
struct CleanupEffect {
  double target_deg = 30.0;
  std::size_t below_before = 0, below_after = 0;  // triangles whose min angle < target_deg
  double min_angle_before = 0.0, min_angle_after = 0.0;
  double max_angle_before = 0.0, max_angle_after = 0.0;
  std::size_t triangles_before = 0, points_before = 0;
  std::size_t inserted = 0, removed = 0, moves = 0;
  double seconds = 0.0;  // printed on stderr only: quality.json stays identical across runs
};

struct RegionQuality;

// Summary over a mesh: the rows of thesis tables 6.2-6.6 and our extra rows.
struct QualitySummary {
  std::size_t triangles = 0;
  std::size_t points = 0;
  double min_angle = 0.0;  // minimum included angle over the mesh, degrees
  double max_angle = 0.0;  // maximum included angle over the mesh, degrees
  double aspect_ratio_avg = 0.0, aspect_ratio_max = 0.0;
  double skewness_avg = 0.0, skewness_max = 0.0;
  double condition_number_avg = 0.0, condition_number_max = 0.0;
  double min_jacobian = 0.0;              // minimum corner Jacobian over all corners
  std::size_t small_angle_triangles = 0;  // min angle < options.small_angle_deg
  double small_angle_share = 0.0;         // small_angle_triangles / triangles
  double small_angle_deg = 30.0;
  Histogram min_angle_histogram;
  Histogram aspect_ratio_histogram;
  bool has_spacing = false;  // spacing conformance computed (a q callback was given)
  SpacingConformance spacing;
  bool has_cleanup = false;  // the mesh is the output of the final cleanup, which `cleanup` describes
  CleanupEffect cleanup;
  bool has_metric = false;  // measured in a metric field (mesh/metric_quality), which `metric` holds
  MetricQualitySummary metric;
  // The embedded constraint curves (Mesh::constraint_curves), each with its number of mesh edges.
  std::vector<std::pair<std::string, std::size_t>> constraints;
  // Per regional attribute of a mesh with regions (io/region_quality.hpp), ascending; empty otherwise.
  std::vector<RegionQuality> regions;
};

// The summary of one region's triangles: the figures summarize_quality gives a mesh, measured on the
// region's triangles and the points they use (no constraints, cleanup, metric or nested regions). Its
// spacing conformance counts every edge of the region's triangles, so an interface edge counts in
// both regions it separates.
struct RegionQuality {
  double attribute = 0.0;
  std::string name;  // as the mesh files name the region (io's region_label)
  QualitySummary quality;
};

using SpacingCallback = std::function<double(Vec2)>;

// Fills summary.constraints from the mesh's embedded constraint curves (none: left empty).
void list_constraints(const Mesh& mesh, QualitySummary& summary);

// Summarises a mesh. `q` is the desired spacing; when empty, spacing conformance is skipped.
// An empty mesh gives a summary with zero counts and zero values.
QualitySummary summarize_quality(const Mesh& mesh, const SpacingCallback& q = {}, const QualityOptions& options = {});
// The same from precomputed per-triangle metrics (no spacing conformance).
QualitySummary summarize_quality(const std::vector<TriangleQuality>& per_triangle, const QualityOptions& options = {});

// q at many points at once (SpacingField::at_many, which may use threads).
using SpacingBatch = std::function<void(const std::vector<Vec2>& points, std::vector<double>& q)>;

// Spacing conformance of the unique edges of `mesh` against q. Throws InputError when q is not
// finite and positive at an edge midpoint (naming the edge and the midpoint). Linear in the mesh:
// each edge is found once without a hash set, and q is asked for all midpoints in one batch.
SpacingConformance spacing_conformance(const Mesh& mesh, const SpacingBatch& q);
SpacingConformance spacing_conformance(const Mesh& mesh, const SpacingCallback& q);

// The unique undirected edges of the mesh's triangles, each once, as point index pairs: an edge
// i -> j of a counter-clockwise triangle with i < j, or with i > j when no triangle has j -> i (an
// edge of the mesh's outline). Compressed rows of the directed edges, no hash set.
std::vector<std::pair<int, int>> unique_edges(const Mesh& mesh);

// Percentile p in [0, 1] by linear interpolation between closest ranks (position p * (n - 1) in
// the sorted values; numpy's default). `sorted` must be ascending and non-empty.
double percentile_sorted(const std::vector<double>& sorted, double p);

}  // namespace pdmesh
