// The clearance-budget refresh (kernels/clearance.cl, BoundaryHandler::refresh_accepts and
// clearance_from): the device's bound against the brute-force distance to the boundary, and the refresh
// rule through one test body for the host and the device (double: bit for bit; float: conservative).
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <random>

#include "device_run_fixtures.hpp"
#include "geometry/brute_force_queries.hpp"
#include "opencl/device_boundary.hpp"
#include "sim/boundary_handling.hpp"

using namespace pdmesh;

namespace {

struct Moves {
  std::vector<double> x, y, dx, dy;
  std::vector<char> inside;  // the start is known inside (the rule's precondition: a budget > 0)
};

// Per move: the bound at the target and the refreshed budget (0: the host's exact test decides).
struct Refresh {
  std::vector<double> bound, budget;
};

// Moves from every interior node of naca0012's start (inside) by multiples of its clearance in random
// directions: well inside it, about it (either side of the rule's margin) and past it (some leave the
// domain); and from points on or a hair off the boundary segments (bound 0 or tiny).
Moves make_moves(const BoundaryHandler& handler, const NodeSet& nodes) {
  std::mt19937_64 rng(20261124);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
  const double factors[] = {0.0, 0.3, 0.9, 0.999, 1.001, 1.5, 4.0};
  Moves m;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes.kind[i] != NodeKind::Interior) continue;
    const double c = handler.clearance_from(nodes.x[i]);
    const double a = angle(rng), f = factors[rng() % std::size(factors)];
    m.x.push_back(nodes.x[i].x);
    m.y.push_back(nodes.x[i].y);
    m.dx.push_back(f * c * std::cos(a));
    m.dy.push_back(f * c * std::sin(a));
    m.inside.push_back(1);
  }
  const Geometry& g = handler.tree().geometry();
  for (std::size_t s = 0; s < g.segments.size(); s += 7) {
    const Segment& seg = g.segments[s];
    const double t = 0.37, off = (s % 3 == 0) ? 0.0 : (s % 3 == 1 ? 1e-14 : 1e-5);
    const Vec2 p = seg.a + t * (seg.b - seg.a);
    m.x.push_back(p.x + off);
    m.y.push_back(p.y - off);
    m.dx.push_back(0.0);
    m.dy.push_back(0.0);
    m.inside.push_back(0);  // either side of the boundary: for the bound only
  }
  return m;
}

Refresh host_refresh(const BoundaryHandler& handler, const Moves& m) {
  Refresh r;
  for (std::size_t k = 0; k < m.x.size(); ++k) {
    const Vec2 target{m.x[k] + m.dx[k], m.y[k] + m.dy[k]};
    const double d = handler.clearance_from(target);
    r.bound.push_back(d);
    r.budget.push_back(BoundaryHandler::refresh_accepts(target.x - m.x[k], target.y - m.y[k], target, d) ? d : 0.0);
  }
  return r;
}

// group: clearance_points_group (a work-group per move, the search of refresh_budgets) instead of
// clearance_points (a work-item per move, device_step's inline refresh).
template <typename Real>
Refresh device_refresh(const Geometry& geometry, const Moves& m, ocl::Precision precision, bool group = false) {
  ocl::Context& ctx = test::test_context();
  ocl::StepProgram& program = test::test_program(precision);
  ocl::DeviceBoundary<Real> boundary(ctx, geometry);
  boundary.upload_curves();
  const std::size_t n = m.x.size();
  auto up = [&](const char* name, const std::vector<double>& v) {
    ocl::Buffer<Real> b(ctx, name, n);
    b.upload(ctx.queue(), ocl::to_real<Real>(v));
    return b;
  };
  ocl::Buffer<Real> x = up("x", m.x), y = up("y", m.y), dx = up("dx", m.dx), dy = up("dy", m.dy);
  ocl::Buffer<Real> bound(ctx, "bound", n), budget(ctx, "budget", n);
  cl::Kernel& kernel = group ? program.clearance_points_group : program.clearance_points;
  const char* name = group ? "clearance_points_group" : "clearance_points";
  ocl::ArgSetter a(kernel, name);
  a(static_cast<cl_int>(n))(x)(y)(dx)(dy)(boundary.segments())(static_cast<cl_int>(boundary.segment_count()))(
      static_cast<Real>(boundary.segment_scale()))(bound)(budget);
  ocl::launch(ctx.queue(), kernel, name, group ? n * program.work_group : n, program.work_group);
  std::vector<Real> b, u;
  bound.download(ctx.queue(), b, n);
  budget.download(ctx.queue(), u, n);
  return Refresh{std::vector<double>(b.begin(), b.end()), std::vector<double>(u.begin(), u.end())};
}

