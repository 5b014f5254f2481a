// The pair-force floor on an OpenCL device; see device_floor.hpp.
#include "opencl/device_floor.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <type_traits>

#include <fmt/format.h>

#include "core/cpu_time.hpp"
#include "core/errors.hpp"
#include "opencl/buffer.hpp"
#include "opencl/cl_errors.hpp"
#include "opencl/command_counts.hpp"
#include "opencl/step_program.hpp"

namespace pdmesh::ocl {

struct DeviceFloor::State {
  virtual ~State() = default;
  virtual Times run(double dt2) = 0;
  virtual void download(std::vector<double>& new_x, std::vector<double>& new_y) = 0;
  virtual double bytes() const = 0;
};

namespace {

// The floor's buffers and kernel in one precision.
template <typename Real>
class FloorOnDevice final : public DeviceFloor::State {
 public:
  FloorOnDevice(Context& ctx, const FloorLattice& l, Precision precision) : lattice_(l), n_(l.size()) {
    cl_int err = CL_SUCCESS;
    queue_ = cl::CommandQueue(ctx.context(), ctx.device().handle, CL_QUEUE_PROFILING_ENABLE, &err);
    check(err, fmt::format("clCreateCommandQueue (profiling) on {}", ctx.device().name));
    program_ = ctx.build({"pair_floor.cl"}, precision_defines(precision, kStepWorkGroup));
    kernel_ = cl::Kernel(program_, "pair_floor", &err);
    check(err, "clCreateKernel(pair_floor)");
    std::size_t limit = 0;
    check(kernel_.getWorkGroupInfo(ctx.device().handle, CL_KERNEL_WORK_GROUP_SIZE, &limit),
          "clGetKernelWorkGroupInfo(pair_floor, CL_KERNEL_WORK_GROUP_SIZE)");
    check_work_group("pair_floor", ctx.device().name, kStepWorkGroup, std::min(limit, ctx.device().max_work_group));
    x_ = Buffer<Real>(ctx, "floor_x", n_);
    y_ = Buffer<Real>(ctx, "floor_y", n_);
    q_ = Buffer<Real>(ctx, "floor_q", n_);
    starts_ = Buffer<cl_uint>(ctx, "floor_cell_start", l.cell_start.size());
    new_x_ = Buffer<Real>(ctx, "floor_new_x", n_);
    new_y_ = Buffer<Real>(ctx, "floor_new_y", n_);
    x_.upload(queue_, to_real<Real>(l.x));
    y_.upload(queue_, to_real<Real>(l.y));
    q_.upload(queue_, to_real<Real>(l.q));
    starts_.upload(queue_, std::vector<cl_uint>(l.cell_start.begin(), l.cell_start.end()));
  }

  DeviceFloor::Times run(double dt2) override {
    const FloorLattice& l = lattice_;
    // The host loop's constants, computed as it computes them (sim/pair_floor_kernel.hpp).
    const double minus_four_a = -4.0 * l.lj_a, half_dt2 = 0.5 * dt2;
    ArgSetter(kernel_,
              "pair_floor")(static_cast<cl_int>(n_))(static_cast<cl_int>(l.cells_x))(static_cast<cl_int>(l.cells_y))(
        static_cast<Real>(l.x0))(static_cast<Real>(l.y0))(static_cast<Real>(l.cell))(static_cast<Real>(l.cutoff))(
        static_cast<Real>(minus_four_a))(static_cast<Real>(half_dt2))(x_)(y_)(q_)(starts_)(new_x_)(new_y_);
    const std::size_t global = (n_ + kStepWorkGroup - 1) / kStepWorkGroup * kStepWorkGroup;
    cl::Event event;
    const double cpu0 = process_cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    check(queue_.enqueueNDRangeKernel(kernel_, cl::NullRange, cl::NDRange(global), cl::NDRange(kStepWorkGroup), nullptr,
                                      &event),
          fmt::format("enqueue 'pair_floor' ({} work-items)", global));
    counting::launch();
    check(queue_.finish(), "pair_floor");
    counting::wait();
    DeviceFloor::Times t;
    t.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    t.cpu = process_cpu_seconds() - cpu0;
    cl_ulong start = 0, end = 0;
    check(event.getProfilingInfo(CL_PROFILING_COMMAND_START, &start), "pair_floor's start time");
    check(event.getProfilingInfo(CL_PROFILING_COMMAND_END, &end), "pair_floor's end time");
    t.device = 1e-9 * static_cast<double>(end - start);
    return t;
  }

