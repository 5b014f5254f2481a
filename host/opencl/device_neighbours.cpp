// The neighbour build on the device: binning, row sizing, gather and sort; see device_neighbours.hpp.
#include "opencl/device_neighbours.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>

#include <fmt/format.h>

#include "core/errors.hpp"

namespace pdmesh::ocl {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

constexpr std::array<std::uint32_t, kRowCounters> kZeroCounters{};

// kernels/binning.cl's bin_state: its initial contents (slots: step_program.hpp).
constexpr std::size_t kBinStateSize = kBinHead + kBinLevels;
const std::array<std::int32_t, kBinStateSize> kBinStateInit = [] {
  std::array<std::int32_t, kBinStateSize> a{};
  a[kBinFirstInvalid] = std::numeric_limits<std::int32_t>::max();
  return a;
}();

std::uint64_t with_slack(std::uint64_t v) { return v + v / 8 + 64; }

// Sizes a grid buffer to `count` elements: grown when smaller, and made again when it holds more than
// half as many again (the first build's guess, or a node set that shrank), the old allocation first.
template <typename T>
void fit_size(Context& ctx, Buffer<T>& b, const std::string& name, std::size_t count) {
  if (b.size() > count + count / 2) b = Buffer<T>();
  ensure_size(ctx, b, name, count);
}

// row_level_tally's output: per level its interior rows' sampled counts and nodes, then the boundary nodes.
constexpr std::size_t kTallySize = 2 * kBinLevels + 1;

}  // namespace

template <typename Real>
std::size_t DeviceNeighbours<Real>::device_bytes() const {
  return count_.bytes() + offset_.bytes() + block_total_.bytes() + index_.bytes() + level_.bytes() +
         bin_state_.bytes() + grid_mask_.bytes() + grid_bucket_offset_.bytes() + grid_inv_cell_.bytes() +
         bucket_.bytes() + grid_nodes_.bytes() + bin_partial_.bytes() + counters_.bytes() + spill_.bytes() +
         move_node_.bytes() + move_start_.bytes() + level_cap_.bytes() + tally_.bytes() + skin_class_.bytes();
}

template <typename Real>
int DeviceNeighbours<Real>::stride_for(std::size_t n) const {
  if (sample_stride > 0) return sample_stride;
  // Tests of whole runs force a stride on their small cases (tests/test_device_simulation.cpp).
  if (const char* v = std::getenv("PDMESH_TEST_SAMPLE_STRIDE")) return std::max(1, std::atoi(v));
  return n >= kSampleFrom ? kSampleStride : 1;
}

template <typename Real>
NeighbourFlags DeviceNeighbours<Real>::build(std::size_t n, double radius_factor, Buffer<Real>& xy, Buffer<Real>& q,
                                             Buffer<std::uint8_t>& kind, Buffer<std::int32_t>& prev,
                                             Buffer<std::int32_t>& next, double pair_skin) {
  NeighbourFlags flags;
  attempts = 0;
  sampled = false;
  launches = 0;
  outgrown_rows = 0;
  spacing_ratio = 0.0;
  uploaded_bytes = 0;
  const auto t0 = std::chrono::steady_clock::now();
  ensure_size(ctx_, counters_, "neighbour_counters", kZeroCounters.size());
  ensure_size(ctx_, offset_, "neighbour_offset", n + 1);
  const bool have_counts = keep_counts(n);
  if (n == 0) {
    build_empty();
    gather_seconds = seconds_since(t0);
    return flags;
  }
  if (n >= (std::size_t{1} << kGridNodeBits))
    throw LimitError(fmt::format("{} nodes are more than the device neighbour build indexes ({} at most)", n,
                                 (std::size_t{1} << kGridNodeBits) - 1));
  const std::size_t wg = program_.work_group;
  const BuildArgs a{n, wg, (n + wg - 1) / wg, static_cast<Real>(radius_factor), xy, q, kind, prev, next};
  size_node_buffers(a);
  pair_skin_ = static_cast<Real>(pair_skin);
  std::vector<std::uint32_t> c;
  run_passes(a, have_counts, flags, c);
  if (flags.first_invalid < 0) {
    flags.max_count = static_cast<std::int32_t>(c[kRowLargest]);
    flags.pairs_examined = c[kRowExamined];
    flags.pairs_within = c[kRowWithin];
    spacing_ratio = static_cast<double>(c[kRowRatio]) / kRowRatioScale;
  }
  gather_seconds = seconds_since(t0);
  return flags;
}

