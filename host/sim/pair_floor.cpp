// The pair-force floor's lattice, counts, threaded iteration and timing; see pair_floor.hpp. The
// force loop itself is in pair_floor_kernel.hpp (compiled by pair_floor_scalar.cpp and _vector.cpp).
#include "sim/pair_floor.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <thread>

#include <fmt/format.h>

#include "core/cpu_time.hpp"
#include "core/errors.hpp"
#include "core/parallel.hpp"

namespace pdmesh {
namespace {

void check_options(const FloorOptions& o) {
  if (o.nodes < 2 || o.nodes > (std::size_t{1} << 31))
    throw InputError(fmt::format("pair floor: nodes must be in [2, 2^31], got {}", o.nodes));
  if (!(o.spacing_ratio > 0.0 && o.spacing_ratio <= 10.0))
    throw InputError(fmt::format("pair floor: spacing ratio must be in (0, 10], got {}", o.spacing_ratio));
  if (!(o.jitter >= 0.0 && o.jitter < 0.5))
    throw InputError(fmt::format("pair floor: jitter must be in [0, 0.5), got {}", o.jitter));
  if (!(o.cutoff > 0.0 && o.cutoff <= 10.0))
    throw InputError(fmt::format("pair floor: cutoff must be in (0, 10], got {}", o.cutoff));
  if (!(o.lj_a > 0.0 && std::isfinite(o.lj_a)))
    throw InputError(fmt::format("pair floor: lj_a must be finite and > 0, got {}", o.lj_a));
  if (o.repeats < 1) throw InputError(fmt::format("pair floor: repeats must be >= 1, got {}", o.repeats));
}

// Times f() and keeps it in `best` when its wall time is the smallest so far.
template <class F>
void time_into(FloorTime& best, bool first, const F& f) {
  const double cpu0 = process_cpu_seconds();
  const auto t0 = std::chrono::steady_clock::now();
  f();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cpu = process_cpu_seconds() - cpu0;
  if (first || wall < best.wall) best = {wall, cpu};
}

std::size_t thread_count(std::size_t threads) {
  const std::size_t hardware = std::max(1u, std::thread::hardware_concurrency());
  return threads == 0 ? hardware : std::min(threads, hardware);
}

// The memory pass: the floor iteration's streams alone (x, y, q read; two arrays written).
void stream_pass(const FloorLattice& l, std::vector<double>& a, std::vector<double>& b, std::size_t threads) {
  const std::size_t n = l.size(), block = 1 << 14;
  parallel_for((n + block - 1) / block,
               [&](std::size_t k) {
                 const std::size_t end = std::min(n, (k + 1) * block);
                 for (std::size_t i = k * block; i < end; ++i) {
                   a[i] = l.x[i] + 1e-9 * l.q[i];
                   b[i] = l.y[i] + 1e-9 * l.q[i];
                 }
               },
               1, threads);
}

}  // namespace

void bin_floor_points(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& q,
                      FloorLattice& l) {
  const std::size_t n = x.size();
  double x1 = -HUGE_VAL, y1 = -HUGE_VAL, q_max = 0.0;
  l.x0 = HUGE_VAL;
  l.y0 = HUGE_VAL;
  for (std::size_t i = 0; i < n; ++i) {
    l.x0 = std::min(l.x0, x[i]);
    l.y0 = std::min(l.y0, y[i]);
    x1 = std::max(x1, x[i]);
    y1 = std::max(y1, y[i]);
    q_max = std::max(q_max, q[i]);
  }
  // Cells of side at least every node's cut-off radius: the 3 x 3 cells around a node hold its pairs.
  l.cell = l.cutoff * q_max;
  l.cells_x = static_cast<std::size_t>((x1 - l.x0) / l.cell) + 1;
  l.cells_y = static_cast<std::size_t>((y1 - l.y0) / l.cell) + 1;
  const auto cell_of = [&](std::size_t i) {
    const auto cx = std::min(l.cells_x - 1, static_cast<std::size_t>((x[i] - l.x0) / l.cell));
    const auto cy = std::min(l.cells_y - 1, static_cast<std::size_t>((y[i] - l.y0) / l.cell));
    return cy * l.cells_x + cx;
  };
  l.cell_start.assign(l.cells_x * l.cells_y + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++l.cell_start[cell_of(i) + 1];
  for (std::size_t c = 1; c < l.cell_start.size(); ++c) l.cell_start[c] += l.cell_start[c - 1];
  std::vector<std::uint32_t> fill(l.cell_start.begin(), l.cell_start.end() - 1);
  l.x.resize(n);
  l.y.resize(n);
  l.q.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t slot = fill[cell_of(i)]++;
    l.x[slot] = x[i];
    l.y[slot] = y[i];
    l.q[slot] = q[i];
  }
}

FloorLattice make_floor_lattice(const FloorOptions& o) {
  check_options(o);
  // Rows of a hexagonal lattice (edge a, rows a sqrt(3)/2 apart, every other row shifted by a/2) in
  // a square, filled row by row to exactly `nodes`.
  const double a = o.spacing_ratio, row_height = a * std::sqrt(3.0) / 2.0;
  const auto per_row = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(o.nodes) * row_height / a)));
  std::mt19937_64 rng(o.seed);
  const auto jitter = [&] { return o.jitter * a * (2.0 * static_cast<double>(rng() >> 11) * 0x1p-53 - 1.0); };
  std::vector<double> x(o.nodes), y(o.nodes), q(o.nodes, 1.0);
  for (std::size_t i = 0; i < o.nodes; ++i) {
    const std::size_t row = i / per_row, col = i % per_row;
    x[i] = a * (static_cast<double>(col) + 0.5 * static_cast<double>(row % 2)) + jitter();
    y[i] = row_height * static_cast<double>(row) + jitter();
  }
  FloorLattice l;
  l.cutoff = o.cutoff;
  l.lj_a = o.lj_a;
  bin_floor_points(x, y, q, l);
  return l;
}

