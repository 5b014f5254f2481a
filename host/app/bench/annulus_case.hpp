// The generated whole-run benchmark case `annulus_<N>` (pdmesh bench --whole-run, docs/performance.md):
// an annulus of radii 1 and 10 whose boundary segments are 20x longer on the outer circle than on the
// inner one, sized so that eq. 3.6's hexagonal-packing estimate is about N nodes. Written as ordinary
// geometry files and a case file, so that the `mesh` command (and Gmsh) can read it.
#pragma once
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "geometry/geometry.hpp"

namespace pdmesh {

inline constexpr double kAnnulusInnerRadius = 1.0;
inline constexpr double kAnnulusOuterRadius = 10.0;
inline constexpr double kAnnulusSpacingRatio = 20.0;  // outer segment length / inner segment length

// Eq. 3.6's hexagonal-packing estimate for inner segment length h: between two concentric circles the
// closest-segment weights make q linear in the radius, so the count is C / h^2 with C the integral of
// 2 / (sqrt(3) q^2) over the annulus at h = 1 (computed once, by the midpoint rule).
double annulus_node_estimate(double inner_spacing);
// The inner segment length whose estimate is `target` nodes.
double annulus_inner_spacing(std::size_t target);

// The two closed circles (inner first), each a closed polyline.
std::vector<RawCurve> annulus_curves(std::size_t target);

// "annulus_4m" -> 4'000'000, "annulus_250k" -> 250'000, "annulus_1200" -> 1200; nullopt for other names.
std::optional<std::size_t> annulus_target(const std::string& name);

// Writes DIR/inner.crv, DIR/outer.crv and DIR/case.toml (name `name`, no other keys: the best
// defaults) atomically; creates DIR. Returns the case file.
std::filesystem::path write_annulus_case(const std::filesystem::path& dir, const std::string& name, std::size_t target);

}  // namespace pdmesh