// Whether count_ holds the last build's counts of these n nodes. The counts of another node set say
// nothing about these rows: then they start from zero (a counting build).
template <typename Real>
bool DeviceNeighbours<Real>::keep_counts(std::size_t n) {
  if (n == counted_n_ && count_.size() >= n) return true;
  ensure_size(ctx_, count_, "neighbour_count", n);
  if (n > 0) fill_zero(ctx_.queue(), count_.get(), n * sizeof(cl_int), "clearing 'neighbour_count'");
  counted_total_ = 0;
  return false;
}

// No nodes: an empty row layout, and the buffers the kernels take as arguments all the same.
template <typename Real>
void DeviceNeighbours<Real>::build_empty() {
  fill_zero(ctx_.queue(), offset_.get(), sizeof(cl_ulong), "clearing 'neighbour_offset'");
  ensure_size(ctx_, index_, "neighbour_index", kRowTail);
  ensure_size(ctx_, skin_class_, "skin_class", 1);  // a kernel argument even without nodes
  counted_n_ = 0;
}

template <typename Real>
void DeviceNeighbours<Real>::size_node_buffers(const BuildArgs& a) {
  ensure_size(ctx_, level_, "level", a.n);
  ensure_size(ctx_, skin_class_, "skin_class", a.n);
  ensure_size(ctx_, bin_state_, "bin_state", kBinStateSize);
  ensure_size(ctx_, bin_partial_, "bin_partial", a.groups + 1);
  ensure_size(ctx_, grid_mask_, "grid_mask", kBinLevels);
  ensure_size(ctx_, grid_bucket_offset_, "grid_bucket_offset", kBinLevels);
  ensure_size(ctx_, grid_inv_cell_, "grid_inv_cell", kBinLevels);
  ensure_size(ctx_, level_cap_, "neighbour_level_cap", kBinLevels);
  // First guesses for the grids (one entry per node and level with nodes, a bucket per two): a
  // build that finds them too small reports the sizes it needs and runs again.
  if (member_capacity_ == 0) member_capacity_ = with_slack(4 * static_cast<std::uint64_t>(a.n));
  if (bucket_capacity_ == 0) bucket_capacity_ = with_slack(2 * static_cast<std::uint64_t>(a.n));
}

// The passes of a build until its rows are whole (or a node is invalid): c receives the last pass's
// counters. Without counts: every stride-th node's scan is counted, and the rows are laid out with
// capacities estimated from that sample (stride 1: an exact counting pass, then the rows at those counts).
template <typename Real>
void DeviceNeighbours<Real>::run_passes(const BuildArgs& a, bool have_counts, NeighbourFlags& flags,
                                        std::vector<std::uint32_t>& c) {
  const int stride = have_counts ? 1 : stride_for(a.n);
  bool estimate = false;  // rows laid out with the sampled estimate (level_cap_)
  bool binned = false;    // the grids of these positions are built (an earlier pass of this build)
  for (int attempt = 0;; ++attempt) {
    const PassCapacities caps = size_pass_buffers(a, binned);
    if (!binned) bin(a, caps);
    // Without counts: count (a sample, or every row), then build with the estimate or the counts.
    const bool counting = !have_counts && !estimate;
    counters_.upload(ctx_.queue(), kZeroCounters.data(), kZeroCounters.size(), false);
    uploaded_bytes += sizeof(kZeroCounters);
    if (counting && stride > 1) {
      bool grids_fit = false;
      if (!sample_counts(a, stride, flags, grids_fit)) return;
      if (grids_fit) binned = estimate = sampled = true;
      continue;  // not a pass of its own: attempts counts whole gathers
    }
    gather_pass(a, caps, counting, estimate && !have_counts);
    // The build's one wait: the counters and the binning's state.
    bin_state_.download(ctx_.queue(), state_host_, kBinHead, false);
    counters_.download(ctx_.queue(), c, kZeroCounters.size());
    bool grids_fit = false;
    if (!take_bin_state(a.n, flags, grids_fit)) return;
    if (grids_fit) {
      binned = true;
      have_counts = true;
      outgrown_rows += c[kRowOutgrown];
      counted_n_ = a.n;
      counted_total_ = c[kRowEntries];
      // Rows that outgrew their capacities were moved behind the others, unless the spill list, the
      // move list or the spare region was too small: then build again with the counts (exact now).
      if (!counting && (c[kRowOutgrown] == 0 ||
                        (c[kRowSpilled] <= caps.spill && c[kRowOutgrown] <= caps.move && c[kRowSpareFull] == 0)))
        return;
    }
    if (attempt >= 4)
      throw SimulationError(fmt::format("neighbour rows still outgrow their capacities after {} passes", attempt + 1));
  }
}