  void download(std::vector<double>& new_x, std::vector<double>& new_y) override {
    std::vector<Real> a, b;
    new_x_.download(queue_, a);
    new_y_.download(queue_, b);
    new_x.assign(a.begin(), a.end());
    new_y.assign(b.begin(), b.end());
  }

  // As the host floor counts them: five arrays of REAL per node (three read, two written) and the cell starts.
  double bytes() const override {
    return 5.0 * sizeof(Real) * static_cast<double>(n_) + 4.0 * static_cast<double>(lattice_.cell_start.size());
  }

 private:
  const FloorLattice& lattice_;
  std::size_t n_;
  cl::CommandQueue queue_;
  cl::Program program_;
  cl::Kernel kernel_;
  Buffer<Real> x_, y_, q_, new_x_, new_y_;
  Buffer<cl_uint> starts_;
};

}  // namespace

DeviceFloor::DeviceFloor(Context& ctx, const FloorLattice& lattice, Precision precision) {
  if (precision == Precision::Double && !ctx.device().fp64)
    throw DeviceError(
        fmt::format("{} has no double precision (cl_khr_fp64) for the pair-force floor in double", ctx.device().name));
  if (lattice.size() > static_cast<std::size_t>(INT32_MAX) || lattice.cell_start.size() > INT32_MAX)
    throw LimitError(fmt::format("device pair-force floor: {} nodes in {} cells are more than a kernel's int indexes",
                                 lattice.size(), lattice.cell_start.size()));
  if (precision == Precision::Double)
    state_ = std::make_unique<FloorOnDevice<double>>(ctx, lattice, precision);
  else
    state_ = std::make_unique<FloorOnDevice<float>>(ctx, lattice, precision);
}

DeviceFloor::~DeviceFloor() = default;

DeviceFloor::Times DeviceFloor::run(double dt2) { return state_->run(dt2); }

void DeviceFloor::download(std::vector<double>& new_x, std::vector<double>& new_y) { state_->download(new_x, new_y); }

double DeviceFloor::bytes() const { return state_->bytes(); }

DeviceFloorResult measure_device_floor(Context& ctx, const FloorOptions& options, Precision precision) {
  if (options.repeats < 1) throw InputError(fmt::format("pair floor: repeats must be >= 1, got {}", options.repeats));
  const FloorLattice lattice = make_floor_lattice(options);
  DeviceFloor floor(ctx, lattice, precision);
  constexpr double kDt2 = 1e-6;  // as measure_pair_floor: moves of ~1e-4 edges
  DeviceFloorResult r;
  r.device = ctx.device().name;
  r.precision = precision;
  r.nodes = lattice.size();
  r.bytes = floor.bytes();
  r.repeats = options.repeats;
  floor.run(kDt2);  // the first launch: the kernel compiled for the device, pages touched
  for (int k = 0; k < options.repeats; ++k) {
    const DeviceFloor::Times t = floor.run(kDt2);
    if (k == 0 || t.device < r.device_seconds) {
      r.device_seconds = t.device;
      r.cpu_seconds = t.cpu;
    }
    if (k == 0 || t.wall < r.wall_seconds) r.wall_seconds = t.wall;
  }
  return r;
}

std::string format_device_floor(const DeviceFloorResult& r) {
  return fmt::format(
      "device pair-force floor at {} nodes on {} ({}): kernel {:.3f} ms (best of {}, process CPU {:.3f} ms; {:.1f} MB "
      "per iteration, {:.1f} GB/s), wall {:.3f} ms with a finish",
      r.nodes, r.device, r.precision == Precision::Double ? "double" : "float", 1e3 * r.device_seconds, r.repeats,
      1e3 * r.cpu_seconds, 1e-6 * r.bytes, r.device_seconds > 0.0 ? 1e-9 * r.bytes / r.device_seconds : 0.0,
      1e3 * r.wall_seconds);
}

}  // namespace pdmesh::ocl
