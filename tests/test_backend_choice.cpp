// The app's choice of simulation backend (app/pipeline/backend_choice): `--device auto` falls back device by
// device, then to the host, when the simulation program does not build (PDMESH_TEST_FAIL_BUILD
// injects a driver's build failure); an explicit device does not fall back; precisions; a metric run's
// choice (choose_metric_backend).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/pipeline/backend_choice.hpp"
#include "core/errors.hpp"
#include "geometry/geometry_tree.hpp"
#include "geometry_fixtures.hpp"
#include "init/initial_distribution.hpp"
#include "spacing/metric_field.hpp"
#include "spacing/spacing_field.hpp"
#include "opencl/device_simulation.hpp"
#include "opencl/devices.hpp"
#include "opencl/precision_probe.hpp"

using namespace pdmesh;

namespace {

struct Notes {
  std::vector<std::string> lines;
  std::function<void(const std::string&)> sink() {
    return [this](const std::string& l) { lines.push_back(l); };
  }
  bool any(const std::string& part) const {
    for (const auto& l : lines)
      if (l.find(part) != std::string::npos) return true;
    return false;
  }
};

ocl::DeviceInfo first_device() {
  const auto devices = ocl::list_devices();
  REQUIRE_FALSE(devices.empty());  // CI has PoCL
  return devices.front();
}

}  // namespace

TEST_CASE("auto falls back to the next device, saying so, when the program does not build", "[opencl][backend]") {
  const ocl::DeviceInfo d = first_device();
  Notes notes;
  ::setenv("PDMESH_TEST_FAIL_BUILD", "1", 1);  // the first build fails, as a driver's would
  const ChosenBackend chosen = choose_among({d, d}, true, Precision::Double, notes.sink());
  ::unsetenv("PDMESH_TEST_FAIL_BUILD");
  INFO(notes.lines.size() << " notes");
  REQUIRE(notes.lines.size() == 1);
  CHECK(notes.any(fmt::format("--device auto: opencl:{}:{} ({}) cannot run the simulation: building OpenCL program",
                              d.platform, d.device, d.name)));
  CHECK(notes.any(fmt::format("; trying opencl:{}:{} ({})", d.platform, d.device, d.name)));
  REQUIRE(chosen.context);
  CHECK(chosen.simulator->describe().find("double, device-resident") != std::string::npos);
}

TEST_CASE("auto ends on the host when no device builds the program, an explicit device does not fall back",
          "[opencl][backend]") {
  const ocl::DeviceInfo d = first_device();
  Notes notes;
  ::setenv("PDMESH_TEST_FAIL_BUILD", "1000", 1);
  const ChosenBackend chosen = choose_among({d}, true, Precision::Float, notes.sink());
  CHECK_FALSE(chosen.context);
  CHECK(chosen.simulator->describe() == "the host reference (double)");
  CHECK(notes.any("; trying the host reference"));
  CHECK(notes.any("--precision float is ignored"));
  CHECK_THROWS_AS(choose_among({d}, false, Precision::Double, notes.sink()), DeviceError);
  ::unsetenv("PDMESH_TEST_FAIL_BUILD");
}

TEST_CASE("precision: double without fp64 runs float, auto follows choose_precision_auto", "[opencl][backend]") {
  ocl::DeviceInfo d = first_device();
  Notes notes;
  const ChosenBackend host = choose_backend("host", Precision::Auto, notes.sink());
  CHECK(notes.lines.empty());
  CHECK_FALSE(host.context);
  const ChosenBackend dev = choose_among({d}, false, Precision::Auto, notes.sink());
  // PoCL's CPU device: double, not measured.
  CHECK(dev.simulator->describe().find(", double, device-resident") != std::string::npos);
  CHECK(notes.any("precision auto: double (a CPU device"));
  // The rule itself, with a measurement stand-in.
  int measured = 0;
  const auto measure = [&](double slowdown) {
    return [&measured, slowdown] {
      ++measured;
      return slowdown;
    };
  };
  d.type = "GPU";
  CHECK(ocl::choose_precision_auto(d, measure(32.0)).precision == ocl::Precision::Float);
  CHECK(ocl::choose_precision_auto(d, measure(2.0)).precision == ocl::Precision::Double);
  CHECK(ocl::choose_precision_auto(d, measure(32.0)).reason.find("double took 32.0x as long as float") !=
        std::string::npos);
  CHECK(measured == 3);
  d.fp64 = false;
  CHECK(ocl::choose_precision_auto(d, measure(1.0)).precision == ocl::Precision::Float);
  d.type = "CPU";
  d.fp64 = true;
  CHECK(ocl::choose_precision_auto(d, measure(100.0)).precision == ocl::Precision::Double);
  CHECK(measured == 3);  // neither without fp64 nor on a CPU device
}

