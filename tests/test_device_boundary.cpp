// The device's boundary re-snapping (kernels/boundary.cl, host/opencl/device_boundary.*) against the
// host's BoundaryHandler::move_boundary_nodes (closest_on_curve_range), bit for bit in double: one
// launch over every boundary node of naca0012 (curves of many segments) with moves of every kind (none,
// small, far past the allowed range so they are clamped, onto a curve vertex), and arc ranges made to
// end exactly at a vertex from either side.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "device_run_fixtures.hpp"
#include "opencl/device_boundary.hpp"
#include "opencl/device_window.hpp"
#include "sim/boundary_handling.hpp"
#include "spacing/background_field.hpp"

using namespace pdmesh;

namespace {

// An arc position a for the neighbour entry so that old -/+ kMaxGapFraction |old - a| is exactly v
// (the host's expression), or NaN when no double near the ideal one gives it.
double neighbour_arc_for(double old, double v, bool below) {
  constexpr double f = BoundaryHandler::kMaxGapFraction;
  double a = below ? old - (old - v) / f : old + (v - old) / f;
  for (int tries = 0; tries < 64; ++tries) {
    const double end = below ? old - f * (old - a) : old + f * (a - old);
    if (end == v) return a;
    // Moving a away from old moves the end away from old too.
    const bool further = below ? end > v : end < v;
    a = std::nextafter(a, (further == below) ? -HUGE_VAL : HUGE_VAL);
  }
  return NAN;
}

}  // namespace

