// Triangles filled in a few colours (a mesh picture's regions, or its values on a colour ramp's
// levels), grouped by colour so that each colour is one FillBatch: one path filled for thousands of
// triangles instead of a fill per triangle.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mesh/mesh.hpp"
#include "render/canvas.hpp"

namespace pdmesh {

struct FillGroups {
  std::vector<Rgb> colours;          // one per group
  std::vector<std::uint32_t> order;  // the triangles group by group, in mesh order within a group
  std::vector<std::size_t> ends;     // each group's end in `order`
  std::size_t count(std::size_t g) const { return ends[g] - (g == 0 ? 0 : ends[g - 1]); }
};

// `group_of[t]` is triangle t's group, below colours.size(); a counting sort into `order`.
FillGroups group_fills(const std::vector<std::uint32_t>& group_of, std::vector<Rgb> colours);

// Fills each visible triangle in its group's colour, one FillBatch per group (a band skips the
// others' triangles as the whole picture does, so banded pictures are one canvas' picture).
// `close_seams`: FillBatch's hairline where a group's batches meet.
void draw_fill_groups(Canvas& canvas, const Mesh& mesh, const FillGroups& groups, bool close_seams = true);

// The groups filled twice: first without anti-aliasing, each pixel in the colour of the triangle
// that holds its centre, which tiles the mesh without gaps; then anti-aliased on top, so that edges
// are smooth and a triangle smaller than a pixel tints it by its coverage. Where two colours meet,
// the anti-aliased fills blend over one of them instead of over the paper: no seams, and no
// hairline strokes to close them.
void draw_fill_groups_seamless(Canvas& canvas, const Mesh& mesh, const FillGroups& groups);

}  // namespace pdmesh
