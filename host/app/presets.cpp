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
  // The thesis runs a fixed 2000 iterations (its report histories and Table 6.x); best stops once the
  // nodes have converged (sim/convergence.hpp), with simulation.iterations as the most it may take.
  c.simulation.stop = thesis ? StopRule::Iterations : StopRule::Converged;
}

}  // namespace pdmesh