TEST_CASE("boundary_snap re-snaps every boundary node exactly as the host (double)", "[opencl][boundary]") {
  const test::Case c = test::load_case("naca0012");
  const GeometryTree& tree = c.inputs->node_tree();
  const Geometry& geometry = tree.geometry();
  NodeSet nodes = c.initial;
  const std::size_t n = nodes.size();
  BoundaryHandler handler(tree, nodes);

  // Ranges ending at a vertex: every fourth node's old arc position is put a little past the curve
  // vertex v below (above) it, and its neighbour's chosen so that the node's lo (hi) is exactly v.
  // The host and the device read only the arc positions there, not where the nodes stand.
  std::vector<std::vector<double>> arcs = handler.arcs();
  int at_vertex = 0;
  for (std::size_t ci = 0; ci < arcs.size(); ++ci) {
    const std::vector<double>& va = geometry.curves[ci].arc;
    std::vector<double>& a = arcs[ci];
    for (std::size_t k = 2; k + 2 < a.size(); k += 4) {
      const bool below = (k / 4) % 2 == 0;
      double v = NAN, old = NAN;
      if (below) {
        const auto it = std::upper_bound(va.begin(), va.end(), a[k]);  // the last vertex <= a[k]
        if (it == va.begin() || !(*(it - 1) > a[k - 2])) continue;
        v = *(it - 1);
        old = v + 0.3 * (a[k + 1] - v);
      } else {
        const auto it = std::lower_bound(va.begin(), va.end(), a[k]);  // the first vertex >= a[k]
        if (it == va.end() || !(*it < a[k + 2])) continue;
        v = *it;
        old = v - 0.3 * (v - a[k - 1]);
      }
      const double arc = neighbour_arc_for(old, v, below);
      if (std::isnan(arc) || !(below ? (a[k - 2] < arc && arc < old) : (old < arc && arc < a[k + 2]))) continue;
      a[k] = old;
      a[below ? k - 1 : k + 1] = arc;
      ++at_vertex;
    }
  }
  handler.restore(nodes, arcs, handler.tangents());
  REQUIRE(at_vertex > 10);

  // Moves: none, small, far (clamped), onto a vertex of the node's curve (averaged tangents).
  std::mt19937_64 rng(20261124);
  std::vector<double> dx(n, 0.0), dy(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (nodes.kind[i] != NodeKind::Boundary) continue;
    const double q = nodes.q[i];
    const double angle = 2.0 * M_PI * pdmesh_test::uniform(rng);
    switch (rng() % 4) {
      case 0:
        break;
      case 1:
        dx[i] = 0.1 * q * std::cos(angle), dy[i] = 0.1 * q * std::sin(angle);
        break;
      case 2:
        dx[i] = 3.0 * q * std::cos(angle), dy[i] = 3.0 * q * std::sin(angle);
        break;
      default: {
        const Curve& curve = geometry.curves[static_cast<std::size_t>(nodes.curve[i])];
        const Vec2 v = curve.points[rng() % curve.points.size()];
        dx[i] = v.x - nodes.x[i].x;
        dy[i] = v.y - nodes.x[i].y;
      }
    }
  }

  // The host.
  NodeSet host = nodes;
  BoundaryHandler host_handler = handler;
  const BoundaryCounts counts = host_handler.apply_subset(host, dx, dy, {});
  CHECK(counts.clamped > 10);

  // The device: one boundary_snap launch from the same state.
  ocl::Context& ctx = test::test_context();
  ocl::StepProgram& program = test::test_program(ocl::Precision::Double);
  ocl::DeviceBoundary<double> device(ctx, geometry);
  device.upload_curves();
  const std::vector<std::int32_t> slots = device.upload_topology(nodes, handler.arcs());
  REQUIRE(slots.size() == nodes.count(NodeKind::Boundary));
  std::vector<double> rec, x(n), y(n), xy(2 * n), q(n), zero(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) x[i] = xy[2 * i] = nodes.x[i].x, y[i] = xy[2 * i + 1] = nodes.x[i].y;
  for (std::int32_t s : slots) {
    const auto i = static_cast<std::size_t>(s);
    for (double v : {x[i], y[i], dx[i], dy[i]}) rec.push_back(v);
  }
  const SimOptions options = test::options_for(c, 1);
  std::unique_ptr<BackgroundSpacing> own;
  const BackgroundFieldData& bg = background_for(options, *c.inputs->spacing, tree, own).data();
  auto buffer = [&](const char* name, const auto& host_data) {
    using T = typename std::decay_t<decltype(host_data)>::value_type;
    ocl::Buffer<T> b(ctx, name, std::max<std::size_t>(host_data.size(), 1));
    b.upload(ctx.queue(), host_data);
    return b;
  };
  ocl::Buffer<double> brec = buffer("brec", rec), bxy = buffer("xy", xy), bq = buffer("q", nodes.q),
                      tx = buffer("tx", zero), ty = buffer("ty", zero), bg_q = buffer("bg_q", bg.corner_q);
  ocl::Buffer<std::int32_t> leaf = buffer("leaf", std::vector<std::int32_t>(n, 0)), root = buffer("root", bg.root_node),
                            child = buffer("child", bg.node_child), corner = buffer("corner", bg.leaf_corner),
                            cell = buffer("cell", bg.leaf_cell),
                            halt = buffer("halt", std::vector<std::int32_t>(ocl::kWindowCounters, 0));
  ocl::Buffer<std::uint8_t> skin_class = buffer("skin_class", std::vector<std::uint8_t>(n, 0));
  device.enqueue(
      program, 0, brec, bxy, bq, tx, ty, leaf, bxy, bq, skin_class, options.cutoff, 0.3 * options.cutoff, halt,
      [&](ocl::ArgSetter& a) {
        a(bg.origin_x)(bg.origin_y)(bg.inv_root_size)(static_cast<cl_int>(bg.grid))(root)(child)(corner)(cell)(bg_q);
      });
  std::vector<double> out_xy, out_x(n), out_y(n), out_tx, out_ty, out_q, out_rec, partials;
  bxy.download(ctx.queue(), out_xy, 2 * n);
  for (std::size_t i = 0; i < n; ++i) out_x[i] = out_xy[2 * i], out_y[i] = out_xy[2 * i + 1];
  tx.download(ctx.queue(), out_tx, n);
  ty.download(ctx.queue(), out_ty, n);
  bq.download(ctx.queue(), out_q, n);
  brec.download(ctx.queue(), out_rec, rec.size());
  device.partials().download(ctx.queue(), partials, device.partial_count(program.work_group));
  const std::vector<std::vector<double>> out_arcs = device.download_arcs(1, nodes);

  const ocl::BoundarySnapResult r = ocl::DeviceBoundary<double>::sum(partials, partials.size());
  CHECK(r.clamped == counts.clamped);
  CHECK(r.non_finite == 0);
  CHECK(out_arcs == host_handler.arcs());
  std::size_t differ = 0, first = n, averaged = 0;
  for (std::size_t s = 0; s < slots.size(); ++s) {
    const auto i = static_cast<std::size_t>(slots[s]);
    const Vec2 t = host_handler.tangent(slots[s]);
    const bool same = out_x[i] == host.x[i].x && out_y[i] == host.x[i].y && out_tx[i] == t.x && out_ty[i] == t.y &&
                      out_rec[4 * s] == host.x[i].x && out_rec[4 * s + 1] == host.x[i].y && out_rec[4 * s + 2] == t.x &&
                      out_rec[4 * s + 3] == t.y && out_q[i] == own->at(host.x[i]);
    if (!same && differ++ == 0) first = i;
    // A vertex hit from the inside of the range: the tangent is the mean of two segments' directions.
    const Curve& curve = geometry.curves[static_cast<std::size_t>(host.curve[i])];
    if (std::find(curve.points.begin(), curve.points.end(), host.x[i]) != curve.points.end()) ++averaged;
  }
  INFO(differ << " boundary nodes differ; the first is node " << first);
  CHECK(differ == 0);
  CHECK(averaged > 10);
  // Interior and fixed nodes are untouched.
  for (std::size_t i = 0; i < n; ++i)
    if (nodes.kind[i] != NodeKind::Boundary) REQUIRE((out_x[i] == x[i] && out_y[i] == y[i] && out_tx[i] == 0.0));
}