FloorCounts count_floor_pairs(const FloorLattice& l) {
  FloorCounts c;
  const std::size_t w = l.cells_x, h = l.cells_y;
  for (std::size_t cy = 0; cy < h; ++cy)
    for (std::size_t cx = 0; cx < w; ++cx)
      for (std::uint32_t i = l.cell_start[cy * w + cx]; i < l.cell_start[cy * w + cx + 1]; ++i) {
        const double rc = l.cutoff * l.q[i];
        for (std::size_t r = cy > 0 ? cy - 1 : 0; r <= std::min(cy + 1, h - 1); ++r) {
          const std::uint32_t b = l.cell_start[r * w + (cx > 0 ? cx - 1 : 0)];
          const std::uint32_t e = l.cell_start[r * w + std::min(cx + 1, w - 1) + 1];
          c.candidates += e - b;
          for (std::uint32_t k = b; k < e; ++k) {
            const double dx = l.x[k] - l.x[i], dy = l.y[k] - l.y[i], r2 = dx * dx + dy * dy;
            c.within += r2 <= rc * rc && r2 > 0.0;
          }
        }
      }
  return c;
}

void floor_iteration(const FloorLattice& l, FloorLoop loop, double dt2, std::vector<double>& new_x,
                     std::vector<double>& new_y, std::size_t threads) {
  new_x.resize(l.size());
  new_y.resize(l.size());
  // Blocks of 4 cell rows (~6 lattice rows each) taken from a shared counter: even finishing times.
  constexpr std::size_t kRows = 4;
  const std::size_t blocks = (l.cells_y + kRows - 1) / kRows;
  parallel_for(
      blocks,
      [&](std::size_t b) {
        const std::size_t end = std::min(l.cells_y, (b + 1) * kRows);
        if (loop == FloorLoop::Scalar)
          floor_rows_scalar(l, b * kRows, end, dt2, new_x.data(), new_y.data());
        else
          floor_rows_vector(l, b * kRows, end, dt2, new_x.data(), new_y.data());
      },
      1, thread_count(threads));
}

double FloorResult::checks_per_core_second(const FloorTime& t) const {
  return static_cast<double>(counts.candidates) / (t.wall * static_cast<double>(threads));
}

FloorResult measure_pair_floor(const FloorOptions& o) {
  const FloorLattice lattice = make_floor_lattice(o);
  FloorResult r;
  r.nodes = lattice.size();
  r.threads = thread_count(o.threads);
  r.counts = count_floor_pairs(lattice);
  r.bytes = 40.0 * static_cast<double>(r.nodes) + 4.0 * static_cast<double>(lattice.cell_start.size());
  r.isa = floor_vector_isa();
  constexpr double kDt2 = 1e-6;  // moves of ~1e-4 edges: the arrays read stay the lattice's
  std::vector<double> new_x, new_y;
  floor_iteration(lattice, FloorLoop::Scalar, kDt2, new_x, new_y, o.threads);  // pages touched, caches warm
  floor_iteration(lattice, FloorLoop::Vector, kDt2, new_x, new_y, o.threads);
  FloorLattice sorted;
  sorted.cutoff = lattice.cutoff;
  for (int k = 0; k < o.repeats; ++k) {
    const bool first = k == 0;
    time_into(r.scalar, first, [&] { floor_iteration(lattice, FloorLoop::Scalar, kDt2, new_x, new_y, o.threads); });
    time_into(r.vector, first, [&] { floor_iteration(lattice, FloorLoop::Vector, kDt2, new_x, new_y, o.threads); });
    time_into(r.memory, first, [&] { stream_pass(lattice, new_x, new_y, r.threads); });
    time_into(r.binning, first, [&] { bin_floor_points(new_x, new_y, lattice.q, sorted); });
  }
  return r;
}

std::string format_floor(const FloorResult& r) {
  const auto per_node = [&](std::uint64_t v) { return static_cast<double>(v) / static_cast<double>(r.nodes); };
  return fmt::format(
      "pair-force floor at {} nodes on {} threads ({:.1f} candidates and {:.2f} pairs within the cut-off per node, "
      "{:.1f} MB per iteration): scalar {:.3f} ms (CPU {:.3f} ms, {:.3g} pair checks per core-second), vector [{}] "
      "{:.3f} ms (CPU {:.3f} ms, {:.3g}); memory pass {:.3f} ms; binning (one thread) {:.3f} ms",
      r.nodes, r.threads, per_node(r.counts.candidates), per_node(r.counts.within), 1e-6 * r.bytes, 1e3 * r.scalar.wall,
      1e3 * r.scalar.cpu, r.checks_per_core_second(r.scalar), r.isa, 1e3 * r.vector.wall, 1e3 * r.vector.cpu,
      r.checks_per_core_second(r.vector), 1e3 * r.memory.wall, 1e3 * r.binning.wall);
}

}  // namespace pdmesh
