// The per-device check of `pdmesh devices --check`; see device_check.hpp.
#include "app/cli/device_check.hpp"

#include <cmath>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "opencl/context.hpp"
#include "opencl/device_simulation.hpp"
#include "opencl/precision_probe.hpp"
#include "opencl/step_program.hpp"
#include "sim/simulation.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {
namespace {

constexpr int kIterations = 20;

// A 2 x 2 square around a hole of radius 0.35: the boundary spacing grades 3x from the hole out.
Geometry check_geometry() {
  RawCurve outer{"square", {}, "built-in", 0, {}}, hole{"hole", {}, "built-in", 0, {}};
  for (int k = 0; k <= 20; ++k) {
    const int side = k / 5, t = k % 5;
    const double s = -1.0 + 0.4 * t;
    const Vec2 p = side == 0 ? Vec2{s, -1.0} : side == 1 ? Vec2{1.0, s} : side == 2 ? Vec2{-s, 1.0} : Vec2{-1.0, -s};
    outer.points.push_back(k == 20 ? outer.points.front() : p);
  }
  for (int k = 0; k <= 40; ++k) {
    const double a = -2.0 * M_PI * k / 40;  // clockwise: a hole
    hole.points.push_back(k == 40 ? hole.points.front() : Vec2{0.35 * std::cos(a), 0.35 * std::sin(a)});
  }
  return build_geometry({outer, hole});
}

}  // namespace

DeviceCheck check_device(const ocl::DeviceInfo& device) {
  DeviceCheck check;
  try {
    ocl::Context ctx(device);
    const ocl::Precision precision = device.fp64 ? ocl::Precision::Double : ocl::Precision::Float;
    const char* precision_name = precision == ocl::Precision::Double ? "double" : "float";
    ocl::DeviceSimulator simulator(ctx, precision);  // builds the program, checks the work-group size
    {
      ocl::StepProgram program(ctx, precision);  // the same program (built again, from the cache on PoCL)
      std::size_t limit = program.limits.front().max_work_group;
      for (const ocl::KernelLimits& k : program.limits) limit = std::min(limit, k.max_work_group);
      check.lines.push_back(
          fmt::format("program: built in {}; work-groups of {} fit every kernel (the smallest "
                      "kernel limit is {}, preferred multiple {})",
                      precision_name, program.work_group, limit, program.limits.front().preferred_multiple));
      const std::string advice = ocl::work_group_advice(program.limits, program.work_group);
      if (!advice.empty()) check.lines.push_back("note: " + advice);
    }
    const Geometry geometry = check_geometry();
    const GeometryTree tree(geometry);
    const BoundarySpacing spacing(tree);
    InitOptions init;
    init.method = InitMethod::Random;
    init.with_estimate = false;
    const NodeSet start = make_initial_distribution(tree, spacing, init).nodes;
    SimOptions options;
    options.iterations = kIterations;
    options.stability_factor = 0.0;  // the thesis rule: larger moves, nodes leave the domain and snap
    options.quiet = true;
    NodeSet host = start, dev = start;
    const SimResult host_run = run_simulation(host, tree, spacing, options);
    const SimResult dev_run = simulator.run(dev, tree, spacing, options);
    std::size_t differ = 0;
    double worst = 0.0;
    for (std::size_t i = 0; i < host.size(); ++i) {
      if (dev.x[i].x != host.x[i].x || dev.x[i].y != host.x[i].y || dev.q[i] != host.q[i]) ++differ;
      worst = std::max(worst, norm(dev.x[i] - host.x[i]) / host.q[i]);
    }
    const bool same_topology = dev.kind == host.kind && dev.curve_nodes == host.curve_nodes;
    const std::string run =
        fmt::format("{} iterations of {} nodes (random start, {} snapped, {} neighbour-list builds)", kIterations,
                    start.size(), host_run.stats.snapped, simulator.stats().rebuilds);
    check.bit_identical = precision == ocl::Precision::Double && same_topology && differ == 0;
    // Float rounds differently by design; a double run off by more than this is wrong, not just
    // rounded differently (a fused multiply-add changes the last bits, which the start amplifies).
    const double tolerance = precision == ocl::Precision::Double ? 1e-3 : 2e-2;
    if (check.bit_identical) {
      check.lines.push_back(
          fmt::format("step: {} equal the host reference bit for bit (FP_CONTRACT OFF honoured, "
                      "double rounded as on the host)",
                      run));
    } else if (same_topology && worst <= tolerance) {
      check.lines.push_back(fmt::format("step: {}: {} of {} nodes differ from the host reference, by at most {:.2g} q",
                                        run, differ, host.size(), worst));
      if (precision == ocl::Precision::Double)
        check.lines.push_back(
            "warning: not bit-identical in double: this device contracts a * b + c into fused "
            "multiply-adds despite FP_CONTRACT OFF, or rounds double / or sqrt differently; its "
            "runs will not repeat the host's bit for bit (their quality is unaffected)");
    } else {
      check.lines.push_back(
          fmt::format("step: {}: {} of {} nodes differ from the host reference, by up to {:.3g} q{} "
                      "(more than the {:g} q a correct {} device stays within)",
                      run, differ, host.size(), worst, same_topology ? "" : ", and the nodes on the curves differ",
                      tolerance, precision_name));
      return check;
    }
    (void)dev_run;
    if (device.fp64) {
      const double slowdown = ocl::measure_fp64_slowdown(ctx);
      const ocl::PrecisionChoice choice = ocl::choose_precision_auto(device, [slowdown] { return slowdown; });
      check.lines.push_back(fmt::format(
          "fp64: double took {:.1f}x as long as float (measured); --precision auto picks {}", slowdown, choice.reason));
    } else {
      check.lines.push_back("fp64: none; --precision auto (and double) simulate in float");
    }
    check.ok = true;
  } catch (const Error& e) {
    check.lines.push_back(e.what());
  }
  return check;
}

}  // namespace pdmesh
