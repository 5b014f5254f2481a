// The far field: a closed curve named "farfield" around everything given (a circle or a square,
// centred on the input's bounding box), so that a body given alone becomes a hole in a flow domain,
// solid with what it encloses unless farfield.cavities = "mesh" (docs/geometry-input.md, "Far field").
#pragma once
#include <string>

#include "geometry/geometry.hpp"

namespace pdmesh {

enum class FarfieldShape { Circle, Box };

// What the far field does with the input's nested loops (farfield.cavities).
enum class FarfieldCavities {
  // The body is solid, with everything it encloses: the loops nested inside another input loop
  // (cavities, and islands inside them) and the hole points, embedded constraints, embedded points and
  // regions inside the body are left out; the domain is the region between the far field and the
  // body's outer loops.
  Solid,
  // Every loop is kept and the even-odd rule decides: the cavities are meshed too (the input's
  // holes become domain again), with the checks on hole points and constraints as given.
  Mesh,
};

// [farfield] / --farfield SHAPE:SIZE. size = 0: no far field.
struct Farfield {
  FarfieldShape shape = FarfieldShape::Circle;
  // The radius (circle) or half-width (box) in multiples of the input's largest extent,
  // max(bounding-box width, height).
  double size = 0.0;
  // Where it was given ("--farfield circle:20", "case.toml:7:8"), for messages and as the curve's file.
  std::string label;
  FarfieldCavities cavities = FarfieldCavities::Solid;
  bool given() const { return size > 0.0; }
};

// The name of the far field's curve (its physical group and marker in the outputs).
inline constexpr const char* kFarfieldName = "farfield";
// The most a circle's polygon may lie inside the circle, relative to its radius: the polygon's
// vertices are on the circle and its sagitta R (1 - cos(pi / n)) stays within this.
inline constexpr double kFarfieldRadiusTolerance = 1e-3;

// The fewest sides of a polygon within kFarfieldRadiusTolerance of its circle (71).
int farfield_min_sides();

// The far field's segment length: the circle's side at farfield_min_sides(), or shorter where the
// field graded from the body (mean segment length `body_spacing`, gradation limit `gradation`, 0 =
// off) is finer at the far field's distance from the bounding box, so that a far-field segment is
// not much longer than the spacing the field gives out there.
double farfield_segment_length(const Box& extents, const Farfield& farfield, double body_spacing, double gradation);

// The smallest size (in multiples of the largest extent) whose far field lies outside the bounding
// box `extents`, at segment length `segment`: a box's half-width must exceed half the largest extent
// (0.5), a circle's inscribed polygon must clear the box's corners (0.5 sqrt(w^2 + h^2) / max(w, h)
// over cos(pi / n), 0.7078 for a square at n = 71). A far field at this size or below is refused.
double farfield_min_size(const Box& extents, const Farfield& farfield, double segment);

// The far field's curve around `extents`: counter-clockwise, closed (last point = first), named
// kFarfieldName. InputError naming farfield.label and the size when the size is not above
// farfield_min_size.
RawCurve farfield_curve(const Box& extents, const Farfield& farfield, double body_spacing, double gradation);

// `body` with the far field added around its extents: its curves (flags, names and sources kept),
// hole points, embedded points and regions, and the far field's curve last, built again with
// `options`. With FarfieldCavities::Solid, what lies inside the body (the union of the interiors of
// its outermost loops, depth 0) is left out: the loops of depth >= 1, the embedded constraints and
// embedded points (all inside the body's domain, so inside it), and the hole points and regions
// whose point lies inside; one note per kind left out (Geometry::notes, after the body's) names the
// count and the first. Without nested loops, constraints, embedded points or regions inside, the
// result is the same for both modes. InputError when a curve of `body` is already named kFarfieldName.
Geometry with_farfield(const Geometry& body, const Farfield& farfield, double gradation,
                       const GeometryOptions& options);

}  // namespace pdmesh
