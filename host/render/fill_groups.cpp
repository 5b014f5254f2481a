// Triangles grouped by fill colour, and their drawing one batch per colour.
#include "render/fill_groups.hpp"

#include "core/interrupt.hpp"

namespace pdmesh {

FillGroups group_fills(const std::vector<std::uint32_t>& group_of, std::vector<Rgb> colours) {
  FillGroups groups;
  groups.colours = std::move(colours);
  const std::size_t n = groups.colours.size();
  std::vector<std::size_t> next(n, 0);
  for (std::uint32_t g : group_of) ++next[g];
  // Counts to starts, and each group's end.
  std::size_t start = 0;
  groups.ends.resize(n);
  for (std::size_t g = 0; g < n; ++g) {
    const std::size_t count = next[g];
    next[g] = start;
    start += count;
    groups.ends[g] = start;
  }
  groups.order.resize(group_of.size());
  for (std::size_t t = 0; t < group_of.size(); ++t) groups.order[next[group_of[t]]++] = static_cast<std::uint32_t>(t);
  return groups;
}

void draw_fill_groups(Canvas& canvas, const Mesh& mesh, const FillGroups& groups, bool close_seams) {
  InterruptPoll poll(65536);
  std::size_t k = 0;
  for (std::size_t g = 0; g < groups.colours.size(); ++g) {
    if (groups.count(g) == 0) continue;
    FillBatch batch(canvas, groups.colours[g], groups.count(g), close_seams);
    for (; k < groups.ends[g]; ++k) {
      poll.tick();
      const auto& tri = mesh.triangles[groups.order[k]];
      Box box;
      for (int v : tri) box.add(mesh.points[static_cast<std::size_t>(v)]);
      if (canvas.visible(box))
        batch.triangle(mesh.points[static_cast<std::size_t>(tri[0])], mesh.points[static_cast<std::size_t>(tri[1])],
                       mesh.points[static_cast<std::size_t>(tri[2])]);
      else
        batch.skip();  // in another band
    }
  }
}

void draw_fill_groups_seamless(Canvas& canvas, const Mesh& mesh, const FillGroups& groups) {
  cairo_t* cr = canvas.context();
  const cairo_antialias_t antialias = cairo_get_antialias(cr);
  cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);
  draw_fill_groups(canvas, mesh, groups, false);
  cairo_set_antialias(cr, antialias);
  draw_fill_groups(canvas, mesh, groups, false);
}

}  // namespace pdmesh
