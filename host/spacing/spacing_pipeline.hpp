// The spacing pipeline: base field (eq. 3.6, an expression, data) x scale -> min with the size
// sources (feature size, curvature) -> gradation limit -> the final field, built once per run as the
// background quadtree that the initialization, both simulation backends, quality and pictures read.
#pragma once
#include <functional>
#include <memory>
#include <vector>

#include "geometry/geometry_tree.hpp"
#include "spacing/background_field.hpp"
#include "spacing/gradation.hpp"
#include "spacing/size_sources.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

// While boundary nodes are the input points, the sources ask for no less than this fraction of the
// closest input segment's length (Gmsh's floor; measured in docs/spacing.md, "Input boundary points").
inline constexpr double kInputBoundaryFloor = 1.0;

struct SpacingOptions {
  double scale = 1.0;                 // spacing.scale: multiplies the base field and the sources
  double gradation = 0.0;             // spacing.gradation g: |grad q| <= g; 0 = off
  double rows_in_gap = 0.0;           // spacing.rows_in_gap k; 0 = off
  double curvature_angle = 0.0;       // spacing.curvature_angle theta in degrees; 0 = off
  double input_boundary_floor = 0.0;  // SizeSourceOptions::input_boundary_floor
  bool final_floor = true;            // SizeSourceOptions::final_floor
  std::vector<PointSource> points;    // sizes at points, limited like the rest (API and tests)
  BackgroundOptions background;
  // False for the thesis' field exactly (all of the above off and scale 1): then the final field is the
  // base field itself, evaluated exactly, and the background is only the simulation's lookup table.
  bool modifies() const {
    return scale != 1.0 || gradation > 0.0 || rows_in_gap > 0.0 || curvature_angle > 0.0 || !points.empty();
  }
};

struct SpacingStats {
  double seconds = 0.0;         // the whole build
  double base_seconds = 0.0;    // the base tree (exact base field samples)
  double source_seconds = 0.0;  // feature size and curvature at the corners
  double limit_seconds = 0.0;   // gradation sweeps
  double refine_seconds = 0.0;  // refinement where the limited field needs it
  int rounds = 0;               // limit-refine rounds
  std::size_t base_leaves = 0;
  std::size_t reduced_corners = 0;  // corners where the final q is below the scaled base field
};

class SpacingPipeline {
 public:
  // Keeps references to base and tree, which must outlive it. Throws InputError on invalid options.
  // Builds the background at once when the options modify the field, else on first background() call.
  // check_base (if set) sees the scaled base field's quadtree before any source or limit is applied
  // (the sources only lower q: a node-count limit can refuse the case there, cheaply).
  using BaseCheck = std::function<void(const BackgroundSpacing& base_tree)>;
  SpacingPipeline(const SpacingField& base, const GeometryTree& tree, const SpacingOptions& options,
                  BaseCheck check_base = {});
  ~SpacingPipeline();
  SpacingPipeline(const SpacingPipeline&) = delete;
  SpacingPipeline& operator=(const SpacingPipeline&) = delete;

  // The final field: the base field when !options.modifies() (bit-identical to the thesis), else the
  // background quadtree. const; thread-safe as the base field is when exact.
  const SpacingField& field() const;
  // The final field's quadtree, as the simulation (host and device) samples it. Not thread-safe on its
  // first call in the exact case, which builds it.
  const BackgroundSpacing& background() const;
  bool exact() const { return !options_.modifies(); }
  const SpacingOptions& options() const { return options_; }
  const SpacingStats& stats() const { return stats_; }

 private:
  void build();

  const SpacingField& base_;
  const GeometryTree& tree_;
  SpacingOptions options_;
  BaseCheck check_base_;
  std::unique_ptr<SpacingField> scaled_;  // base x scale, when scale != 1
  mutable std::unique_ptr<BackgroundSpacing> background_;
  SpacingStats stats_;
};

// Throws InputError naming the first invalid option.
void check_spacing_options(const SpacingOptions& options);

}  // namespace pdmesh
