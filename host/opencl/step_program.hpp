// The simulation kernels of one device and precision, built once: kernels/spacing_field.cl,
// neighbours.cl, forces.cl, time_step.cl, metric.cl, reduce.cl and device_step.cl in one program, with the shape
// of the force loop chosen for the device (ForceLoop), plus the argument helper every launch uses
// (errors name the kernel and the argument).
#pragma once
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include <fmt/format.h>

#include "opencl/buffer.hpp"
#include "opencl/cl_errors.hpp"
#include "opencl/context.hpp"

namespace pdmesh::ocl {

// Work-group size of every simulation kernel (a power of two: the reductions halve it). 64 measured
// best on PoCL's CPU device among 32/64/128 (docs/opencl.md).
inline constexpr std::size_t kStepWorkGroup = 64;
// Partial sums per group written by the device_step kernel (STEP_PARTIALS in device_step.cl: sum |F|,
// sum kinetic, moving, pairs within, coincident | max |F|, max skin use) and by boundary_snap
// (BOUNDARY_PARTIALS in boundary.cl: clamped count, non-finite targets | max skin use); the program
// builder passes both to the kernels.
inline constexpr std::size_t kStepPartials = 7;
inline constexpr std::size_t kBoundaryPartials = 3;

// The shape of the force loop in kernels/forces.cl (docs/opencl.md, "Force loop"): Vector walks a
// row 8 entries at a time in REAL8 vectors (CPU devices: PoCL does not vectorize across work-items);
// Scalar takes one entry at a time (GPUs: few registers per work-item). Both give the same results
// bit for bit in double. Auto: the environment variable PDMESH_FORCE_LOOP (auto | vector | scalar)
// when set, else Vector on CPU devices and Scalar on every other type.
// (The enum itself is in context.hpp, beside Precision.)
// "auto" | "vector" | "scalar"; anything else throws InputError naming `what` (an option or variable).
ForceLoop parse_force_loop(const std::string& text, const std::string& what);
const char* force_loop_name(ForceLoop loop);
// Never Auto: `requested` unless Auto, then PDMESH_FORCE_LOOP, then the device's type.
ForceLoop resolve_force_loop(ForceLoop requested, const std::string& device_type);

// The device's time-step rule (kernels/window.cl) by a whole work-group (the Scalar shape, for GPUs:
// PDMESH_RULE_GROUP, iteration_rule launched as one group) or by one work-item (the Vector shape: a CPU
// device runs a group's work-items one after the other, so the group's shape only adds work there).
inline bool rule_by_group(ForceLoop loop) { return loop == ForceLoop::Scalar; }
// Step groups the group-wide rule loads at a time (RULE_CHUNK; each work-item kRuleChunk / work_group
// of them): kRuleChunk, or PDMESH_TEST_RULE_CHUNK (1 to kRuleChunk) so that tests' small runs span
// several chunks.
inline constexpr int kRuleChunk = 512;
int rule_chunk();

// The program StepProgram builds, as data (tools/check/kernel_registers.sh compiles the same text for GPU
// targets): its kernel files in build order, and its defines (precision_defines plus
// PDMESH_FORCE_LOOP_VECTOR / PDMESH_FORCE_LOOP_SCALAR, one of them 1). `loop` must not be Auto.
const std::vector<std::string>& step_program_files();
std::map<std::string, std::string> step_program_defines(Precision precision, std::size_t work_group, ForceLoop loop);

// Grid levels the device binning allows (kernels/binning.cl's PDMESH_GRID_LEVELS, which the builder defines):
// the list radii of a run span less than 2^kBinLevels.
inline constexpr int kBinLevels = 64;

// A grid entry (kernels/binning.cl, grid_nodes) holds its node in the low kGridNodeBits bits and, above
// them, a tag of its cell (the top bits of a second hash of the cell), so the gather skips most entries of other
// cells sharing the bucket without loading their positions. Device runs index fewer nodes than this.
inline constexpr int kGridNodeBits = 28;

// Slots of the words a neighbour build leaves for the host: the binning's state (kernels/binning.cl,
// bin_state: kBinHead words, then kBinLevels member counts) and the row counters (kernels/neighbours.cl).
// Defined once here; step_program_defines passes each to the kernels as a define (BIN_FIRST_INVALID,
// ROW_OUTGROWN, ...), so host and kernels index the same slot.
enum BinStateSlot : int {
  kBinFirstInvalid = 0,   // smallest invalid node (non-finite x, y or q, or q <= 0); INT_MAX: none
  kBinTop = 1,            // the top level
  kBinTooManyLevels = 2,  // the radii span more than kBinLevels levels
  kBinBuckets = 3,        // buckets the grids need
  kBinMembers = 4,        // grid entries the grids need
  kBinTooSmall = 5,       // the grids did not fit their capacities
  kBinHead = 8            // the per-level member counts follow
};
enum RowCounter : int {
  kRowOutgrown = 0,   // rows that outgrew their capacities
  kRowEntries = 1,    // entries of all rows
  kRowLargest = 2,    // the largest row (atomic max)
  kRowExamined = 3,   // candidate pairs examined
  kRowWithin = 4,     // pairs within the cut-off (interior rows)
  kRowSpilled = 5,    // entries sent to the spill list
  kRowSpareUsed = 6,  // spare entries taken by moved rows
  kRowMoved = 7,      // rows moved behind the others
  kRowSpareFull = 8,  // the spare region was full: build again
  kRowRatio = 9,      // the largest q_m / q_j of a pair within r_m, j interior, in 1/kRowRatioScale (atomic max)
  kRowCounters = 10   // how many
};
// kRowRatio's fixed point: gather_rows rounds q_m / q_j * kRowRatioScale up (ROW_RATIO_SCALE).
inline constexpr std::uint32_t kRowRatioScale = 4096;
// A node's skin class c (gather_rows, one byte per node) allows it the share 2^(-1 - c / kSkinClassSteps)
// of its skin (SKIN_CLASS_STEPS; opencl/device_run.hpp).
inline constexpr int kSkinClassSteps = 16;
// 2^(k / kSkinClassSteps) for k < kSkinClassSteps (SKIN_CLASS_ROOTS); class c's quotient factor is
// 2^(1 + c / kSkinClassSteps) = (2 << c / kSkinClassSteps) root(c % kSkinClassSteps) on both sides.
inline double skin_class_root(int k) { return std::exp2(static_cast<double>(k) / kSkinClassSteps); }
inline double skin_class_factor(int c) {
  return static_cast<double>(2 << (c / kSkinClassSteps)) * skin_class_root(c % kSkinClassSteps);
}

// What the device allows one kernel of the program (clGetKernelWorkGroupInfo).
struct KernelLimits {
  std::string name;
  std::size_t max_work_group = 0;      // CL_KERNEL_WORK_GROUP_SIZE
  std::size_t preferred_multiple = 0;  // CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE
};

// Throws DeviceError naming the kernel, the device and both sizes when work_group > kernel_limit.
void check_work_group(const std::string& kernel, const std::string& device, std::size_t work_group,
                      std::size_t kernel_limit);
// "" when work_group is a multiple of every kernel's preferred multiple, else what idles (a note, not an error).
std::string work_group_advice(const std::vector<KernelLimits>& limits, std::size_t work_group);

// Builds the program for `precision` and the force loop resolve_force_loop(loop, device type)
// (DeviceError when the device has no fp64 for Double, or the build fails, with the build log) and
// checks every kernel's CL_KERNEL_WORK_GROUP_SIZE against work_group (check_work_group).
struct StepProgram {
  StepProgram(Context& ctx, Precision precision, ForceLoop loop = ForceLoop::Auto,
              std::size_t work_group = kStepWorkGroup);
  Precision precision;
  ForceLoop force_loop;  // as built: Vector or Scalar
  std::size_t work_group;
  cl::Program program;
  cl::Kernel row_capacity_scan, row_level_tally, place_spilled, row_block_offsets, row_offsets_add, gather_rows,
      sort_rows, relocate_rows, apply_row_moves, bin_bounds, bin_rmin, bin_levels, bin_plan, bin_count, bucket_scan,
      bucket_offsets_add, bin_fill, compute_forces, time_step_and_move, apply_momentum, reduce, device_step,
      apply_host_moves, boundary_snap, clearance_points, clearance_points_group,
      refresh_budgets;  // refresh_budgets: launched by the Scalar shape only
  // Metric mode of the StepBackend (kernels/metric.cl).
  cl::Kernel compute_forces_metric, time_step_and_move_metric, apply_momentum_metric, metric_force_norms;
  // Only where the device has cl_khr_fp64 (kernels/window.cl): the rule alone, and boundary_snap with the
  // rule in its last work-group.
  cl::Kernel iteration_rule, boundary_snap_rule;
  std::vector<KernelLimits> limits;  // per kernel, in the order above
};

// Sets arguments 0.. of `kernel` in order; Buffer<T> arguments pass their cl::Buffer.
class ArgSetter {
 public:
  ArgSetter(cl::Kernel& kernel, const char* name) : kernel_(kernel), name_(name) {}
  template <typename T>
  ArgSetter& operator()(Buffer<T>& b) {
    const cl_int err = kernel_.setArg(index_, b.get());
    if (err != CL_SUCCESS) check(err, fmt::format("setting argument {} ('{}') of '{}'", index_, b.name(), name_));
    ++index_;
    return *this;
  }
  template <typename T>
  ArgSetter& operator()(const T& value) {
    static_assert(std::is_arithmetic_v<T>);
    const cl_int err = kernel_.setArg(index_, value);
    if (err != CL_SUCCESS) check(err, fmt::format("setting argument {} of '{}'", index_, name_));
    ++index_;
    return *this;
  }

 private:
  cl::Kernel& kernel_;
  const char* name_;
  cl_uint index_ = 0;
};

// Grows a buffer (new allocation, contents lost) when it holds fewer than `count` elements. The old
// allocation goes first, so that the two are never held together (a device run's peak memory).
template <typename T>
void ensure_size(Context& ctx, Buffer<T>& b, const std::string& name, std::size_t count) {
  if (b.size() < count || b.name().empty()) {
    b = Buffer<T>();
    b = Buffer<T>(ctx, name, count);
  }
}

// Host doubles as the device's REAL.
template <typename Real>
std::vector<Real> to_real(const std::vector<double>& v) {
  return std::vector<Real>(v.begin(), v.end());
}

}  // namespace pdmesh::ocl
