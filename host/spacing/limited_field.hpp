// The final field on the background quadtree: the base tree's corners take min(base, sources), the
// gradation limit runs over the corner graph, and the leaves are refined where the limited field needs
// it (size and interpolation error against the limited field), repeated until nothing splits.
#pragma once
#include <vector>

#include "spacing/background_builder.hpp"
#include "spacing/gradation.hpp"
#include "spacing/size_sources.hpp"

namespace pdmesh {

struct LimitedFieldStats {
  double source_seconds = 0.0;
  double limit_seconds = 0.0;
  double refine_seconds = 0.0;
  int rounds = 0;
  std::size_t reduced_corners = 0;  // corners whose final q is below the base field
};

// `builder` holds the base tree (BackgroundBuilder::build done) of the scaled base field. g: the
// gradation (0 = none); points: extra sizes at points (need g > 0). Returns the arrays to upload.
BackgroundFieldData build_limited_field(BackgroundBuilder& builder, const SizeSources& sources, double g,
                                        const std::vector<PointSource>& points, LimitedFieldStats& stats);

}  // namespace pdmesh
