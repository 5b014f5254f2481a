// Debug trace of one simulation iteration; see step_trace.hpp.
#include "sim/step_trace.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <vector>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"

namespace pdmesh {

TraceRange TraceRange::from_environment() {
  TraceRange range;
  const char* text = std::getenv("PDMESH_SIM_TRACE");
  if (!text) return range;
  int consumed = 0;
  if (std::sscanf(text, "%d-%d%n", &range.first, &range.last, &consumed) != 2 || text[consumed] != '\0' ||
      range.first < 0 || range.last < range.first)
    throw InputError(fmt::format(
        "the environment variable PDMESH_SIM_TRACE must be FIRST-LAST (iterations, 0 <= FIRST <= LAST), got '{}'",
        quote_input(text)));
  return range;
}

namespace {
const char* kind_name(std::uint8_t k) { return k == kSimFixed ? "F" : k == kSimBoundary ? "B" : "I"; }

bool list_has(const NeighbourList& list, std::size_t i, std::size_t j) {
  const auto base = i * static_cast<std::size_t>(list.stride);
  for (int k = 0; k < std::min(list.count[i], list.stride); ++k)
    if (static_cast<std::size_t>(list.index[base + static_cast<std::size_t>(k)]) == j) return true;
  return false;
}
}  // namespace

void trace_step(std::FILE* out, int iteration, const SimParticles& p, const NeighbourList& list,
                const ForceResult& forces, const MoveResult& moves, double dt_gm2, double cutoff, int top) {
  const std::size_t n = p.size();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  auto mag = [&](std::size_t i) { return std::hypot(forces.fx[i], forces.fy[i]); };
  const auto count = std::min<std::size_t>(static_cast<std::size_t>(top), n);
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(count), order.end(),
                    [&](std::size_t a, std::size_t b) { return mag(a) > mag(b); });
  for (std::size_t t = 0; t < count; ++t) {
    const std::size_t i = order[t];
    const double f = mag(i), step = std::hypot(moves.dx[i], moves.dy[i]);
    // Nearest neighbour in any direction, for comparison with r0.
    double nearest = HUGE_VAL;
    const auto base = i * static_cast<std::size_t>(list.stride);
    const int cnt = std::min(list.count[i], list.stride);
    for (int k = 0; k < cnt; ++k) {
      const auto j = static_cast<std::size_t>(list.index[base + static_cast<std::size_t>(k)]);
      nearest = std::min(nearest, std::hypot(p.x[j] - p.x[i], p.y[j] - p.y[i]));
    }
    const bool stiff = !forces.dt2_limit.empty() && moves.dt2[i] == forces.dt2_limit[i] && moves.dt2[i] < dt_gm2;
    const char* limit = stiff ? " (stiffness)" : moves.dt2[i] < dt_gm2 ? " (r0-capped)" : " (dtGM)";
    fmt::print(out,
               "it {} #{} node {} {} ({:.5f},{:.5f}) q {:.4f} |F| {:.4g} r0 {:.4f} nearest {:.4f} dt2 {:.4g}{} "
               "step {:.4g} step/q {:.4f} step/nearest {:.3f}\n",
               iteration, t, i, kind_name(p.kind[i]), p.x[i], p.y[i], p.q[i], f, forces.r0[i], nearest, moves.dt2[i],
               limit, step, step / p.q[i], nearest < HUGE_VAL ? step / nearest : 0.0);
    for (int k = 0; k < cnt; ++k) {
      const auto j = static_cast<std::size_t>(list.index[base + static_cast<std::size_t>(k)]);
      const double dx = p.x[j] - p.x[i], dy = p.y[j] - p.y[i], r = std::hypot(dx, dy);
      const double sigma = 0.5 * (p.q[i] + p.q[j]);
      const bool ahead = forces.fx[i] * dx + forces.fy[i] * dy > 0.0;
      const bool sees_back = p.kind[j] == kSimInterior ? r <= cutoff * p.q[j] : list_has(list, j, i);
      fmt::print(out, "    nb {} {} r/sigma {:.4f} r/(cut q_i) {:.4f} {} {} |F_j| {:.4g} step_j {:.4g}\n", j,
                 kind_name(p.kind[j]), r / sigma, r / (cutoff * p.q[i]), ahead ? "ahead" : "behind",
                 sees_back ? "mutual" : "ONE-WAY", mag(j), std::hypot(moves.dx[j], moves.dy[j]));
    }
  }
}

}  // namespace pdmesh