TEST_CASE("the fp64 rate is measured on the device", "[opencl][backend]") {
  const ocl::DeviceInfo d = first_device();
  REQUIRE(d.fp64);
  ocl::Context ctx(d);
  const double slowdown = ocl::measure_fp64_slowdown(ctx);
  INFO("double / float time: " << slowdown);
  // A ratio of two timings (no bound on it: timings are for benchmarks, not tests; measured 1.1x on PoCL).
  CHECK(std::isfinite(slowdown));
  CHECK(slowdown > 0.0);
}

TEST_CASE("auto order: discrete GPU, fp64, compute units, then CPUs", "[opencl][backend]") {
  const auto make = [](std::string name, std::string type, bool unified, bool fp64, unsigned units) {
    ocl::DeviceInfo d;
    d.name = std::move(name);
    d.type = std::move(type);
    d.unified_memory = unified;
    d.fp64 = fp64;
    d.compute_units = units;
    return d;
  };
  const auto order =
      ocl::auto_order({make("cpu", "CPU", true, true, 64), make("igpu", "GPU", true, false, 96),
                       make("small", "GPU", false, true, 20), make("big", "GPU", false, true, 80),
                       make("nofp64", "GPU", false, false, 128), make("fpga", "accelerator", false, true, 8)});
  std::vector<std::string> names;
  for (const auto& d : order) names.push_back(d.name);
  CHECK(names == std::vector<std::string>{"big", "small", "nofp64", "igpu", "cpu", "fpga"});
}

TEST_CASE("a metric run gets the host driver: the reference, or an explicit device's OpenCL step backend",
          "[opencl][backend][metric]") {
  const ocl::DeviceInfo d = first_device();
  const Geometry geometry = fixtures::square(1.0, 4);
  const GeometryTree tree(geometry);
  const BoundarySpacing spacing(tree);
  const NodeSet initial = make_initial_distribution(tree, spacing, {InitMethod::Structured, 1, {}}).nodes;
  const ConstantMetricField metric(Metric{16.0, 0.0, 16.0});
  SimOptions o;
  o.iterations = 5;
  o.quiet = true;
  o.metric = &metric;
  Notes notes;
  const ChosenBackend host = choose_metric_backend("host", Precision::Double, notes.sink());
  CHECK_FALSE(host.context);
  CHECK(host.simulator->describe() == "the host reference (double)");
  const ChosenBackend automatic = choose_metric_backend("auto", Precision::Auto, notes.sink());
  CHECK_FALSE(automatic.context);
  CHECK(notes.any("the host reference for a run with a metric field"));
  NodeSet a = initial;
  const SimResult ra = automatic.simulator->run(a, tree, spacing, o);
  for (const Precision precision : {Precision::Double, Precision::Float}) {
    const ChosenBackend device =
        choose_metric_backend(fmt::format("opencl:{}:{}", d.platform, d.device), precision, notes.sink());
    REQUIRE(device.context);
    const std::string described = device.simulator->describe();
    INFO(described);
    CHECK(described.find("host-driven steps") != std::string::npos);
    NodeSet b = initial;
    const SimResult rb = device.simulator->run(b, tree, spacing, o);  // the device-resident run would refuse
    REQUIRE(rb.history.size() == 5);
    if (precision == Precision::Double && d.fp64) CHECK(b.x == a.x);
  }
}
