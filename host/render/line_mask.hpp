// Thin lines of one colour (a mesh's edges) rasterised by pdmesh into a coverage mask that paint()
// fills with the colour in one cairo call. cairo strokes a segment in ~1.5 us (its stroker, then its
// scan converter at 256 x 15 samples a pixel), most of a 1600 px mesh picture's time; here a pixel
// near a segment is covered by the share of its area within the line's half width across the line
// times the share within the segment's ends along it (each the pixel's area projected onto that
// direction; the ends lengthened so that the line has the area of a segment with round ends, as
// cairo's round caps): exact for a line along the pixel grid, within a few per cent of cairo's
// coverage otherwise. Where lines meet or cross, coverages combine as 1 - (1 - a)(1 - b) (the
// union's expected coverage): crossings and dense parts as dark as cairo draws them, the lines'
// order immaterial. A PNG canvas only (Canvas::raster); a band covers its own rows, so a picture
// drawn in bands is pixel for pixel the picture of one canvas.
#pragma once
#include <exception>
#include <vector>

#include "core/vec2.hpp"
#include "render/canvas.hpp"

namespace pdmesh {

class LineMask {
 public:
  // `width_px` > 0 (made for lines of about a pixel: at several pixels cairo's stroke costs little
  // more than the mask).
  LineMask(Canvas& canvas, Rgb colour, double width_px);
  ~LineMask() {
    if (std::uncaught_exceptions() == 0) paint();
  }
  LineMask(const LineMask&) = delete;
  LineMask& operator=(const LineMask&) = delete;
  void segment(Vec2 a, Vec2 b);  // world coordinates
  void paint();                  // fills the covered pixels and clears the mask

 private:
  void cover(int x, int y, float coverage);  // picture pixel (x, y); nothing outside this canvas

  Canvas& canvas_;
  Rgb colour_;
  float half_width_;
  int width_ = 0;
  int first_row_ = 0;
  int rows_ = 0;
  int stride_ = 0;
  std::vector<unsigned char> alpha_;  // cairo A8 rows, this canvas' rows
  bool any_ = false;
};

}  // namespace pdmesh
