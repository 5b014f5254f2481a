// Neighbour lists on the device in compact rows (CSR), built on the device from the device's
// positions: binning by a counting sort into the multi-level grids (kernels/binning.cl), the rows
// sized by a prefix sum over capacities, gathered with integer atomics per row and sorted
// (kernels/neighbours.cl); the host enqueues the kernels and reads 13 ints at the end (one wait).
// Used by the StepBackend and the device-resident run. neighbour_grids.hpp is the host's binning,
// the oracle of the device's (tests/test_device_neighbours.cpp).
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "opencl/buffer.hpp"
#include "opencl/step_program.hpp"
#include "sim/step_backend.hpp"

namespace pdmesh::ocl {

// Row i of a build holds count()[i] entries at index()[offset()[i] ..] (64-bit offsets, n + 1 of them;
// offset[i + 1] - offset[i] is the row's capacity, >= its count). Interior rows are sorted ascending,
// boundary rows are [prev, next]: the reference's rows (host/sim/reference/binning.cpp), slot by slot,
// never truncated. index() has kRowTail readable entries past offset[n] (the vector force loop reads
// whole chunks of 8).
inline constexpr std::size_t kRowTail = 8;

template <typename Real>
class DeviceNeighbours {
 public:
  DeviceNeighbours(Context& ctx, StepProgram& program) : ctx_(ctx), program_(program) {}
  // A build that throws may leave the non-blocking read into state_host_ in flight: wait for it
  // before the vector goes (the error is moot here).
  ~DeviceNeighbours() { ctx_.queue().finish(); }
  DeviceNeighbours(const DeviceNeighbours&) = delete;
  DeviceNeighbours& operator=(const DeviceNeighbours&) = delete;

  // Builds the rows of n nodes (device arrays xy: 2n positions, x and y interleaved as the step keeps
  // them; q, kind, prev, next), interior radius radius_factor * q_i. Grid and row capacities are those
  // of the last build plus slack (kSpareShift, kSpareMin; after a population event those carried over,
  // carry_counts); a build without them (a run's first, or after the node set changed size without
  // carry_counts) counts a sample of the rows (every stride_for(n)-th node's scan)
  // and gives every interior row its level's estimated capacity. Rows that outgrow their capacities
  // move behind the others in the same pass; when too many do (or the grids outgrow theirs) the build
  // runs again at the sizes it found (exact). With stride 1 the sample is an exact counting pass.
  // Sets the flags (first_invalid: the smallest node with a non-finite x, y or q, or q <= 0, whose
  // rows are then not built; overflow stays 0: rows are never truncated). Before the index buffer
  // grows, check_entries (when set) is called with its new size: it throws when the device cannot
  // hold it (the device-resident run's check_device_memory).
  // pair_skin = s c > 0 (radius_factor = c (1 + s)): a finer interior row also takes each coarser
  // node m within c q_i + s c q_m (the device run's lists, kernels/neighbours.cl); 0: the reference's rows.
  NeighbourFlags build(std::size_t n, double radius_factor, Buffer<Real>& xy, Buffer<Real>& q,
                       Buffer<std::uint8_t>& kind, Buffer<std::int32_t>& prev, Buffer<std::int32_t>& next,
                       double pair_skin = 0.0);

  // After a population event renumbered the nodes (new node k was old node old_of_new[k], or is new
  // when that is < 0): the last build's counts carried over to the new numbering, a new node's its
  // neighbours' mean, so that the next build lays its rows out from them instead of counting first (an
  // extra gather per event). Only the layout depends on the counts: the rows are the same, and those
  // that outgrow their estimate move as in any build. Nothing happens without counts of old_n nodes.
  void carry_counts(const std::vector<int>& old_of_new, std::size_t old_n);
  // Frees the rows and the build's scratch (release_build_scratch): the next build makes them again
  // at its own capacities. The counts, offsets and skin classes stay, so that the next build may lay
  // its rows out from the counts. For a population event's host work, which sets a device run's peak
  // memory while the lists wait for a rebuild.
  void release_rows();
  // Frees what only a build reads (the grids' nodes and buckets, the levels, the spill and move
  // lists): every build bins again and sizes them from the capacities the last one found, which stay.
  // The rows, counts, offsets and skin classes (what the step reads) stay. For a device run between
  // builds, where these would sit beside a convergence check's triangulation; the grid accessors
  // below are then empty until the next build.
  void release_build_scratch();

  // A row's capacity is c + (c >> kSpareShift) + kSpareMin for the count c of the last build: rows
  // grow a little between rebuilds as nodes move (docs/opencl.md, "Neighbour lists: Verlet skin").
  static constexpr int kSpareShift = 3, kSpareMin = 2;
  // A build without counts samples every kSampleStride-th node's scan from kSampleFrom nodes on (a
  // counting pass costs about a gather: at 1M nodes a quarter of a 20-iteration run's gathers); below,
  // it counts every row (exact: fewer moved rows, and the pass is cheap). sample_stride > 0 overrides
  // it (tests).
  static constexpr int kSampleStride = 16;
  static constexpr std::size_t kSampleFrom = 65536;
  int sample_stride = 0;
  int stride_for(std::size_t n) const;