// The buffers of one pass at the capacities the build knows now (the grids' only when they are to
// be built again).
template <typename Real>
typename DeviceNeighbours<Real>::PassCapacities DeviceNeighbours<Real>::size_pass_buffers(const BuildArgs& a,
                                                                                          bool binned) {
  constexpr std::uint64_t kMaxIndex = std::numeric_limits<std::int32_t>::max();
  if (bucket_capacity_ > kMaxIndex || member_capacity_ > kMaxIndex)
    throw SimulationError(
        fmt::format("the neighbour grids of {} nodes need {} buckets and {} entries, more than "
                    "the device binning indexes (2^31)",
                    a.n, bucket_capacity_, member_capacity_));
  // A pass after one whose grids fit (a counting pass, or rows that outgrew) keeps those grids: the
  // positions are the same. Growing a grid buffer would drop its contents.
  if (!binned) {
    fit_size(ctx_, bucket_, "grid_bucket", bucket_capacity_);
    fit_size(ctx_, grid_nodes_, "grid_nodes", member_capacity_);
  }
  PassCapacities caps;
  caps.buckets = bucket_.size();
  caps.bucket_groups = (caps.buckets + a.wg - 1) / a.wg;
  ensure_size(ctx_, block_total_, "neighbour_block_total", std::max(a.groups, caps.bucket_groups) + 1);
  // Every capacity sum bounds offset[n]: sum(c + c >> s + m) <= total + total >> s + m n (an
  // estimated layout's sum is the same with the estimated total); behind the rows a spare region
  // for the rows that outgrow their capacities (relocate_rows). The spill list holds the entries
  // past the capacities (a few per outgrown row), the move list the outgrown rows: n / 64 rows, as
  // many rows of the mean count as half the spare region holds. A layout from the last counts can
  // leave more outgrown rows early in a run's transient than a smaller list holds, and a list
  // that overflows makes the build gather twice (docs/opencl.md, the rebuild's commands).
  const std::uint64_t spare_capacity = std::max<std::uint64_t>(4096, counted_total_ / 64);
  caps.spill = std::max<std::uint64_t>(4096, counted_total_ / 256);
  caps.move = std::max<std::uint64_t>(1024, a.n / 64);
  const std::uint64_t bound = counted_total_ + (counted_total_ >> kSpareShift) +
                              static_cast<std::uint64_t>(kSpareMin) * a.n + 2 * spare_capacity + kRowTail;
  ensure_size(ctx_, spill_, "neighbour_spill", 2 * caps.spill);
  ensure_size(ctx_, move_node_, "neighbour_move_node", caps.move);
  ensure_size(ctx_, move_start_, "neighbour_move_start", caps.move);
  if (index_.size() < bound) {
    if (check_entries) check_entries(bound);
    ensure_size(ctx_, index_, "neighbour_index", bound);
    // Slack slots are read (masked) by the vector force loop: give them defined contents.
    fill_zero(ctx_.queue(), index_.get(), index_.size() * sizeof(cl_int), "clearing 'neighbour_index'");
  }
  caps.entries = index_.size() - kRowTail;
  return caps;
}

