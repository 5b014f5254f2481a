// The reference StepBackend: forwards each step to its plain C++ function (the neighbour build
// through a Verlet candidate cache, neighbour_cache.hpp); and the stride-growing
// neighbour build shared by all backends.
#include <fmt/format.h>

#include "core/errors.hpp"
#include "sim/reference/neighbour_cache.hpp"
#include "sim/reference/reference_backend.hpp"

namespace pdmesh {
namespace {

class ReferenceBackend final : public StepBackend {
 public:
  std::string name() const override { return "host"; }
  void build_neighbours(const SimParticles& p, double cutoff, NeighbourList& list, NeighbourFlags& flags) override {
    cache_.build(p, cutoff, list, flags);
  }
  void compute_forces(const SimParticles& p, const NeighbourList& list, const ForceParams& params,
                      ForceResult& out) override {
    reference::compute_forces(p, list, params, out);
  }
  void time_step_and_move(const SimParticles& p, const ForceResult& forces, double dt_gm2, MoveResult& out) override {
    reference::time_step_and_move(p, forces, dt_gm2, out);
  }
  void apply_momentum(const SimParticles& p, const ForceResult& forces, double beta, double mix, MoveResult& moves,
                      MomentumState& carried) override {
    reference::apply_momentum(p, forces, beta, mix, moves, carried);
  }
  StepSums reduce(const SimParticles& p, const ForceResult& forces, const MoveResult& moves) override {
    return reference::reduce(p, forces, moves);
  }

 private:
  reference::NeighbourCache cache_;  // skin 0.1, growth 0.05: measured best on circle_circle/naca0012
};

}  // namespace

std::unique_ptr<StepBackend> make_reference_backend() { return std::make_unique<ReferenceBackend>(); }

void build_neighbours_growing(StepBackend& backend, const SimParticles& p, double cutoff, NeighbourList& list,
                              NeighbourFlags& flags) {
  for (int attempt = 0; attempt < 3; ++attempt) {
    backend.build_neighbours(p, cutoff, list, flags);
    if (flags.first_invalid >= 0) {
      const auto i = static_cast<std::size_t>(flags.first_invalid);
      throw SimulationError(
          fmt::format("node {} is invalid before binning: x = ({}, {}), q = {}", i, p.x[i], p.y[i], p.q[i]));
    }
    if (!flags.overflow) return;
    // Round up to a multiple of 8 so the padded rows stay aligned for the device.
    list.stride = (flags.max_count + 7) / 8 * 8;
  }
  throw SimulationError(
      fmt::format("neighbour list still overflows at stride {} (max count {})", list.stride, flags.max_count));
}

}  // namespace pdmesh
