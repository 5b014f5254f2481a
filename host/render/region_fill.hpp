// A mesh picture's regions (Mesh::region): a categorical, colour-blind-safe palette, the legend of the
// regions' names and colours, the triangles filled by region, and the edges between regions.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "mesh/mesh.hpp"
#include "render/canvas.hpp"
#include "render/fill_groups.hpp"

namespace pdmesh {

// The triangles outside every region (attribute 0), and all of a mesh without regions.
inline constexpr Rgb kNoRegion{0.8, 0.8, 0.8};

// Okabe and Ito's colour-blind-safe palette without its black (the edges' colour): orange, sky blue,
// bluish green, yellow, blue, vermillion, reddish purple. Region k (0-based, in ascending attribute
// order) gets colour k modulo the palette's size.
std::size_t region_palette_size();
Rgb region_palette_colour(std::size_t k);

struct RegionLegendEntry {
  double attribute = 0.0;  // 0: the "no region" entry
  std::string label;       // the name in Mesh::region_names, "attribute N" where none, "no region" for 0
  Rgb colour;
  std::size_t triangles = 0;
};

// The legend of a mesh's regions and each triangle's entry in it. Entries: the nonzero finite
// attributes of Mesh::region in ascending order (palette colours 0, 1, ...), then "no region" when
// a triangle has attribute 0 (or a non-finite one) or the mesh has no regions (Mesh::region empty).
// `groups` has one group per entry, in the entry's colour, for draw_fill_groups.
struct RegionFill {
  std::vector<RegionLegendEntry> entries;
  FillGroups groups;
  bool has_regions() const { return entries.size() > 1 || (entries.size() == 1 && entries[0].attribute != 0.0); }
};
// Throws Error when Mesh::region is neither empty nor one attribute per triangle.
RegionFill region_fill(const Mesh& mesh);

// The edges (point pairs, the lower index first, ascending) between two triangles of different
// attributes in Mesh::region that are not boundary edges (those a picture draws thick already):
// the interfaces of regions whose common curve is not a constraint of the mesh, e.g. those of a mesh
// file's physical surfaces. Empty for a mesh with one region or none.
std::vector<std::pair<int, int>> region_interfaces(const Mesh& mesh);

// The side band's width for the legend: its longest label at the legend's font size, and the swatch.
int region_legend_width(const RegionFill& fill);
// The legend in the canvas' side band: a "region" caption, then a colour swatch and label per entry,
// as many as fit the plot's height (the last row then says how many more there are).
void draw_region_legend(Canvas& canvas, const RegionFill& fill);

}  // namespace pdmesh