// Binning (kernels/binning.cl): the grid levels and buckets of the positions, nodes sorted into them.
template <typename Real>
void DeviceNeighbours<Real>::bin(const BuildArgs& a, const PassCapacities& caps) {
  const auto n_arg = static_cast<cl_int>(a.n), groups_arg = static_cast<cl_int>(a.groups);
  const std::size_t n = a.n, wg = a.wg, buckets = caps.buckets;
  bin_state_.upload(ctx_.queue(), kBinStateInit.data(), kBinStateInit.size(), false);
  uploaded_bytes += sizeof(kBinStateInit);
  ArgSetter(program_.bin_bounds, "bin_bounds")(n_arg)(a.radius)(a.xy)(a.q)(bin_partial_)(bin_state_);
  launch(ctx_.queue(), program_.bin_bounds, "bin_bounds", n, wg);
  ArgSetter(program_.bin_rmin, "bin_rmin")(groups_arg)(bin_partial_);
  launch(ctx_.queue(), program_.bin_rmin, "bin_rmin", wg, wg);
  ArgSetter(program_.bin_levels, "bin_levels")(n_arg)(groups_arg)(a.radius)(a.q)(bin_partial_)(level_)(bin_state_);
  launch(ctx_.queue(), program_.bin_levels, "bin_levels", n, wg);
  ArgSetter(program_.bin_plan, "bin_plan")(n_arg)(groups_arg)(static_cast<cl_uint>(buckets))(static_cast<cl_uint>(
      grid_nodes_.size()))(bin_partial_)(bin_state_)(grid_mask_)(grid_bucket_offset_)(grid_inv_cell_);
  launch(ctx_.queue(), program_.bin_plan, "bin_plan", wg, wg);
  fill_zero(ctx_.queue(), bucket_.get(), buckets * sizeof(cl_uint), "clearing 'grid_bucket'");
  ArgSetter(program_.bin_count,
            "bin_count")(n_arg)(a.xy)(level_)(bin_state_)(grid_mask_)(grid_bucket_offset_)(grid_inv_cell_)(bucket_);
  launch(ctx_.queue(), program_.bin_count, "bin_count", n, wg);
  ArgSetter(program_.bucket_scan, "bucket_scan")(static_cast<cl_uint>(buckets))(bucket_)(block_total_);
  launch(ctx_.queue(), program_.bucket_scan, "bucket_scan", buckets, wg);
  ArgSetter(program_.row_block_offsets, "row_block_offsets")(static_cast<cl_int>(caps.bucket_groups))(block_total_);
  launch(ctx_.queue(), program_.row_block_offsets, "row_block_offsets", wg, wg);
  ArgSetter(program_.bucket_offsets_add, "bucket_offsets_add")(static_cast<cl_uint>(buckets))(bucket_)(block_total_);
  launch(ctx_.queue(), program_.bucket_offsets_add, "bucket_offsets_add", buckets, wg);
  ArgSetter(program_.bin_fill, "bin_fill")(n_arg)(a.xy)(
      level_)(bin_state_)(grid_mask_)(grid_bucket_offset_)(grid_inv_cell_)(bucket_)(grid_nodes_);
  launch(ctx_.queue(), program_.bin_fill, "bin_fill", n, wg);
  launches += 9;
}

// The sample: every stride-th node's counts summed per level (row_level_tally); nothing else of a
// build. False when a node is invalid; grids_fit: the grids held every node, and the level capacities
// are set from the sample (set_level_caps).
template <typename Real>
bool DeviceNeighbours<Real>::sample_counts(const BuildArgs& a, int stride, NeighbourFlags& flags, bool& grids_fit) {
  const auto n_arg = static_cast<cl_int>(a.n);
  ensure_size(ctx_, tally_, "neighbour_level_tally", kTallySize);
  fill_zero(ctx_.queue(), tally_.get(), kTallySize * sizeof(cl_uint), "clearing 'neighbour_level_tally'");
  fill_zero(ctx_.queue(), count_.get(), a.n * sizeof(cl_int), "clearing 'neighbour_count'");
  gather(n_arg, a.radius, a.xy, a.q, a.kind, a.prev, a.next, 0, 0, true, stride);
  ArgSetter(program_.row_level_tally, "row_level_tally")(n_arg)(a.kind)(level_)(count_)(tally_);
  launch(ctx_.queue(), program_.row_level_tally, "row_level_tally", a.n, a.wg);
  launches += 2;
  std::vector<std::uint32_t> tally;
  bin_state_.download(ctx_.queue(), state_host_, kBinHead, false);
  tally_.download(ctx_.queue(), tally, kTallySize);
  if (!take_bin_state(a.n, flags, grids_fit)) return false;
  if (grids_fit) counted_total_ = set_level_caps(tally, stride);
  return true;
}

