// SpacingPipeline: validates the options, scales the base field, builds the base tree and, when
// anything modifies the field, the limited final field on it (docs/spacing.md, "The pipeline").
#include "spacing/spacing_pipeline.hpp"

#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "spacing/background_builder.hpp"
#include "spacing/limited_field.hpp"
#include "spacing/scaled_spacing.hpp"

namespace pdmesh {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

}  // namespace

void check_spacing_options(const SpacingOptions& o) {
  auto bad = [](const char* name, double value, const char* rule) {
    throw InputError(fmt::format("spacing.{} = {}: {}", name, value, rule));
  };
  if (!(o.scale > 0.0) || !std::isfinite(o.scale)) bad("scale", o.scale, "must be a positive number");
  if (!(o.gradation >= 0.0) || !std::isfinite(o.gradation))
    bad("gradation", o.gradation, "must be a number >= 0 (0 = off)");
  if (!(o.rows_in_gap == 0.0 || (o.rows_in_gap >= 1.0 && std::isfinite(o.rows_in_gap))))
    bad("rows_in_gap", o.rows_in_gap, "must be 0 (off) or a number >= 1");
  if (!(o.curvature_angle >= 0.0 && o.curvature_angle <= 90.0))
    bad("curvature_angle", o.curvature_angle, "must be in [0, 90] degrees (0 = off)");
  if (!(o.input_boundary_floor >= 0.0 && o.input_boundary_floor <= 1.0))
    bad("input_boundary_floor", o.input_boundary_floor, "must be in [0, 1]");
  for (const PointSource& p : o.points) {
    if (!(p.q > 0.0) || !std::isfinite(p.q) || !std::isfinite(p.p.x) || !std::isfinite(p.p.y))
      throw InputError(fmt::format("spacing point source at ({}, {}) with q = {}: needs finite coordinates and q > 0",
                                   p.p.x, p.p.y, p.q));
  }
  if (!o.points.empty() && !(o.gradation > 0.0))
    throw InputError("spacing point sources need spacing.gradation > 0 (they spread by the gradation limit)");
  check_background_options(o.background);
}

SpacingPipeline::SpacingPipeline(const SpacingField& base, const GeometryTree& tree, const SpacingOptions& options,
                                 BaseCheck check_base)
    : base_(base), tree_(tree), options_(options), check_base_(std::move(check_base)) {
  check_spacing_options(options_);
  if (options_.scale != 1.0) scaled_ = std::make_unique<ScaledSpacing>(base_, options_.scale);
  if (options_.modifies()) build();
}

SpacingPipeline::~SpacingPipeline() = default;

const SpacingField& SpacingPipeline::field() const {
  if (!options_.modifies()) return base_;
  return *background_;
}

const BackgroundSpacing& SpacingPipeline::background() const {
  if (!background_) const_cast<SpacingPipeline*>(this)->build();
  return *background_;
}

void SpacingPipeline::build() {
  const auto start = Clock::now();
  const SpacingField& scaled = scaled_ ? *scaled_ : base_;
  SizeSourceOptions so;
  so.rows_in_gap = options_.rows_in_gap;
  so.curvature_angle = options_.curvature_angle;
  so.input_boundary_floor = options_.input_boundary_floor;
  so.final_floor = options_.final_floor;
  so.scale = options_.scale;
  BackgroundBuilder builder(scaled, tree_, options_.background);
  builder.build();
  BackgroundStats bs;
  bs.exact_evaluations = builder.samples();
  bs.exact_batches = builder.batches();
  stats_.base_seconds = seconds_since(start);
  stats_.base_leaves = builder.leaves().size();
  BackgroundFieldData data;
  const bool limited = so.active() || options_.gradation > 0.0 || !options_.points.empty();
  std::unique_ptr<BackgroundSpacing> base_tree;
  if (limited || check_base_) base_tree = std::make_unique<BackgroundSpacing>(builder.emit(), BackgroundStats{});
  if (check_base_) check_base_(*base_tree);
  if (limited) {
    const SizeSources sources(tree_, so);
    // Refinement for the limited field reads the base field from the base tree (within its stated
    // tolerance) instead of evaluating it again: cheap, and a field backed by an interpreter is not
    // called after the base tree's batches.
    builder.sample_from(*base_tree);
    LimitedFieldStats ls;
    data = build_limited_field(builder, sources, options_.gradation, options_.points, ls);
    stats_.source_seconds = ls.source_seconds;
    stats_.limit_seconds = ls.limit_seconds;
    stats_.refine_seconds = ls.refine_seconds;
    stats_.rounds = ls.rounds;
    stats_.reduced_corners = ls.reduced_corners;
  } else {
    data = builder.emit();  // the base tree as it is (the thesis' background, or a scaled one)
  }
  background_ = std::make_unique<BackgroundSpacing>(std::move(data), bs);
  stats_.seconds = seconds_since(start);
}

}  // namespace pdmesh
