// Node distribution pictures: tree overlay, then geometry, then interior and boundary nodes on top.
#include "render/node_picture.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <fmt/format.h>

#include "core/interrupt.hpp"
#include "render/canvas.hpp"

namespace pdmesh {

double node_dot_radius(double q, double scale, bool fixed) {
  double r = std::isfinite(q) && q > 0 ? 0.12 * q * scale : 1.5;
  r = std::clamp(r, kMinNodeDot, 5.0);
  return fixed ? 1.5 * r + 0.5 : r;
}

void write_node_picture(const std::filesystem::path& path, const Geometry& geometry, const NodeSet& nodes,
                        const NodePictureOptions& options) {
  CanvasOptions layout;
  layout.window = options.window ? *options.window : padded_window(geometry.extents);
  layout.long_side = options.long_side;
  render_picture(path, layout, [&](Canvas& canvas) {
    if (options.tree_quads != nullptr) {
      StrokeBatch tree(canvas, colours::kTree, 0.6);
      for (const Box& b : *options.tree_quads) {
        if (canvas.visible(b)) tree.box(b);
      }
    }
    {
      StrokeBatch curves(canvas, colours::kGeometry, 1.5);
      for (const Segment& s : geometry.segments) {
        Box b;
        b.add(s.a);
        b.add(s.b);
        if (canvas.visible(b)) curves.segment(s.a, s.b);
      }
    }
    // Interior nodes first so that boundary nodes stay visible where they overlap.
    // Interior nodes outnumbering a quarter of the plot's pixels are set in a PixelSplat (each dot's
    // square) instead of drawn as paths: at that density the dots' union is what shows.
    for (NodeKind pass : {NodeKind::Interior, NodeKind::Boundary, NodeKind::Fixed}) {
      const Rgb colour = pass == NodeKind::Interior ? colours::kInteriorNode : colours::kBoundaryNode;
      std::optional<PixelSplat> splat;
      if (pass == NodeKind::Interior && splat_worthwhile(canvas, nodes.count(NodeKind::Interior)))
        splat.emplace(canvas, colour);
      // The dots at the smallest radius (the dense parts' nodes, most of them) with cairo's pen.
      DotBatch dots(canvas, colour, kMinNodeDot);
      for (std::size_t i = 0; i < nodes.size(); ++i) {
        if ((i & 65535) == 0) check_interrupt();
        if (nodes.kind[i] != pass) continue;
        const double q = i < nodes.q.size() ? nodes.q[i] : 0.0;
        const double r = node_dot_radius(q, canvas.scale(), pass == NodeKind::Fixed);
        if (!canvas.visible(nodes.x[i], r)) continue;
        if (splat)
          splat->dot(nodes.x[i], r);
        else
          dots.dot(nodes.x[i], r);
      }
    }
    canvas.title(fmt::format("{}   {} nodes: {} fixed, {} boundary, {} interior", options.title, nodes.size(),
                             nodes.count(NodeKind::Fixed), nodes.count(NodeKind::Boundary),
                             nodes.count(NodeKind::Interior)));
  });
}

}  // namespace pdmesh