// The contract of the refresh, whoever computed it: the bound never exceeds the brute-force distance
// (the moves' starts are inside or on the boundary); a refreshed move is one the exact test accepts,
// with its bound as the budget; positions on the boundary are left to the host.
// In float the moves are the device's: the coordinates rounded to float and added in float.
void check_refresh(const GeometryTree& tree, const Moves& m, const Refresh& r, bool in_float, std::size_t& accepted,
                   std::size_t& rejected) {
  const Geometry& g = tree.geometry();
  for (std::size_t k = 0; k < m.x.size(); ++k) {
    Vec2 from{m.x[k], m.y[k]}, target{m.x[k] + m.dx[k], m.y[k] + m.dy[k]};
    if (in_float) {
      const float fx = static_cast<float>(m.x[k]), fy = static_cast<float>(m.y[k]);
      from = {fx, fy};
      target = {fx + static_cast<float>(m.dx[k]), fy + static_cast<float>(m.dy[k])};
    }
    const double exact = brute_force::closest(g, target).distance;
    INFO("move " << k << " from (" << from.x << ", " << from.y << ") to (" << target.x << ", " << target.y << ")");
    CHECK(r.bound[k] >= 0.0);
    CHECK(r.bound[k] <= exact);
    if (exact == 0.0) CHECK(r.budget[k] == 0.0);
    if (!m.inside[k]) {  // on or 1e-5 off a segment
      CHECK(r.bound[k] <= 2e-5);
      continue;
    }
    if (r.budget[k] > 0.0) {
      ++accepted;
      CHECK(r.budget[k] == r.bound[k]);
      CHECK(brute_force::inside(g, target));
      CHECK_FALSE(brute_force::crosses_boundary(g, from, target));
    } else {
      ++rejected;
    }
  }
}

}  // namespace

TEST_CASE("clearance refresh: one rule on the host and the device, checked against brute force",
          "[opencl][boundary][clearance]") {
  const test::Case c = test::load_case("naca0012");
  const GeometryTree& tree = c.inputs->node_tree();
  const BoundaryHandler handler(tree, c.initial);
  const Moves moves = make_moves(handler, c.initial);
  REQUIRE(moves.x.size() > 1000);

  const std::pair<const char*, std::function<Refresh()>> runs[] = {
      {"host", [&] { return host_refresh(handler, moves); }},
      {"device double", [&] { return device_refresh<double>(tree.geometry(), moves, ocl::Precision::Double); }},
      {"device float", [&] { return device_refresh<float>(tree.geometry(), moves, ocl::Precision::Float); }}};
  for (const auto& [name, run] : runs) {
    SECTION(name) {
      const Refresh r = run();
      std::size_t accepted = 0, rejected = 0;
      check_refresh(tree, moves, r, std::string(name) == "device float", accepted, rejected);
      // Most moves within their clearance are refreshed, the ones past it are not.
      CHECK(accepted > moves.x.size() / 4);
      CHECK(rejected > moves.x.size() / 4);
      if (std::string(name) == "device double") {
        // Bit for bit the host's rule: same bounds (or 0 where the host's exact on-segment snap could
        // apply), same decisions.
        const Refresh host = host_refresh(handler, moves);
        std::size_t same = 0;
        for (std::size_t k = 0; k < moves.x.size(); ++k) {
          INFO("move " << k);
          if (r.bound[k] != 0.0) CHECK(r.bound[k] == host.bound[k]);
          same += r.bound[k] == host.bound[k];
          // Where only the host's bound is not 0 (a point within 1e-12 of a segment, where the host's
          // exact on-segment test may snap the distance) the device leaves the move to the host.
          if (r.bound[k] != 0.0 || host.bound[k] == 0.0)
            CHECK(r.budget[k] == host.budget[k]);
          else
            CHECK(r.budget[k] == 0.0);
        }
        CHECK(same + 3 * moves.x.size() / 1000 >= moves.x.size());
      }
    }
  }
}

TEST_CASE("clearance refresh: a work-group's search gives one work-item's bounds bit for bit",
          "[opencl][boundary][clearance]") {
  const test::Case c = test::load_case("naca0012");
  const GeometryTree& tree = c.inputs->node_tree();
  const BoundaryHandler handler(tree, c.initial);
  const Moves moves = make_moves(handler, c.initial);
  // More segments than work-items in a group: every work-item walks several, and the group's minimum
  // comes from different work-items for different moves.
  REQUIRE(tree.geometry().segments.size() > 4 * ocl::kStepWorkGroup);
  const auto check_same = [&](const Refresh& one, const Refresh& group) {
    std::size_t positive = 0;
    for (std::size_t k = 0; k < moves.x.size(); ++k) {
      INFO("move " << k);
      CHECK(group.bound[k] == one.bound[k]);
      CHECK(group.budget[k] == one.budget[k]);
      positive += one.bound[k] > 0.0;
    }
    CHECK(positive > moves.x.size() / 2);
  };
  SECTION("double") {
    check_same(device_refresh<double>(tree.geometry(), moves, ocl::Precision::Double),
               device_refresh<double>(tree.geometry(), moves, ocl::Precision::Double, true));
  }
  SECTION("float") {
    check_same(device_refresh<float>(tree.geometry(), moves, ocl::Precision::Float),
               device_refresh<float>(tree.geometry(), moves, ocl::Precision::Float, true));
  }
}