// One pass of rows (kernels/neighbours.cl): laid out from the counts (or with estimated, the level
// capacities), gathered, sorted, and the rows that outgrew their capacities moved behind the others.
// A counting pass moves nothing (move capacity 0): the next pass builds with the counts.
template <typename Real>
void DeviceNeighbours<Real>::gather_pass(const BuildArgs& a, const PassCapacities& caps, bool counting,
                                         bool estimated) {
  const auto n_arg = static_cast<cl_int>(a.n), groups_arg = static_cast<cl_int>(a.groups);
  const std::size_t n = a.n, wg = a.wg;
  const cl_ulong entries_size = caps.entries;
  const auto spill_capacity = static_cast<cl_uint>(caps.spill);
  const auto move_capacity = static_cast<cl_uint>(counting ? 0 : caps.move);
  ArgSetter(program_.row_capacity_scan,
            "row_capacity_scan")(n_arg)(static_cast<cl_int>(kSpareShift))(static_cast<cl_int>(kSpareMin))(
      count_)(static_cast<cl_int>(estimated ? 1 : 0))(a.kind)(level_)(level_cap_)(offset_)(block_total_);
  launch(ctx_.queue(), program_.row_capacity_scan, "row_capacity_scan", n, wg);
  ArgSetter(program_.row_block_offsets, "row_block_offsets")(groups_arg)(block_total_);
  launch(ctx_.queue(), program_.row_block_offsets, "row_block_offsets", wg, wg);
  // row_offsets_add also zeroes the counts for the gather (when the grids fit: see the kernel).
  ArgSetter(program_.row_offsets_add, "row_offsets_add")(n_arg)(offset_)(block_total_)(bin_state_)(count_);
  launch(ctx_.queue(), program_.row_offsets_add, "row_offsets_add", n, wg);
  gather(n_arg, a.radius, a.xy, a.q, a.kind, a.prev, a.next, entries_size, caps.spill, counting, 1);
  ++attempts;
  ArgSetter(program_.sort_rows,
            "sort_rows")(n_arg)(a.kind)(offset_)(count_)(entries_size)(index_)(counters_)(bin_state_)(spill_capacity);
  launch(ctx_.queue(), program_.sort_rows, "sort_rows", n, wg);
  ArgSetter(program_.relocate_rows, "relocate_rows")(n_arg)(a.kind)(
      offset_)(count_)(entries_size)(index_)(spill_capacity)(spill_)(move_capacity)(move_node_)(move_start_)(counters_);
  launch(ctx_.queue(), program_.relocate_rows, "relocate_rows", n, wg);
  ArgSetter(program_.place_spilled,
            "place_spilled")(n_arg)(offset_)(index_)(spill_capacity)(spill_)(move_capacity)(counters_);
  launch(ctx_.queue(), program_.place_spilled, "place_spilled", caps.spill, wg);
  ArgSetter(program_.apply_row_moves, "apply_row_moves")(move_node_)(move_start_)(counters_)(count_)(index_)(offset_);
  launch(ctx_.queue(), program_.apply_row_moves, "apply_row_moves", caps.move, wg);
  launches += 8;
}

template <typename Real>
void DeviceNeighbours<Real>::release_rows() {
  index_ = Buffer<std::int32_t>();
  release_build_scratch();
}

template <typename Real>
void DeviceNeighbours<Real>::release_build_scratch() {
  grid_nodes_ = Buffer<std::int32_t>();
  bucket_ = Buffer<std::uint32_t>();
  level_ = Buffer<std::int32_t>();
  spill_ = Buffer<std::int32_t>();
  move_node_ = Buffer<std::int32_t>();
  move_start_ = Buffer<std::uint64_t>();
}

template <typename Real>
void DeviceNeighbours<Real>::carry_counts(const std::vector<int>& old_of_new, std::size_t old_n) {
  if (old_n == 0 || counted_n_ != old_n || count_.size() < old_n || old_of_new.empty()) return;
  std::vector<std::int32_t> old_counts;
  count_.download(ctx_.queue(), old_counts, old_n);
  const std::size_t n = old_of_new.size();
  std::vector<std::int32_t> counts(n);
  const auto mean = static_cast<std::int32_t>(counted_total_ / old_n);
  std::uint64_t total = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const int old = old_of_new[k];
    counts[k] = old >= 0 && static_cast<std::size_t>(old) < old_n
                    ? std::max(old_counts[static_cast<std::size_t>(old)], 0)
                    : mean;
    total += static_cast<std::uint64_t>(counts[k]);
  }
  ensure_size(ctx_, count_, "neighbour_count", n);
  count_.upload(ctx_.queue(), counts.data(), n);
  uploaded_bytes += n * sizeof(std::int32_t);
  counted_n_ = n;
  counted_total_ = total;
}