  Buffer<std::int32_t>& count() { return count_; }
  Buffer<std::uint64_t>& offset() { return offset_; }
  Buffer<std::int32_t>& index() { return index_; }
  // Per node its skin class from the last build (kernels/neighbours.cl, gather_rows; n entries).
  Buffer<std::uint8_t>& skin_class() { return skin_class_; }
  std::size_t device_bytes() const;
  std::function<void(std::uint64_t entries)> check_entries;
  // The device grids of the last build (kernels/binning.cl): per node its level; per level L its
  // bucket mask (-1: no grid), first bucket and inverse cell size; bucket b of all grids holds
  // grid_nodes[bucket[b - 1] .. bucket[b]) (0 for b = 0).
  Buffer<std::int32_t>& level() { return level_; }
  Buffer<std::int32_t>& grid_mask() { return grid_mask_; }
  Buffer<std::uint32_t>& grid_bucket_offset() { return grid_bucket_offset_; }
  Buffer<Real>& grid_inv_cell() { return grid_inv_cell_; }
  Buffer<std::uint32_t>& bucket() { return bucket_; }
  Buffer<std::int32_t>& grid_nodes() { return grid_nodes_; }
  std::size_t uploaded_bytes = 0;  // by the last build
  double gather_seconds = 0.0;     // the whole build on the device (binning, rows), last build
  int attempts = 0;      // gather passes of the last build (2 or 3 when the grids or a row outgrew their capacities)
  bool sampled = false;  // the last build laid its rows out from a sampled estimate
  int launches = 0;      // kernel launches of the last build
  std::uint64_t outgrown_rows = 0;  // rows of the last build that outgrew their capacities (each pass)
  // The largest q_m / q_j over the pairs of the last build with j interior of m's grid level and
  // |x_m - x_j| <= the radius of m, rounded up to 1/kRowRatioScale (0: no such pair); kernels/neighbours.cl.
  double spacing_ratio = 0.0;

 private:
  // One build's nodes and arguments (build's parameters, the work-group size and the groups of n).
  struct BuildArgs {
    std::size_t n, wg, groups;
    Real radius;  // radius_factor
    Buffer<Real>& xy;
    Buffer<Real>& q;
    Buffer<std::uint8_t>& kind;
    Buffer<std::int32_t>& prev;
    Buffer<std::int32_t>& next;
  };
  // The capacities of one pass: the grids' buckets (and their work-groups), the row entries before the
  // tail, the spill list's entries and the move list's rows.
  struct PassCapacities {
    std::size_t buckets = 0, bucket_groups = 0;
    cl_ulong entries = 0;
    std::uint64_t spill = 0, move = 0;
  };
  // build's steps, in order.
  bool keep_counts(std::size_t n);
  void build_empty();
  void size_node_buffers(const BuildArgs& a);
  void run_passes(const BuildArgs& a, bool have_counts, NeighbourFlags& flags, std::vector<std::uint32_t>& c);
  PassCapacities size_pass_buffers(const BuildArgs& a, bool binned);
  void bin(const BuildArgs& a, const PassCapacities& caps);
  bool sample_counts(const BuildArgs& a, int stride, NeighbourFlags& flags, bool& grids_fit);
  void gather_pass(const BuildArgs& a, const PassCapacities& caps, bool counting, bool estimated);
  void gather(cl_int n_arg, Real radius, Buffer<Real>& xy, Buffer<Real>& q, Buffer<std::uint8_t>& kind,
              Buffer<std::int32_t>& prev, Buffer<std::int32_t>& next, cl_ulong entries_size,
              std::uint64_t spill_capacity, bool counting, int stride);
  std::uint64_t set_level_caps(const std::vector<std::uint32_t>& tally, int stride);
  bool take_bin_state(std::size_t n, NeighbourFlags& flags, bool& grids_fit);

  Context& ctx_;
  StepProgram& program_;
  Buffer<std::int32_t> count_, index_, level_, bin_state_, grid_mask_, grid_nodes_, spill_, move_node_, level_cap_;
  Buffer<std::uint32_t> grid_bucket_offset_, bucket_, tally_;
  Buffer<std::uint64_t> offset_, block_total_, move_start_;
  Buffer<std::uint32_t> counters_;
  Buffer<Real> bin_partial_, grid_inv_cell_;
  Buffer<std::uint8_t> skin_class_;
  Real pair_skin_ = 0;                                       // the last build's
  std::uint64_t bucket_capacity_ = 0, member_capacity_ = 0;  // wanted by the next build
  std::size_t counted_n_ = 0;        // nodes whose counts count_ holds (the last build's n; 0: none)
  std::uint64_t counted_total_ = 0;  // their sum
  // Target of the build's non-blocking read of bin_state: a member, so that a read still in flight
  // when the build throws (the next download fails) never writes into freed memory.
  std::vector<std::int32_t> state_host_;
};

}  // namespace pdmesh::ocl
