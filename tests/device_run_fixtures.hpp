// Shared fixtures of the device-resident run tests (test_device_simulation.cpp, test_device_cases.cpp):
// a case from cases/ loaded and initialized, and one run of it on the host reference or the device.
#pragma once
#include <catch2/catch.hpp>

#include <memory>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "opencl/device_simulation.hpp"
#include "source_dir.hpp"
#include "step_backend_inputs.hpp"

namespace pdmesh::test {

struct Case {
  CaseConfig config;
  std::unique_ptr<MeshInputs> inputs;
  std::unique_ptr<SpacingStage> spacing;  // the final field the initial distribution was made with
  NodeSet initial;
};

inline Case load_case(const std::string& name, const std::vector<CaseOverride>& overrides = {}) {
  Case c;
  c.config = load_case_file(source_dir() + "/cases/" + name + "/case.toml", overrides);
  c.config.quiet = true;
  c.inputs = std::make_unique<MeshInputs>(c.config);
  c.spacing = std::make_unique<SpacingStage>(c.config, *c.inputs, SpacingStage::Build::FieldOnly);
  c.initial = make_initial(c.config, *c.inputs, *c.spacing).nodes;
  return c;
}

inline SimOptions options_for(const Case& c, int iterations) {
  SimOptions o;
  o.iterations = iterations;
  o.dt_initial = c.config.simulation.dt_for(c.config.init.method);
  o.cutoff = c.config.simulation.cutoff;
  o.lj_a = c.config.simulation.lj_a;
  o.r0_any_direction = c.config.simulation.r0_any_direction;
  o.stability_factor = c.config.simulation.stability_factor;
  o.quiet = true;
  return o;
}

struct Outcome {
  NodeSet nodes;
  SimResult result;
  ocl::DeviceRunStats stats;
};

// Both shapes of the force loop (kernels/forces.cl), for tests that run every device test body with each.
inline constexpr ocl::ForceLoop kForceLoops[] = {ocl::ForceLoop::Vector, ocl::ForceLoop::Scalar};

// A run with options `o` from `start`: on the host reference, or device-resident on test_context()
// (double unless use_float; the force loop `loop`, Auto: the device's).
inline Outcome run_from(const Case& c, const NodeSet& start, const SimOptions& o, bool device, bool use_float = false,
                        ocl::ForceLoop loop = ocl::ForceLoop::Auto) {
  Outcome out{start, {}, {}};
  if (device) {
    out.result =
        ocl::run_device_simulation(out.nodes, c.inputs->node_tree(), *c.inputs->spacing, o, test_context(),
                                   use_float ? ocl::Precision::Float : ocl::Precision::Double, {}, &out.stats, loop);
  } else {
    out.result = run_simulation(out.nodes, c.inputs->node_tree(), *c.inputs->spacing, o);
  }
  return out;
}

// `iterations` of the case from its initial distribution: on the host reference, or device-resident
// on test_context() (double unless use_float; Verlet skin `skin`; force loop `loop`).
inline Outcome run_case(const Case& c, int iterations, bool device, bool use_float = false, double skin = 0.3,
                        ocl::ForceLoop loop = ocl::ForceLoop::Auto) {
  SimOptions o = options_for(c, iterations);
  o.verlet_skin = skin;
  return run_from(c, c.initial, o, device, use_float, loop);
}

// Every node at the same position with the same spacing and kind, and the same curve lists: bit for bit.
inline void require_identical_nodes(const NodeSet& host, const NodeSet& dev) {
  REQUIRE(dev.size() == host.size());
  REQUIRE(dev.kind == host.kind);
  REQUIRE(dev.curve_nodes == host.curve_nodes);
  std::size_t differ = 0, first = host.size();
  for (std::size_t i = 0; i < host.size(); ++i) {
    if (dev.x[i].x == host.x[i].x && dev.x[i].y == host.x[i].y && dev.q[i] == host.q[i]) continue;
    if (differ++ == 0) first = i;
  }
  INFO(differ << " nodes differ; the first is node " << first);
  CHECK(differ == 0);
}

}  // namespace pdmesh::test
