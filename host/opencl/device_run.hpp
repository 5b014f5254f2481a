// DeviceRun: the state and steps of one device-resident run (internal to host/opencl; the entry
// point is run_device_resident in device_simulation.hpp). The loop is sim/iteration_loop's, shared with
// the host driver: DeviceRun is its IterationSteps, each iteration's computation the next row of a
// window of device iterations. Its members are defined in two files: device_run_state.cpp (uploads,
// read-backs, the saved state, population events) and device_simulation.cpp (rebuilds, windows, the
// iteration's steps).
#pragma once
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <limits>
#include <optional>
#include <thread>
#include <type_traits>
#include <utility>

#include "opencl/command_counts.hpp"
#include "opencl/device_boundary.hpp"
#include "opencl/device_neighbours.hpp"
#include "opencl/device_population.hpp"
#include "opencl/device_simulation.hpp"
#include "opencl/device_window.hpp"
#include "opencl/measure_overlap.hpp"
#include "opencl/step_program.hpp"
#include "sim/boundary_handling.hpp"
#include "sim/global_time_step.hpp"
#include "sim/iteration_loop.hpp"

namespace pdmesh::ocl {

using Clock = std::chrono::steady_clock;
inline double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// How much of its skin a node may use before the lists are rebuilt. Row i (interior) holds every j
// with |x_j,b - x_i,b| <= R_ij, where c is the cut-off, s the skin, q_b the spacings at the build:
// R_ij = c (1 + s) q_b,i, and for j of a coarser grid level (q_b,j > q_b,i: kernels/neighbours.cl,
// pair_skin) R_ij = c q_b,i + s c q_b,j. A needed pair, |x_j - x_i| <= c q_i, is missing only when
// (triangle inequality; d: distances moved since the build) d_i + c (q_i - q_b,i) + d_j > R_ij - c q_b,i.
// Each node's skin use u = (d + c max(0, q - q_b)) / (c s q_b) is kept at most its share L, so the
// left side is at most s c (L_i q_b,i + L_j q_b,j). Every share is at most 1/2: pairs with q_b,j <=
// q_b,i and pairs across levels hold (R_ij - c q_b,i = s c max(q_b,i, q_b,j)). A pair of one level
// with rho = q_b,j / q_b,i in (1, 2) needs L_i + rho L_j <= 1; it can matter only when |x_j,b - x_i,b|
// <= c q_b,i (1 + L_i s) + L_j s c q_b,j <= c (1 + s) q_b,j, within j's radius, where the build
// measures rho_j, the largest such ratio over j's level (gather_rows). L_j <= 1 / (2 rho_j) gives rho
// L_j <= 1/2 and L_i <= 1/2 the rest. So node j's share is 2^(-1 - c_j / kSkinClassSteps) for its skin
// class c_j = ceil(kSkinClassSteps log2 max(1, rho_j)) (one byte per node; 0-17: a share of 0.24 at
// least), the device divides each skin use by it (skin_use_of), and the lists hold while the largest
// quotient stays at most 1 (less a margin far above the rounding). Rows of R_ij = c (1 + s) q_b,i with
// every share 0.25 would assume rho <= 3 across levels, which the spacing does not guarantee (30P30N's
// thesis case has pairs at 4.5: docs/journal/, "Neighbour work per iteration").
// The limit on the quotient: 1 less the margin (a ratio beyond the largest class, which a level's
// factor 2 rules out, would scale it down).
inline double skin_use_limit(double largest_spacing_ratio) {
  const double top = std::exp2(254.0 / kSkinClassSteps);
  return (1.0 - 1e-4) * (largest_spacing_ratio > top ? top / largest_spacing_ratio : 1.0);
}

template <typename Real>
class DeviceRun final : public IterationSteps {
 public:
  DeviceRun(NodeSet& nodes, const GeometryTree& tree, const SpacingField& spacing, const SimOptions& options,
            Context& ctx, StepProgram& program, DeviceRunStats& stats)
      : nodes_(nodes),
        options_(options),
        ctx_(ctx),
        stats_(stats),
        boundary_(tree, nodes),
        background_(background_for(options, spacing, tree, own_background_)),
        program_(program),
        neighbours_(ctx, program_),
        device_boundary_(ctx, tree.geometry()),
        n_(nodes.size()),
        window_(ctx, program.iteration_rule.get() != nullptr && !std::getenv("PDMESH_TEST_HOST_TIME_STEP_RULE")),
        cpu_device_(ctx.device().type == "CPU"),
        loop_(nodes, options) {}
  // Non-blocking uploads read host vectors of this object: wait for them (errors are moot here), and
  // for the thread that runs ahead of a measurement.
  ~DeviceRun() override {
    ahead_stop_ = true;
    join_ahead();
    ctx_.queue().finish();
  }
  DeviceRun(const DeviceRun&) = delete;
  DeviceRun& operator=(const DeviceRun&) = delete;