// The binning's state after a wait (state_host_): false when a node is invalid (flags.first_invalid
// set; no rows are built, and the counts are of no rows). Otherwise the grid capacities grow to what
// the binning needed, and grids_fit says whether these grids held every node.
template <typename Real>
bool DeviceNeighbours<Real>::take_bin_state(std::size_t n, NeighbourFlags& flags, bool& grids_fit) {
  const std::vector<std::int32_t>& state = state_host_;
  if (state[kBinFirstInvalid] < static_cast<std::int32_t>(n)) {
    flags.first_invalid = state[kBinFirstInvalid];
    counted_n_ = 0;
    return false;
  }
  if (state[kBinTooManyLevels])
    throw SimulationError(
        fmt::format("the list radii of the nodes span more than 2^{}: the device binning has {} "
                    "grid levels at most",
                    kBinLevels, kBinLevels));
  // What this binning needed, with slack, also when that is less than the first guess (4n entries,
  // 2n buckets): the next build's grids shrink to it (fit_size). The sizes decide only whether a build
  // bins again, never the grids' layout (bin_plan's masks come from the level counts).
  member_capacity_ = with_slack(static_cast<std::uint64_t>(state[kBinMembers]));
  bucket_capacity_ = with_slack(static_cast<std::uint64_t>(state[kBinBuckets]));
  grids_fit = state[kBinTooSmall] == 0;
  return true;
}

template <typename Real>
void DeviceNeighbours<Real>::gather(cl_int n_arg, Real radius, Buffer<Real>& xy, Buffer<Real>& q,
                                    Buffer<std::uint8_t>& kind, Buffer<std::int32_t>& prev, Buffer<std::int32_t>& next,
                                    cl_ulong entries_size, std::uint64_t spill_capacity, bool counting, int stride) {
  ArgSetter(program_.gather_rows, "gather_rows")(n_arg)(
      radius)(xy)(q)(kind)(prev)(next)(level_)(bin_state_)(grid_mask_)(grid_bucket_offset_)(grid_inv_cell_)(bucket_)(grid_nodes_)(offset_)(count_)(entries_size)(index_)(static_cast<
                                                                                                                                                                         cl_uint>(
      spill_capacity))(spill_)(counters_)(static_cast<cl_int>(counting ? 1 : 0))(static_cast<cl_int>(stride))(
      skin_class_)(pair_skin_);
  const std::size_t items =
      (static_cast<std::size_t>(n_arg) + static_cast<std::size_t>(stride) - 1) / static_cast<std::size_t>(stride);
  launch(ctx_.queue(), program_.gather_rows, "gather_rows", items, program_.work_group);
}

// Per level L with interior nodes: their mean count m = stride x (sampled counts) / (nodes), and the
// capacity every interior row of L gets, c + (c >> kSpareShift) + kSpareMin for c = m rounded: the
// layout a build from counts would make if every row had its level's mean. Returns the estimated
// entries of all rows (the boundary rows' 2 each included), which sizes the index like a total.
template <typename Real>
std::uint64_t DeviceNeighbours<Real>::set_level_caps(const std::vector<std::uint32_t>& tally, int stride) {
  std::vector<std::int32_t> cap(kBinLevels, kSpareMin);
  std::uint64_t total = 2 * static_cast<std::uint64_t>(tally[2 * kBinLevels]);
  for (int L = 0; L < kBinLevels; ++L) {
    const std::uint64_t nodes = tally[2 * L + 1];
    if (nodes == 0) continue;
    const std::uint64_t sum = static_cast<std::uint64_t>(tally[2 * L]) * static_cast<std::uint64_t>(stride);
    const std::uint64_t mean = (sum + nodes / 2) / nodes;
    const std::uint64_t c =
        std::min<std::uint64_t>(mean + (mean >> kSpareShift) + kSpareMin, std::numeric_limits<std::int32_t>::max());
    cap[static_cast<std::size_t>(L)] = static_cast<std::int32_t>(c);
    total += mean * nodes;
  }
  level_cap_.upload(ctx_.queue(), cap, true);
  uploaded_bytes += cap.size() * sizeof(std::int32_t);
  return total;
}

template class DeviceNeighbours<double>;
template class DeviceNeighbours<float>;

}  // namespace pdmesh::ocl
