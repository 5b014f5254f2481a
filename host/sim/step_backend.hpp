// The per-iteration contract of the particle dynamics simulation (thesis ch. 5): one interface,
// implemented by the plain C++ reference (host/sim/reference) and later by the OpenCL backend.
// All data is structure-of-arrays with explicit flags so a device implementation maps 1:1.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pdmesh {

// Node kinds as stored in SimParticles::kind (same values as NodeKind).
inline constexpr std::uint8_t kSimFixed = 0;
inline constexpr std::uint8_t kSimBoundary = 1;
inline constexpr std::uint8_t kSimInterior = 2;

// The particles as every backend sees them. The host owns and updates these arrays
// (boundary handling and the spacing update run on the host between steps).
struct SimParticles {
  std::vector<double> x, y;              // positions
  std::vector<double> q;                 // desired spacing at (x, y)
  std::vector<std::uint8_t> kind;        // kSimFixed / kSimBoundary / kSimInterior
  std::vector<std::int32_t> prev, next;  // Boundary nodes: previous/next node along the curve; else -1
  std::vector<double> tx, ty;            // Boundary nodes: unit tangent of the curve at the node; else 0
  // Metric mode (off while m11 is empty, the isotropic default): node i's metric
  // M_i = [[m11, m12], [m12, m22]], symmetric positive definite, with unit length = the desired edge
  // (docs/metric-fields.md). Pairs are measured in the geometric mean of the two nodes' metrics
  // (sim/reference/metric_pair.hpp); q is then not read by the step functions.
  std::vector<double> m11, m12, m22;
  bool has_metric() const { return !m11.empty(); }
  std::size_t size() const { return x.size(); }
  void resize(std::size_t n) {
    x.resize(n);
    y.resize(n);
    q.resize(n);
    kind.resize(n);
    prev.resize(n, -1);
    next.resize(n, -1);
    tx.resize(n);
    ty.resize(n);
    if (has_metric()) {
      m11.resize(n);
      m12.resize(n);
      m22.resize(n);
    }
  }
};

// Fixed-stride padded neighbour list (what a device kernel wants): node i's neighbours are
// index[i*stride + k] for k < min(count[i], stride), sorted by node index. count[i] is the TRUE
// count; when it exceeds stride the list is incomplete and NeighbourFlags::overflow is set:
// the caller grows stride to flags.max_count and builds again.
// Interior nodes: every j != i with |x_j - x_i| <= cutoff * q_i (any kind, coincident nodes included);
// in metric mode every j != i with |x_j - x_i|_{M_ij} <= cutoff, M_ij the pair's metric (symmetric in i, j).
// Boundary nodes: exactly {prev, next}. Fixed nodes: none.
struct NeighbourList {
  int stride = 16;
  std::vector<std::int32_t> count;
  std::vector<std::int32_t> index;
};

// Condition flags of a neighbour build (HOOMD-style): set by every backend, checked by the host.
struct NeighbourFlags {
  std::uint32_t overflow = 0;        // 1 when some count[i] > stride
  std::int32_t max_count = 0;        // the largest count[i]
  std::int32_t first_invalid = -1;   // lowest node index with non-finite x or y, or q not (finite and > 0),
                                     // or in metric mode a metric not finite and positive definite; -1 if none
  std::uint64_t pairs_examined = 0;  // candidate pairs whose distance was computed
  std::uint64_t pairs_within = 0;    // of those, pairs within the cutoff (sum of interior counts)
};

// Per-node results of the force step (eq. 5.11 summed, eq. 5.3).
struct ForceResult {
  std::vector<double> fx, fy;          // net force; Boundary nodes: projected onto (tx, ty); Fixed: 0
  std::vector<double> r0;              // distance to the nearest neighbour j with F_i . r_ij > 0 (see
                                       // ForceParams::r0_any_direction); 0 if none or F_i = 0. Metric mode:
                                       // the pair's metric distance, and the half-plane F_i^T M_ij r_ij > 0
  std::uint64_t coincident_pairs = 0;  // neighbour pairs at distance 0 (skipped: no direction)
  // Only when ForceParams::stability_factor > 0 (else empty): the per-node stability bound on dt_i^2,
  // 2 c / K_i with K_i = sum_j max(|df/dr|, |f|/r) over i's list (HUGE_VAL when K_i = 0).
  std::vector<double> dt2_limit;
};