  SimResult run(const SimCallbacks& callbacks);

 private:
  // IterationSteps (device_simulation.cpp): the loop's iteration is the next row of a window.
  std::string backend_name() const override;
  IterationStep compute(int iteration, const GlobalTimeStep& gm) override;
  IterationMoves apply(int iteration) override;
  void after_row() override;
  void before_measure(int iteration, const GlobalTimeStep& gm) override;
  void after_measure() override;
  void after_observe() override;
  // Not while the device is ahead, but at the measurement it ran ahead of (what it ran is dropped).
  bool may_stop() const override { return ahead_used_ || (window_next_ >= window_rows_ && held_next_ >= held_.size()); }
  void after_iterations() override;
  SimState failure_state() override;
  void end_run(SimResult& result) override;

  // Before the iteration after loop_.done(): the lists rebuilt when the skin is used up; true when they were.
  bool rebuild_if_due(int next_iteration);
  // The row take_row read: throws SimulationError when the device's dt differs from the host's or a
  // move or sum is not finite (then with the last good state in failed_at_).
  void check_row(int iteration, double dt_gm);
  // SimState::momentum after loop_.done().
  std::vector<Vec2> final_momentum();
  std::size_t device_bytes() const;
  void check_memory(std::uint64_t entries) const;
  // The state after loop_.done() (its history rows by count), to fall back on (see saved_state_); its
  // carried moves `momentum` when given, else read from the device's.
  void remember(std::optional<std::vector<Vec2>> momentum = std::nullopt);
  // A convergence check's triangulation runs beside the saved state: while the device runs ahead of
  // it, the saved positions and q (the build state, also on the device: xy_build_, q_build_) are
  // freed, and read back from the device when the next iteration is computed (compute; none when the
  // run stops at the check). Only where they are the device's
  // build state bit for bit (saved_is_build_state_); the positions of the nodes that are not interior
  // are the host's, kept aside. Meanwhile the state after the check stands in for the saved state.
  void release_saved_positions();
  void restore_saved_positions();
  SimState last_good_state();
  SimulationError non_finite_error(int iteration, const SimState& good);
  void upload_initial();
  bool with_momentum() const { return options_.momentum > 0.0; }
  // The carried moves (SimState::momentum) from the device; the device must not be ahead of the host.
  std::vector<Vec2> read_momentum(Buffer<Real>& carried);
  std::vector<Vec2> read_momentum() { return read_momentum(carried_); }
  // Zeroes the carried moves of `nodes` (interior nodes just snapped onto a curve), on the device.
  void reset_momentum(const std::vector<std::int32_t>& nodes);
  // The node arrays for n_ nodes, with the given clearance budgets and background leaves, or (null)
  // computed from the node set: at the start and after a population event.
  void upload_nodes(const std::vector<double>* budgets, const std::vector<std::int32_t>* leaves);
  std::optional<PopulationCounts> population_event(int iteration);
  // The buffers the next step writes before it reads them (xy_ and q_ of 1 - cur_, the candidates):
  // freed during a population event's host work, made again for n_ nodes.
  void release_step_outputs();
  void allocate_step_outputs();
  void read_back_nodes();
  void upload_topology();  // kind, prev, next, boundary slots and arc positions (start and after snapping)
  // The boundary state (positions of the Boundary nodes, tangents, arc positions) into nodes_ and
  // boundary_: the device re-snaps, the host reads it back only when it needs it. sync_boundary: the
  // last boundary_snap's result (its per-slot records and arcs, a few bytes per boundary node);
  // sync_boundary_from: positions and arcs of buffer `which` and the tangents, whole (the last good
  // state after a failed step, when boundary_snap did not run or was halted).
  void sync_boundary();
  void sync_boundary_from(int which);
  // In float, the host's boundary positions are put back exactly onto their curves (at their arc
  // positions, in double), as the host computed them before the device re-snapped: the rounding of
  // the device's float copy stays on the device. Nothing to do in double.
  void boundary_positions_on_curves();
  // read_state: the build state read back for the saved state (remember); not while running ahead of
  // a measurement (run_ahead reads it when the loop reaches the build).
  void rebuild(bool read_state = true);
  // The overlapped measurement (overlap_; on its own thread while the host measures the mesh after
  // iteration first - 1): windows and the builds between them from iteration `first` at `gm`, up to
  // where the host must act (a population event, the next measurement, the last iteration, a window
  // that halted for the host's exact test or a move that is not finite) or until after_measure asks
  // it to stop. The rows of every window but the last are held back (held_), the device's side of
  // their iterations done (the double buffers, the skin, the builds); the last window stays the
  // current one. Touches neither nodes_ nor the loop's state (the measurement reads nodes_).
  void run_ahead(int first, GlobalTimeStep gm);
  // The build run_ahead makes before iteration `next`: the boundary state it is saved with kept aside.
  void build_ahead(int next);
  // Waits for run_ahead's thread (asks it to stop first); its error, if any, stays in ahead_error_.
  void join_ahead();
  // The run goes on past a measurement the device ran ahead of (the first compute after it).
  void go_on_after_ahead();
  // The next held row as the iteration's row (take_row's part for a row without candidates).
  void take_held_row();
  // At the iteration a build run ahead of the measurement preceded (the last of them): its saved state.
  void remember_build_ahead();
  // The boundary state from a boundary_snap's records and arc positions read back (sync_boundary's).
  void restore_boundary(const std::vector<Real>& rec, const std::vector<Real>& arcs);
  void enqueue_iteration(int cur);
  void start_window(int first, const GlobalTimeStep& gm);
  // start_window in two halves: the window's iterations (at most `most`) enqueued, then its rows
  // waited for. The loop measures a convergence check's mesh between the two (run_ahead).
  void begin_window(int first, const GlobalTimeStep& gm, int most);
  void end_window();
  void take_row();
  void take_row_sums(const double* row);
  int window_length() const;
  BoundaryCounts host_boundary(double& skin_use);
  // PDMESH_TEST_CHECK_ROWS: throws SimulationError when a pair within the cut-off at the state the
  // next step reads (xy_[cur_], q_[cur_]) is missing from the current rows.
  void check_rows_hold(int iteration);
  void bg_args(ArgSetter& a) {
    const BackgroundFieldData& d = background_.data();
    a(static_cast<Real>(d.origin_x))(static_cast<Real>(d.origin_y))(static_cast<Real>(d.inv_root_size))(
        static_cast<cl_int>(d.grid))(bg_root_)(bg_child_)(bg_corner_)(bg_cell_)(bg_q_);
  }
  // Transfers with blocking = false are enqueued only: the host data must stay untouched until the
  // next synchronisation (finish or a blocking transfer). Per iteration the host waits on the
  // device twice (after the step and its records, and for the candidates when there are any).
  template <typename T>
  void read(Buffer<T>& b, std::vector<T>& host, std::size_t count, bool blocking = true) {
    b.download(ctx_.queue(), host, count, blocking);
    ++stats_.transfers;
    stats_.bytes_down += count * sizeof(T);
  }
  // Positions of buffer `which` split into x and y: read counts the transfer, download does not. Both
  // block, into a local vector (positions_host_ may be the target of a read still in flight).
  void read_positions(int which, std::vector<Real>& x, std::vector<Real>& y) {
    std::vector<Real> xy;
    read(xy_[which], xy, 2 * n_);
    split(xy, x, y);
  }
  void download_positions(int which, std::vector<Real>& x, std::vector<Real>& y) {
    std::vector<Real> xy;
    xy_[which].download(ctx_.queue(), xy, 2 * n_);
    split(xy, x, y);
  }
  static void split(const std::vector<Real>& xy, std::vector<Real>& x, std::vector<Real>& y) {
    x.resize(xy.size() / 2);
    y.resize(xy.size() / 2);
    for (std::size_t i = 0; i < x.size(); ++i) {
      x[i] = xy[2 * i];
      y[i] = xy[2 * i + 1];
    }
  }
  static std::vector<Real> interleave(const std::vector<double>& x, const std::vector<double>& y) {
    std::vector<Real> xy(2 * x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      xy[2 * i] = static_cast<Real>(x[i]);
      xy[2 * i + 1] = static_cast<Real>(y[i]);
    }
    return xy;
  }
  template <typename T>
  void write(Buffer<T>& b, const std::vector<T>& host, bool blocking = true) {
    b.upload(ctx_.queue(), host, blocking);
    ++stats_.transfers;
    stats_.bytes_up += host.size() * sizeof(T);
  }
  std::size_t groups() const { return (n_ + program_.work_group - 1) / program_.work_group; }
  // A host clearance budget for the device's copy of p: in float the stored position is p rounded,
  // up to eps (|p.x| + |p.y|) away, which comes off the budget.
  static double device_budget(Vec2 p, double budget) {
    if constexpr (std::is_same_v<Real, double>) return budget;
    const double b = budget - std::numeric_limits<Real>::epsilon() * (std::fabs(p.x) + std::fabs(p.y));
    return b > 0.0 ? b : 0.0;
  }

