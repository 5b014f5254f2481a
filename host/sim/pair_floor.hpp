// The pair-force floor: the least work one iteration of a Lennard-Jones relaxation of N nodes must do
// on this machine, measured on the node distribution pdmesh settles to, so that the simulation's
// per-iteration time can be given as a ratio to it (`pdmesh bench`, tools/bench/bench_pair_floor).
//
// One floor iteration, on a jittered hexagonal lattice of N nodes with uniform q = 1 (edges
// `spacing_ratio` q, the mean edge/q of a settled run), sorted by the cells of a grid of side cutoff q:
// for every node, every candidate of its 3 x 3 cells (three contiguous runs of the sorted arrays) is
// tested against the cut-off, the pairs within it get the force of eq. 5.11 (sigma the pair's mean q,
// as the simulation's kernel), and the node's new position x + dt^2/2 F is written to a second array.
// The bytes it must move: x, y, q read and the new x, y written (40 B per node) plus the cell starts.
// Not in the floor: the binning (a skin makes it occasional; measured apart), and what pdmesh's
// method adds per node (r0, the stability bound, boundary handling, the spacing lookup, the reductions).
// Threaded over row blocks of cells by parallel_for (every core, as PoCL's CPU device uses them).
// Two loops over the same source (sim/pair_floor_kernel.hpp): scalar (the compiler's vectorizer off)
// and vector (OpenMP SIMD, compiled for the best of x86-64-v4, v3 and baseline the CPU supports).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pdmesh {

struct FloorOptions {
  std::size_t nodes = 1'000'000;
  double spacing_ratio = 0.91;  // lattice edge / q
  double jitter = 0.05;         // each coordinate moved by up to this fraction of an edge (seeded)
  double cutoff = 1.5;          // pairs within cutoff q, as simulation.cutoff
  double lj_a = 15.0;           // a of eq. 5.11, as simulation.lj_a
  std::uint64_t seed = 1;
  int repeats = 5;          // timed iterations per loop; the best is kept
  std::size_t threads = 0;  // 0: every core
};

// The nodes sorted by cell: cell (cx, cy) holds entries [cell_start[cy W + cx], cell_start[cy W + cx + 1]).
struct FloorLattice {
  std::vector<double> x, y, q;
  std::vector<std::uint32_t> cell_start;  // cells_x cells_y + 1 entries
  std::size_t cells_x = 0, cells_y = 0;
  double x0 = 0.0, y0 = 0.0, cell = 1.0;  // the grid's corner and side
  double cutoff = 1.5, lj_a = 15.0;
  std::size_t size() const { return x.size(); }
};

enum class FloorLoop { Scalar, Vector };

// The seeded lattice of `options` (InputError naming a value out of range).
FloorLattice make_floor_lattice(const FloorOptions& options);
// Sorts unsorted points into `lattice`'s cells (a counting sort; the grid covers the points' box).
void bin_floor_points(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& q,
                      FloorLattice& lattice);

struct FloorCounts {
  std::uint64_t candidates = 0;  // distances computed per iteration (pair checks, the node itself included)
  std::uint64_t within = 0;      // of them, pairs within the cut-off (each pair counted at both ends)
};
FloorCounts count_floor_pairs(const FloorLattice& lattice);

// One floor iteration: new positions into (new_x, new_y), resized to the node count; `threads` 0 = all.
void floor_iteration(const FloorLattice& lattice, FloorLoop loop, double dt2, std::vector<double>& new_x,
                     std::vector<double>& new_y, std::size_t threads = 0);
// The same over cell rows [row_begin, row_end) on the calling thread: the kernel of both loops.
void floor_rows_scalar(const FloorLattice& lattice, std::size_t row_begin, std::size_t row_end, double dt2,
                       double* new_x, double* new_y);
void floor_rows_vector(const FloorLattice& lattice, std::size_t row_begin, std::size_t row_end, double dt2,
                       double* new_x, double* new_y);
// The instruction set floor_rows_vector runs with on this CPU ("x86-64-v4 (AVX-512)", ...).
std::string floor_vector_isa();

struct FloorTime {
  double wall = 0.0, cpu = 0.0;  // seconds: the best wall of the repeats, and that repeat's process CPU
};

struct FloorResult {
  std::size_t nodes = 0, threads = 0;
  FloorCounts counts;
  double bytes = 0.0;  // per iteration: 40 B per node and 4 B per cell
  FloorTime scalar, vector;
  FloorTime memory;   // the same bytes streamed alone (read x, y, q; write two arrays)
  FloorTime binning;  // the counting sort of the nodes into the cells, one thread
  std::string isa;
  // The floor: the faster of the two loops (its wall time, and that repeat's CPU time, which on a
  // loaded machine is the figure to compare).
  const FloorTime& best() const { return scalar.wall < vector.wall ? scalar : vector; }
  double seconds() const { return best().wall; }
  double checks_per_core_second(const FloorTime& t) const;
};

// Builds the lattice of `options` and times each loop `options.repeats` times (after one untimed
// iteration), alternating scalar and vector, and the memory pass and the binning as often.
FloorResult measure_pair_floor(const FloorOptions& options);

// One line: "floor at N nodes, T threads: scalar S ms (C pair checks per core-second), vector ...".
std::string format_floor(const FloorResult& result);

}  // namespace pdmesh
