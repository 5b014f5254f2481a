// The device-resident run behind the simulation contract (ocl::DeviceSimulator; device_simulation.hpp):
// the program is built once, at construction, so that a failing build comes before the run.
#include <fmt/format.h>

#include "core/errors.hpp"
#include "opencl/device_simulation.hpp"
#include "opencl/step_program.hpp"

namespace pdmesh::ocl {

DeviceSimulator::DeviceSimulator(Context& ctx, Precision precision, ForceLoop loop)
    : ctx_(ctx), program_(std::make_unique<StepProgram>(ctx, precision, loop)) {}

DeviceSimulator::~DeviceSimulator() = default;

Precision DeviceSimulator::precision() const { return program_->precision; }

ForceLoop DeviceSimulator::force_loop() const { return program_->force_loop; }

std::string DeviceSimulator::describe() const {
  const DeviceInfo& d = ctx_.device();
  return fmt::format("opencl:{}:{} ({}, {}, {}, device-resident, {} force loop)", d.platform, d.device, d.name, d.type,
                     precision() == Precision::Double ? "double" : "float", force_loop_name(force_loop()));
}

SimResult DeviceSimulator::run(NodeSet& nodes, const GeometryTree& tree, const SpacingField& spacing,
                               const SimOptions& options, const SimCallbacks& callbacks) {
  check_node_set(nodes);
  if (options.exact_spacing)
    throw InputError(
        "the device-resident simulation reads the background spacing field; exact_spacing needs --device host");
  if (options.metric)
    throw InputError(
        "the device-resident simulation has no metric mode yet (its loop keeps the isotropic spacing on "
        "the device); a run with a metric field needs the host driver (--device host) or the host-driven "
        "OpenCL step backend");
  trace_nodes_at_start(nodes, options);
  return run_device_resident(nodes, tree, spacing, options, ctx_, *program_, callbacks, stats_);
}

SimResult run_device_simulation(NodeSet& nodes, const GeometryTree& tree, const SpacingField& spacing,
                                const SimOptions& options, Context& ctx, Precision precision,
                                const SimCallbacks& callbacks, DeviceRunStats* stats, ForceLoop loop) {
  DeviceSimulator simulator(ctx, precision, loop);
  try {
    SimResult result = simulator.run(nodes, tree, spacing, options, callbacks);
    if (stats) *stats = simulator.stats();
    return result;
  } catch (...) {
    if (stats) *stats = simulator.stats();
    throw;
  }
}

}  // namespace pdmesh::ocl
