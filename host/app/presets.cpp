// The two presets of the case-file defaults (docs/cli.md, "Presets"): `best`, the settings that give
// the best meshes, which a geometry given alone runs with; and `thesis`, Fackler's settings, which
// the thesis case files name so that report/ still reproduces chapter 6.
#include "app/case_file.hpp"

namespace pdmesh {

const char* to_string(Preset preset) { return preset == Preset::Thesis ? "thesis" : "best"; }

void apply_preset(CaseConfig& c, Preset preset) {
  c.preset = preset;
  const bool thesis = preset == Preset::Thesis;
  // One line per key whose default differs between the presets; CaseConfig's member initializers
  // hold the best values. Each line says what the thesis does instead.
  // Double on every device: the thesis runs reproduce the host reference where a device can (best: auto,
  // float on GPUs whose fp64 is slow).
  c.simulation.precision = thesis ? Precision::Double : Precision::Auto;
  // Eq. 3.6 alone: no gradation limit, no feature size, no curvature rule.
  if (thesis) c.spacing.gradation = 0.0;
  if (thesis) c.spacing.rows_in_gap = 0.0;
  if (thesis) c.spacing.curvature_angle = 0.0;
  // Every geometry point is a boundary node (thesis ch. 4, "Boundary Nodes"), instead of nodes placed
  // by the spacing field. (geometry.curves is "polyline" in both: smooth curves did not measurably
  // help; docs/initialization.md, "Measured".)
  c.boundary.nodes = thesis ? BoundaryNodeRule::Input : BoundaryNodeRule::Spacing;
  // The thesis keeps the initial node count for the whole run (population control is its ch. 7
  // future work).
  c.population.enabled = !thesis;
  // The thesis meshes the final node distribution as it is (no cleanup pass).
  c.cleanup.enabled = !thesis;
  // The thesis runs a fixed 2000 iterations (its report histories and Table 6.x); best stops once the
  // nodes have converged (sim/convergence.hpp), with simulation.iterations as the most it may take.
  c.simulation.stop = thesis ? StopRule::Iterations : StopRule::Converged;
}

}  // namespace pdmesh