// Per-node results of the time-step/move step (eqs. 5.6, 5.8, 5.9).
struct MoveResult {
  std::vector<double> dx, dy;  // displacement
  std::vector<double> dt2;     // local dt_i^2 used (dt_GM^2 when r0 = 0 or |F| = 0, each capped by
                               // ForceResult::dt2_limit when that is filled); 0 for Fixed. Metric mode:
                               // |F| is measured in the node's metric, so the move is at most r0/3 in it
};

// Reductions over moving (Boundary + Interior) nodes, summed in node order by the reference.
// Metric mode: |F_i| is measured in node i's metric.
struct StepSums {
  std::size_t moving = 0;
  double sum_force = 0.0;    // sum |F_i|
  double max_force = 0.0;    // max |F_i|
  double sum_kinetic = 0.0;  // sum 1/2 |dx_i / dt_i|^2 = sum dt_i^2 |F_i|^2 / 8
};

// Heavy-ball momentum's carried state (SimOptions::momentum): p_i, node i's move d_i of the previous
// iteration; zero at the start of a run, for every node after a population event that changed the node
// set, and for a node whose kind changed (an interior node snapped onto a curve).
struct MomentumState {
  std::vector<double> px, py;
};

struct ForceParams {
  double cutoff = 1.5;  // cut-off distance factor: neighbours within cutoff * q_i
  double lj_a = 15.0;   // a of eq. 5.11
  // false (thesis eq. 5.3): r0 = nearest neighbour with F . r_ij > 0. true: nearest neighbour in any
  // direction (r0 = 0 still when F = 0), which damps the period-2 oscillation of crowded pairs.
  bool r0_any_direction = false;
  // c of the stability bound dt_i^2 <= 2 c / K_i (ForceResult::dt2_limit); 0 = off (thesis eqs. 5.8,
  // 5.9 only). The explicit step dx = dt^2/2 F is stable for modes of node i when dt_i^2 K_i / 2 <= c
  // with c <= 1 (Gershgorin); see docs/simulation.md, "Stability".
  double stability_factor = 0.0;
};

// One operation per simulation step. Implementations must give the same neighbour sets and
// counts exactly and the same floating-point results within rounding.
class StepBackend {
 public:
  virtual ~StepBackend() = default;
  virtual std::string name() const = 0;
  // Step 1: neighbour list (see NeighbourList). Resizes `list` arrays; never grows stride itself.
  virtual void build_neighbours(const SimParticles& p, double cutoff, NeighbourList& list, NeighbourFlags& flags) = 0;
  // Steps 2 and 3: net forces and r0 over the neighbour list.
  virtual void compute_forces(const SimParticles& p, const NeighbourList& list, const ForceParams& params,
                              ForceResult& out) = 0;
  // Step 4: local time step and displacement. dt_gm2 is the squared global maximum time step.
  virtual void time_step_and_move(const SimParticles& p, const ForceResult& forces, double dt_gm2, MoveResult& out) = 0;
  // Step 4, heavy-ball momentum (beta in (0, 1); callers skip it for beta = 0): turns moves' g_i =
  // dt_i^2/2 F_i into d_i = g_i + beta p_i, where mix in [0, 1) > 0 first turns p_i towards F_i
  // (p_i = (1 - mix) p_i + mix |p_i| F_i / |F_i|, where p_i and F_i are not zero); d_i = g_i where
  // d_i . F_i < 0; then |d_i| capped to r0_i / 3 where r0_i > 0 (metric mode: |d_i| in node i's metric).
  // Fixed nodes: d_i = 0. Sets p_i = d_i (carried: n entries each, resized with zeros).
  virtual void apply_momentum(const SimParticles& p, const ForceResult& forces, double beta, double mix,
                              MoveResult& moves, MomentumState& carried) = 0;
  // Reductions for the history and the global time step rule.
  virtual StepSums reduce(const SimParticles& p, const ForceResult& forces, const MoveResult& moves) = 0;
};

// The plain double-precision C++ reference (the oracle for every other backend).
std::unique_ptr<StepBackend> make_reference_backend();

// Builds the list, growing stride to the reported maximum until nothing overflows (at most twice).
void build_neighbours_growing(StepBackend& backend, const SimParticles& p, double cutoff, NeighbourList& list,
                              NeighbourFlags& flags);

}  // namespace pdmesh
