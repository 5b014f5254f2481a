// Builds the simulation program, creates its kernels and checks their work-group limits; see step_program.hpp.
#include "opencl/step_program.hpp"

#include "opencl/device_window.hpp"

#include <atomic>
#include <cstdlib>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "sim/boundary_handling.hpp"

namespace pdmesh::ocl {
namespace {

cl::Kernel make_kernel(cl::Program& program, const char* name) {
  cl_int err = CL_SUCCESS;
  cl::Kernel k(program, name, &err);
  check(err, fmt::format("clCreateKernel({})", name));
  return k;
}

template <cl_kernel_work_group_info Name>
std::size_t group_info(cl::Kernel& k, const cl::Device& device, const char* kernel, const char* what) {
  std::size_t v = 0;
  check(k.getWorkGroupInfo(device, Name, &v), fmt::format("clGetKernelWorkGroupInfo({}, {})", kernel, what));
  return v;
}

}  // namespace

void check_work_group(const std::string& kernel, const std::string& device, std::size_t work_group,
                      std::size_t kernel_limit) {
  if (work_group <= kernel_limit) return;
  throw DeviceError(
      fmt::format("kernel '{}' runs at most {} work-items per group on {} (CL_KERNEL_WORK_GROUP_SIZE: "
                  "too many registers or too much local memory for this device), but pdmesh's kernels "
                  "need groups of {}: simulate on another device or with --device host",
                  kernel, kernel_limit, device, work_group));
}

std::string work_group_advice(const std::vector<KernelLimits>& limits, std::size_t work_group) {
  std::string advice;
  for (const KernelLimits& k : limits)
    if (k.preferred_multiple > 0 && work_group % k.preferred_multiple != 0)
      advice += fmt::format(
          "{}kernel '{}' prefers multiples of {} work-items (CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_"
          "MULTIPLE), the group size {} is not one: part of each group idles",
          advice.empty() ? "" : "; ", k.name, k.preferred_multiple, work_group);
  return advice;
}

namespace {

// Test-only (docs/robustness.md): PDMESH_TEST_FAIL_BUILD=N makes simulation-program builds fail as a
// driver's would until N have failed in this process, to exercise --device auto's fallback.
bool injected_build_failure() {
  static std::atomic<long> failed{0};
  const char* v = std::getenv("PDMESH_TEST_FAIL_BUILD");
  const long wanted = v ? std::strtol(v, nullptr, 10) : 0L;
  if (failed.load() >= wanted) return false;
  ++failed;
  return true;
}

}  // namespace

int rule_chunk() {
  const char* v = std::getenv("PDMESH_TEST_RULE_CHUNK");
  if (!v) return kRuleChunk;
  const long chunk = std::strtol(v, nullptr, 10);
  if (chunk < 1 || chunk > kRuleChunk)
    throw InputError(fmt::format("PDMESH_TEST_RULE_CHUNK must be 1 to {}, got '{}'", kRuleChunk, v));
  return static_cast<int>(chunk);
}

ForceLoop parse_force_loop(const std::string& text, const std::string& what) {
  if (text == "auto") return ForceLoop::Auto;
  if (text == "vector") return ForceLoop::Vector;
  if (text == "scalar") return ForceLoop::Scalar;
  throw InputError(fmt::format("{} must be auto, vector or scalar, got '{}'", what, quote_input(text)));
}

const char* force_loop_name(ForceLoop loop) {
  switch (loop) {
    case ForceLoop::Vector:
      return "vector";
    case ForceLoop::Scalar:
      return "scalar";
    case ForceLoop::Auto:
      break;
  }
  return "auto";
}

ForceLoop resolve_force_loop(ForceLoop requested, const std::string& device_type) {
  if (requested != ForceLoop::Auto) return requested;
  if (const char* v = std::getenv("PDMESH_FORCE_LOOP")) {
    const ForceLoop env = parse_force_loop(v, "the environment variable PDMESH_FORCE_LOOP");
    if (env != ForceLoop::Auto) return env;
  }
  // PoCL's CPU device runs the vector loop as AVX code; a GPU runs work-items as SIMD lanes already,
  // where 8-wide double vectors only cost registers (docs/opencl.md, "Force loop").
  return device_type == "CPU" ? ForceLoop::Vector : ForceLoop::Scalar;
}

const std::vector<std::string>& step_program_files() {
  static const std::vector<std::string> files = {
      "spacing_field.cl", "reduce.cl",    "forces.cl",      "time_step.cl", "metric.cl",  "binning.cl",
      "neighbours.cl",    "clearance.cl", "device_step.cl", "window.cl",    "boundary.cl"};  // boundary_snap_rule calls
                                                                                             // window.cl's rule
  return files;
}

std::map<std::string, std::string> step_program_defines(Precision precision, std::size_t work_group, ForceLoop loop) {
  if (loop == ForceLoop::Auto) throw DeviceError("step_program_defines: the force loop must be resolved (not auto)");
  std::map<std::string, std::string> d = precision_defines(precision, work_group);
  d.emplace("PDMESH_FORCE_LOOP_VECTOR", loop == ForceLoop::Vector ? "1" : "0");
  d.emplace("PDMESH_FORCE_LOOP_SCALAR", loop == ForceLoop::Scalar ? "1" : "0");
  // The GPU shape refreshes clearance budgets in their own kernel (refresh_budgets): device_step keeps
  // fewer registers. The CPU shape keeps it inline: a launch costs more there than the registers.
  d.emplace("PDMESH_REFRESH_KERNEL", loop == ForceLoop::Scalar ? "1" : "0");
  d.emplace("PDMESH_RULE_GROUP", rule_by_group(loop) ? "1" : "0");
  d.emplace("RULE_CHUNK", std::to_string(rule_chunk()));
  d.emplace("PDMESH_GRID_LEVELS", std::to_string(kBinLevels));
  d.emplace("GRID_NODE_BITS", std::to_string(kGridNodeBits));
  d.emplace("STEP_PARTIALS", std::to_string(kStepPartials));
  d.emplace("BOUNDARY_PARTIALS", std::to_string(kBoundaryPartials));
  // kernels/boundary.cl's Jacobi rule: the host's fraction (shortest round-trip text, so the same double).
  d.emplace("MAX_GAP_FRACTION", fmt::format("REAL_C({})", BoundaryHandler::kMaxGapFraction));
  for (const auto& [name, slot] : {std::pair{"BIN_FIRST_INVALID", kBinFirstInvalid},
                                   {"BIN_TOP", kBinTop},
                                   {"BIN_TOO_MANY_LEVELS", kBinTooManyLevels},
                                   {"BIN_BUCKETS", kBinBuckets},
                                   {"BIN_MEMBERS", kBinMembers},
                                   {"BIN_TOO_SMALL", kBinTooSmall},
                                   {"BIN_LEVEL_COUNT", kBinHead}})
    d.emplace(name, std::to_string(static_cast<int>(slot)));
  for (const auto& [name, slot] : {std::pair{"ROW_OUTGROWN", kRowOutgrown},
                                   {"ROW_ENTRIES", kRowEntries},
                                   {"ROW_LARGEST", kRowLargest},
                                   {"ROW_EXAMINED", kRowExamined},
                                   {"ROW_WITHIN", kRowWithin},
                                   {"ROW_SPILLED", kRowSpilled},
                                   {"ROW_SPARE_USED", kRowSpareUsed},
                                   {"ROW_MOVED", kRowMoved},
                                   {"ROW_SPARE_FULL", kRowSpareFull},
                                   {"ROW_RATIO", kRowRatio}})
    d.emplace(name, std::to_string(static_cast<int>(slot)));
  d.emplace("ROW_RATIO_SCALE", std::to_string(kRowRatioScale));
  d.emplace("SKIN_CLASS_STEPS", std::to_string(kSkinClassSteps));
  std::string roots;
  for (int k = 0; k < kSkinClassSteps; ++k)
    // Shortest round trip (the same double), always with a point or an exponent: REAL_C(1.0) pastes an f in float.
    roots += fmt::format("{}REAL_C({:#})", k ? ", " : "", skin_class_root(k));
  d.emplace("SKIN_CLASS_ROOTS", roots);
  for (const auto& [name, value] : window_defines())
    if (!d.emplace(name, value).second)
      throw DeviceError(fmt::format("step program: the define {} is given twice", name));
  return d;
}

StepProgram::StepProgram(Context& ctx, Precision p, ForceLoop loop, std::size_t wg)
    : precision(p), force_loop(resolve_force_loop(loop, ctx.device().type)), work_group(wg) {
  if (p == Precision::Double && !ctx.device().fp64)
    throw DeviceError(
        fmt::format("{} has no double precision (cl_khr_fp64): use --precision float", ctx.device().name));
  if (injected_build_failure())
    throw DeviceError(
        fmt::format("building OpenCL program on {} failed: CL_BUILD_PROGRAM_FAILURE (-11) (injected by "
                    "PDMESH_TEST_FAIL_BUILD)\nbuild log:\n(none)",
                    ctx.device().name));
  program = ctx.build(step_program_files(), step_program_defines(p, wg, force_loop));
  const std::pair<cl::Kernel*, const char*> kernels[] = {{&row_capacity_scan, "row_capacity_scan"},
                                                         {&row_block_offsets, "row_block_offsets"},
                                                         {&row_offsets_add, "row_offsets_add"},
                                                         {&gather_rows, "gather_rows"},
                                                         {&sort_rows, "sort_rows"},
                                                         {&bin_bounds, "bin_bounds"},
                                                         {&bin_rmin, "bin_rmin"},
                                                         {&bin_levels, "bin_levels"},
                                                         {&bin_plan, "bin_plan"},
                                                         {&bin_count, "bin_count"},
                                                         {&bucket_scan, "bucket_scan"},
                                                         {&bucket_offsets_add, "bucket_offsets_add"},
                                                         {&bin_fill, "bin_fill"},
                                                         {&relocate_rows, "relocate_rows"},
                                                         {&apply_row_moves, "apply_row_moves"},
                                                         {&row_level_tally, "row_level_tally"},
                                                         {&place_spilled, "place_spilled"},
                                                         {&compute_forces, "compute_forces"},
                                                         {&time_step_and_move, "time_step_and_move"},
                                                         {&apply_momentum, "apply_momentum"},
                                                         {&reduce, "reduce"},
                                                         {&device_step, "device_step"},
                                                         {&apply_host_moves, "apply_host_moves"},
                                                         {&boundary_snap, "boundary_snap"},
                                                         {&clearance_points, "clearance_points"},
                                                         {&clearance_points_group, "clearance_points_group"},
                                                         {&refresh_budgets, "refresh_budgets"},
                                                         {&compute_forces_metric, "compute_forces_metric"},
                                                         {&time_step_and_move_metric, "time_step_and_move_metric"},
                                                         {&apply_momentum_metric, "apply_momentum_metric"},
                                                         {&metric_force_norms, "metric_force_norms"}};
  // Every kernel declares reqd_work_group_size(WG_SIZE): a device that cannot run a group that size
  // (registers, local memory) would fail at the first enqueue with CL_INVALID_WORK_GROUP_SIZE or
  // CL_OUT_OF_RESOURCES; checked here, it fails before the run with the reason.
  for (const auto& [kernel, name] : kernels) {
    *kernel = make_kernel(program, name);
    KernelLimits k{
        name, group_info<CL_KERNEL_WORK_GROUP_SIZE>(*kernel, ctx.device().handle, name, "CL_KERNEL_WORK_GROUP_SIZE"),
        group_info<CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE>(*kernel, ctx.device().handle, name,
                                                                 "CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE")};
    check_work_group(name, ctx.device().name, wg, std::min(k.max_work_group, ctx.device().max_work_group));
    limits.push_back(k);
  }
  // kernels/window.cl needs cl_khr_fp64 (the time-step rule's state is double); without it the host
  // runs the rule (DeviceWindow).
  if (ctx.device().fp64) {
    iteration_rule = make_kernel(program, "iteration_rule");
    boundary_snap_rule = make_kernel(program, "boundary_snap_rule");
    const char* name = "boundary_snap_rule";
    KernelLimits k{name,
                   group_info<CL_KERNEL_WORK_GROUP_SIZE>(boundary_snap_rule, ctx.device().handle, name,
                                                         "CL_KERNEL_WORK_GROUP_SIZE"),
                   group_info<CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE>(
                       boundary_snap_rule, ctx.device().handle, name, "CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE")};
    check_work_group(name, ctx.device().name, wg, std::min(k.max_work_group, ctx.device().max_work_group));
    limits.push_back(k);
  }
}

}  // namespace pdmesh::ocl