  NodeSet& nodes_;
  const SimOptions& options_;
  Context& ctx_;
  DeviceRunStats& stats_;
  BoundaryHandler boundary_;
  std::unique_ptr<BackgroundSpacing> own_background_;  // when options.background is null
  const BackgroundSpacing& background_;
  StepProgram& program_;
  DeviceNeighbours<Real> neighbours_;
  DeviceBoundary<Real> device_boundary_;
  std::size_t n_;
  int largest_row_ = 0;  // the longest neighbour row any build found (rows are compact: for the stats)
  int cur_ = 0;          // which of the double-buffered x, y, q is current
  // Positions packed, x and y interleaved (2n entries): the force loop's gather of a neighbour fetches
  // both coordinates with one load, from one cache line (docs/journal/, "Step on PoCL").
  Buffer<Real> xy_[2], q_[2], tx_, ty_, xy_build_, q_build_, brec_, cand_rec_, partials_, rec_, bg_q_, budget_;
  Buffer<std::uint8_t> kind_;
  Buffer<std::int32_t> prev_, next_, bslot_, cand_index_, counters_, rec_index_, bg_root_, bg_child_, bg_corner_,
      bg_cell_, node_leaf_;
  Buffer<Real> carried_;  // momentum's carried moves, x and y interleaved (2 entries when momentum is off)
  // Host mirrors.
  std::vector<std::uint8_t> kind_host_;
  std::vector<std::int32_t> boundary_nodes_;  // Boundary nodes in slot order
  std::vector<std::int32_t> candidates_;      // the step's candidates for the host's exact test
  std::vector<Vec2> moves_;                   // their moves, parallel to candidates_
  std::vector<Real> brec_host_, arcs_host_, cand_rec_host_, rec_host_;
  std::vector<std::int32_t> rec_index_host_;
  // Targets of non-blocking downloads are members too: when a wait fails and the error unwinds, a
  // read still in flight must not write into freed memory (~DeviceRun waits for the queue first).
  std::vector<Real> positions_host_[2];  // xy, q: a build's reads, emptied once remember() has them
  std::vector<std::int32_t> cand_index_host_;
  double skin_use_ = HUGE_VAL;                 // since the last build; HUGE_VAL forces a build
  double skin_limit_ = skin_use_limit(0.0);    // the largest skin use over share the current lists allow
  std::vector<std::uint8_t> skin_class_host_;  // the last build's skin classes (host_boundary's test)
  std::uint64_t pairs_examined_ = 0;  // rebuild candidates (the loop adds the current lists' entries every iteration)
  std::uint64_t list_entries_ = 0;    // entries of the current lists (within the skin radius)
  std::size_t within_ = 0, coincident_ = 0, sum_moving_ = 0;
  double sum_force_ = 0, sum_kinetic_ = 0, max_force_ = 0, device_skin_use_ = 0;
  double row_dt_ = 0;              // the global time step the iteration's row used (the device's rule)
  std::uint64_t row_entries_ = 0;  // the list entries of the row's iteration
  bool row_held_ = false;          // the iteration's row was held back (take_held_row)
  // The state to fall back on when the device cannot be read after a failure: saved before the first
  // iteration and after every neighbour-list build (which reads every position anyway). Its history
  // is the first saved_rows_ rows of the run's.
  NodeSet saved_nodes_;
  SimState saved_state_;  // its tangents empty: the nonzero ones are saved_tangents_
  std::vector<std::pair<std::size_t, Vec2>> saved_tangents_;
  // saved_nodes_'s interior positions and every q are xy_build_ and q_build_ read back (in double
  // always; in float from the second build on, when the build read them from the device).
  bool saved_is_build_state_ = false;
  bool saved_released_ = false;  // saved_nodes_.x and .q are freed (release_saved_positions)
  std::vector<std::pair<std::size_t, Vec2>> saved_off_interior_;  // their non-interior positions meanwhile
  // PDMESH_TEST_CHECK_SAVED_RESTORE: a copy of what was released, which the restore must reproduce bit
  // for bit (else a SimulationError; tests/test_device_momentum.cpp).
  const bool check_restore_ = std::getenv("PDMESH_TEST_CHECK_SAVED_RESTORE") != nullptr;
  NodeSet released_copy_;
  // PDMESH_TEST_CHECK_ROWS (double runs): before every iteration's step, the rows must hold every pair
  // the step's forces take (the reference's exact rows at the current positions and q), else a
  // SimulationError naming the first missing pair: the test that the skin's rebuild trigger is safe
  // (tests/test_device_simulation.cpp). Windows are one iteration long then and none runs ahead of a
  // measurement, so that the host sees the state before every step.
  const bool check_rows_ = std::getenv("PDMESH_TEST_CHECK_ROWS") != nullptr;
  std::size_t saved_tangent_count_ = 0;
  std::size_t saved_rows_ = 0;
  // host_boundary has moved nodes on the host that xy_[cur_] does not hold yet (until the iteration ends).
  bool host_ahead_ = false;
  bool tangents_ahead_ = false;  // boundary_snap has run in the iteration not yet complete
  // The device re-snapped the boundary nodes since the host last read their state (sync_boundary).
  bool boundary_stale_ = false;
  int snap_arcs_ = 0;         // the arc buffer the last boundary_snap wrote
  BoundarySnapResult snap_;   // of this iteration's boundary_snap
  bool moves_finite_ = true;  // every move of the iteration take_row read is finite
  DeviceWindow<Real> window_;
  int window_rows_ = 0, window_next_ = 0;  // rows the last window ran, the next one to take
  // A window begun and not yet ended (begin_window): its first iteration and length, its start time.
  // run_ahead_: a convergence check's window begins before the host measures the mesh (off with
  // PDMESH_TEST_NO_RUN_AHEAD, for the test that the runs are the same); its first part is kAheadIterations
  // long, about what the device runs while the host triangulates (6.5 ms for 30P30N's 14k final nodes,
  // bench_triangulation --nodes).
  static constexpr int kAheadIterations = 4;
  const bool run_ahead_ = std::getenv("PDMESH_TEST_NO_RUN_AHEAD") == nullptr && !check_rows_;
  bool window_pending_ = false;
  int pending_first_ = 0, pending_length_ = 0;
  Clock::time_point pending_t0_;
  // The carried moves after a convergence check's iteration, read before the device ran ahead of it:
  // the state's momentum when the run stops there (emptied when it goes on). Not read when the lists
  // were rebuilt just before the check (check_momentum_saved_): the saved state's momentum, read by
  // that build's remember(), is the same, and a second copy would sit beside the check's triangulation.
  std::vector<Real> momentum_at_check_;
  bool check_momentum_saved_ = false;
  int since_build_ = 0, build_interval_ = 0;  // iterations since the last build; between the last two (0: unknown)
  bool cpu_device_ = false;                   // window_length's choice
  double seconds_per_iteration_ = 0.0;        // the last window's wall time per iteration (0: none yet)
  std::size_t fixed_ = 0, on_boundary_ = 0, interior_ = 0;  // node counts by kind after the last iteration
  std::optional<SimState> failed_at_;                       // the last good state, where a failure computed it already
  bool rebuilt_ahead_ = false;  // the lists were rebuilt while the device ran ahead of a measurement
  // The overlapped measurement (run_ahead): while the host triangulates, the device runs on through
  // windows and builds, not one window only (opencl/measure_overlap.hpp: PDMESH_MEASURE_OVERLAP).
  const MeasureOverlap overlap_ = measure_overlap(cpu_device_);
  std::thread ahead_thread_;
  std::atomic<bool> ahead_stop_{false};
  std::exception_ptr ahead_error_;
  bool ahead_used_ = false;  // run_ahead ran for the last measurement: the device holds iterations past loop_.done()
  // A row of a window run ahead, held back: the window's row, the list entries of its iteration, the
  // arc buffer its boundary_snap wrote (-1: none).
  struct HeldRow {
    std::array<double, kRingSize> row{};
    std::uint64_t entries = 0;
    int snap_arcs = -1;
  };
  std::vector<HeldRow> held_;
  std::size_t held_next_ = 0;
  bool ahead_window_ = false;                  // run_ahead left its last window as the current one (its rows unread)
  int ahead_builds_ = 0;                       // builds run_ahead made for the last measurement
  int ahead_build_at_ = 0;                     // the iteration the last of them preceded
  int ahead_snap_arcs_ = 0;                    // the arc buffer the last held row's boundary_snap wrote
  bool ahead_stale_ = false;                   // and whether one did
  std::vector<Real> ahead_brec_, ahead_arcs_;  // the boundary state the last build ahead is saved with
  Buffer<Real> carried_build_;                 // and its carried moves (momentum), on the device
  std::uint64_t pairs_examined_at_check_ = 0;  // pairs_examined_ and largest_row_ at the measurement
  int largest_row_at_check_ = 0;               // (a stop there drops what the builds ahead added)
  // The iterations' bookkeeping: history, time step rule, population schedule, stopping rule (its
  // samples go into every saved state). Last: it checks the options when the run is set up.
  IterationLoop loop_;
};

}  // namespace pdmesh::ocl
