// The presets of the case-file defaults (docs/cli.md, "Presets"): `best`, the settings that give the
// best meshes, which a geometry given alone runs with (`fast` is an older name of it); `thesis`,
// Fackler's settings, which the thesis case files name so that report/ still reproduces chapter 6;
// and `long`, the slower schedule best replaced (no momentum, three times the iterations).
#include "app/config/case_file.hpp"

namespace pdmesh {

const char* to_string(Preset preset) {
  switch (preset) {
    case Preset::Thesis:
      return "thesis";
    case Preset::Fast:
      return "fast";
    case Preset::Long:
      return "long";
    case Preset::Best:
      break;
  }
  return "best";
}

namespace {

// The best preset's spacing.relax_scale per fill (preset_relax_scale): measured, see
// apply_momentum_schedule.
constexpr double kBestRelaxScale = 1.09;
constexpr double kBestHexagonalRelaxScale = 1.03;
// The best preset's simulation.stop_angle per kind of run (preset_stop_angle): measured, see
// apply_momentum_schedule.
constexpr double kBestStopAngle = 6.0;
constexpr double kBestMetricStopAngle = 3.0;
// The best preset's simulation.dt_initial.structured, simulation.stop_aspect, simulation.momentum_mix and
// population.stop for an isotropic run (preset_dt_structured, preset_stop_aspect, preset_momentum_mix,
// preset_population_stop): measured, see apply_momentum_schedule. A metric run keeps the automatic step,
// 7e-4 and no mix; its population.stop is the isotropic run's too (kBestMetricPopulationStop).
constexpr double kBestStructuredDt = 0.016;
constexpr double kBestStopAspect = 1.5e-3;
constexpr double kBestMomentumMix = 0.2;
constexpr double kBestMetricStopAspect = 7e-4;
constexpr double kBestPopulationStop = 0.15;
// A metric run's step anneals from its last event on (metric_anneal_from), so a later last event only
// delays the stop: the nodes it adds leave the mean Q and the edges in the window as they are
// (docs/simulation.md, "Annealing a metric run").
constexpr double kBestMetricPopulationStop = kBestPopulationStop;
// The best preset's cleanup.settle: measured, see apply_momentum_schedule.
constexpr double kBestCleanupSettle = 1e-6;
// The best preset's init.density, in units of the hexagonal-packing estimate: the structured patterns hold
// about 1.21 on a graded field; 1.25 also brings rods_fine, whose lattice quads keep the patterns' 1.05,
// within 1 +- 0.03 (docs/initialization.md, "The hybrid fill's density").
constexpr double kBestDensity = 1.25;
// The best preset's init.hybrid_spread: measured, see apply_momentum_schedule.
constexpr double kBestHybridSpread = 0.2;
// The best preset's spacing.background_min_side, in units of the smallest corner q: inside the domain the
// cells still failing the interpolation test below q/2 straddle the jumps of eq. 3.6 (the rays where a
// curve's closest segment changes to one of another length), which no cell size resolves. Between q/4 and
// q/2 a cell is tested only where its corners differ by more than BackgroundOptions::jump_tolerance
// (25 %), so the edge of a refinement region (a jump by a factor) is narrowed to q/4 all the same
// (docs/spacing.md, "The best preset's interior cap").
constexpr double kBestBackgroundMinSide = 0.5;

// Best (and fast) = long plus these: over the 16 runs of the stopping study (tools/studies/stop_study) it
// stops after 500-750 iterations instead of 1300-2000 with a lower mean aspect ratio everywhere, and
// with the cleanup's compound trials its smallest angle is within 0.5 degrees of long's or better on
// all 16 (medians of 3); under other population intervals it loses 0.6-2.6 degrees on three of them,
// all at or above 40.3 degrees (docs/journal/, "Momentum and an early stop" and "The
// cleanup's last defects").
void apply_momentum_schedule(CaseConfig& c) {
  // Heavy-ball momentum: the lattice's defects anneal ~4x faster (docs/simulation.md, "Momentum").
  c.simulation.momentum = 0.9;
  // Its carried move turned towards the force (FIRE's velocity mixing) in an isotropic run: the lattice
  // reaches a lower mean aspect ratio by the same iteration, which the looser drift tolerance below
  // turns into an earlier stop (docs/simulation.md, "Momentum"). A metric run keeps the plain
  // heavy-ball move (preset_momentum_mix).
  c.simulation.momentum_mix = preset_momentum_mix(Preset::Best, c.spacing.metric());
  // Population control only over the first 15 % of the maximum (to iteration 300 of 2000), with a
  // fixed vacancy threshold (a ramp keeps opening candidates), ending early once two events in a row
  // change at most 0.1 % of the nodes. Each event's insertions lower the mean aspect ratio in a step
  // that holds the drift rule (below) for the next window; with the larger step (below) the lattice has
  // filled its vacancies by 300. A metric run too (preset_population_stop).
  c.population.stop = preset_population_stop(Preset::Best, c.spacing.metric());
  c.population.insert = {0.7, 0.7};
  c.population.settle = 1e-3;
  c.population.settle_events = 2;
  // The rule on the faster time scale: measured every 50 iterations over a 100-iteration window, from
  // iteration 150, with a mean aspect ratio that moved less than 1.5e-3 over the window. What holds a
  // structured start to its stop is that drift; a looser tolerance stops sooner but leaves a higher
  // mean aspect ratio after the cleanup, which the larger step (below) and the steered momentum (above)
  // make up for: over the 19 calibration runs' eight draws 1.5e-3 with both leaves a lower mean aspect
  // ratio than 9e-4 without the steering, in about a sixth fewer iterations (docs/simulation.md, "When
  // a run stops"). A metric run keeps 7e-4 (preset_stop_aspect). A start near equilibrium (the hybrid fill at scale)
  // has no drift to wait for: 150 is the first window after the first two population events.
  c.simulation.stop_aspect = preset_stop_aspect(Preset::Best, c.spacing.metric());
  c.simulation.stop_every = 50;
  c.simulation.stop_window = 100;
  c.simulation.stop_min = 150;
  // The drift judged from population control's last change on too: an event's insertions lower the mean
  // aspect ratio in a step that is no drift of the settling lattice and would hold the rule until it has
  // left the window. Quiet events do not count: after one, two measurements that happen to agree would
  // stop an unsettled run (docs/simulation.md, "When a run stops"). A metric run keeps the whole window
  // alone, and so does a run with boundary layers, whose core must settle against the layers' front for
  // the junction's triangles to match the last layer's height (test_layer_junction)
  // (preset_stop_from_event).
  c.simulation.stop_from_event = preset_stop_from_event(Preset::Best, c.spacing.metric(), !c.boundary_layers.empty());
  // The smallest angle before the cleanup is one triangle's and moves by 0.5-2.5 degrees between
  // measurements of a settled lattice, while the 40-degree cleanup lifts the final meshes to 43-44
  // degrees whatever the stop: a rise of up to 6 degrees over the earlier best counts as such a move,
  // not as progress to wait for; on the lattice's 4 levels (below) the seams anneal with rises of
  // 2-5 degrees. A metric run keeps 3 (preset_stop_angle): its "smallest angle" is 60 x the mean Q of
  // its worst 1 % of triangles, not one triangle's, and its cleanup works in the metric on the nodes as
  // they stopped, which must have settled first (docs/simulation.md, "When a run stops").
  c.simulation.stop_angle = preset_stop_angle(Preset::Best, c.spacing.metric());
  // A structured (or hybrid) start's lattice takes larger steps where nothing nearer limits them (dt_GM
  // binds where the forces are small, late in a run): it reaches a given mean aspect ratio sooner, so
  // the drift rule above lets it go sooner without a worse mesh. 1.6 x the automatic rule's 0.0100 (at
  // lj_a 15, default_dt_initial); the steps around it that were measured and why they were not taken are
  // in docs/simulation.md, "Initial dt_GM". A random start, and a metric run, keep the automatic rule
  // (preset_dt_structured).
  c.simulation.dt_structured = preset_dt_structured(Preset::Best, c.spacing.metric());
  // A cleanup that works harder on the worst triangles of the shorter run.
  c.cleanup.min_angle = 40.0;
  c.cleanup.iterations = 32;
  // A smaller first trial budget for its topology passes: long's (max(10000, 0.5 x triangles)) went
  // mostly on 40-55 degree triangles of a settled lattice, 0.12 s of the 30P30N curves' 0.23 s
  // cleanup; the triangles below the target still take a second budget. Over the stopping study's 16
  // runs (and its two other population intervals) the smallest angle moves by at most 0.3 degrees
  // (docs/journal/). At scale the bound is what the first pass spends, on triangles already above the
  // target (docs/cleanup.md, "The pass"); small runs keep the 2000 floor.
  c.cleanup.trials_per_triangle = 0.05;
  c.cleanup.min_trials = 2000;
  // Its repairs end once an iteration lifts nothing below the target and lowers the mean aspect ratio
  // by < kBestCleanupSettle: the sweeps' long tail of tiny moves on a settled lattice. A larger value
  // can stop a run before a late rise of its smallest angle (docs/cleanup.md, "Settling").
  c.cleanup.settle = kBestCleanupSettle;
  // The hybrid fill: a lattice as dense as the structured patterns where q is flat well inside the
  // domain, which starts there near equilibrium (annulus_1m: 200 iterations instead of 500), and the
  // patterns next to the boundary and where q is graded, so small and strongly graded runs start as
  // before (docs/initialization.md, "The hybrid fill").
  c.init.method = InitMethod::Hybrid;
  // Where q is flat the patterns' count depends on the one band the quads' area ratio falls in (0.72-1.61
  // x the estimate on the uniform fields of tools/studies/edge_calib.py); there the quads start at the
  // graded fields' average instead, so that one relax_scale centres the mean edge/q on both. Graded quads
  // keep the patterns, which hold about that average already.
  c.init.density = kBestDensity;
  c.init.density_where = DensityWhere::Flat;
  // The lattice quads where q is graded take the lattice of the level nearest q / sqrt(d) on 4 levels per
  // octave, so that they start at d x the estimate as the flat pattern quads do (annulus_1m: edge/q std
  // 0.033 against 0.079 with the patterns' band-dependent density); those on a plateau of q keep the
  // patterns' density (docs/initialization.md, "The lattice's levels").
  c.init.lattice_levels = 4;
  // A quad clear of the boundary takes the lattice where q spans at most a factor 1.2 around it: 1.05 over
  // three quads is relative to the quads' size and held for no quad of annulus_100k and 38 % of
  // annulus_250k's, which then started far from equilibrium and ran 450 and 500 iterations (250 and 250 with
  // 1.2; docs/initialization.md, "The lattice test's spread").
  c.init.hybrid_spread = kBestHybridSpread;
  // Relaxed at kBestRelaxScale x q, the lattice's edges come out at q (mean edge/q 0.91 at 1; docs/spacing.md,
  // "The node count").
  c.spacing.relax_scale = preset_relax_scale(Preset::Best, c.init.method);
  // Interior cells of the background stop refining for small errors at q/2: below that only eq. 3.6's
  // jumps still fail the test.
  c.spacing.background_min_side = kBestBackgroundMinSide;
}

// The long preset's values of the keys apply_momentum_schedule sets: CaseConfig's initializers. So
// applying one preset after another leaves no key of the first behind.
void apply_long_schedule(CaseConfig& c) {
  const CaseConfig long_values;
  c.simulation.momentum = long_values.simulation.momentum;
  c.simulation.momentum_mix = long_values.simulation.momentum_mix;
  c.population.stop = long_values.population.stop;
  c.population.insert = long_values.population.insert;
  c.population.settle = long_values.population.settle;
  c.population.settle_events = long_values.population.settle_events;
  c.simulation.stop_aspect = long_values.simulation.stop_aspect;
  c.simulation.stop_every = long_values.simulation.stop_every;
  c.simulation.stop_window = long_values.simulation.stop_window;
  c.simulation.stop_min = long_values.simulation.stop_min;
  c.simulation.stop_from_event = long_values.simulation.stop_from_event;
  c.simulation.stop_angle = long_values.simulation.stop_angle;
  c.simulation.dt_structured = long_values.simulation.dt_structured;
  c.cleanup.min_angle = long_values.cleanup.min_angle;
  c.cleanup.iterations = long_values.cleanup.iterations;
  c.cleanup.trials_per_triangle = long_values.cleanup.trials_per_triangle;
  c.cleanup.min_trials = long_values.cleanup.min_trials;
  c.cleanup.settle = long_values.cleanup.settle;
  c.spacing.relax_scale = long_values.spacing.relax_scale;
  c.init.method = long_values.init.method;
  c.init.density = long_values.init.density;
  c.init.density_where = long_values.init.density_where;
  c.init.lattice_levels = long_values.init.lattice_levels;
  c.init.hybrid_spread = long_values.init.hybrid_spread;
  c.spacing.background_min_side = long_values.spacing.background_min_side;
}

}  // namespace

double preset_relax_scale(Preset preset, InitMethod method) {
  if (preset != Preset::Best && preset != Preset::Fast) return 1.0;
  // The structured patterns start above the hexagonal-packing estimate, by a share that differs
  // between geometries, so one factor cannot centre them all; the hexagonal fill starts near the
  // estimate everywhere and needs a smaller one (docs/spacing.md, "The node count").
  return method == InitMethod::Hexagonal ? kBestHexagonalRelaxScale : kBestRelaxScale;
}

double preset_stop_angle(Preset preset, bool metric) {
  // Thesis and long keep the rule's own tolerance in both kinds of run.
  if (preset != Preset::Best && preset != Preset::Fast) return CaseConfig{}.simulation.stop_angle;
  return metric ? kBestMetricStopAngle : kBestStopAngle;
}

double preset_stop_aspect(Preset preset, bool metric) {
  if (preset != Preset::Best && preset != Preset::Fast) return CaseConfig{}.simulation.stop_aspect;
  return metric ? kBestMetricStopAspect : kBestStopAspect;
}

double preset_momentum_mix(Preset preset, bool metric) {
  if (preset != Preset::Best && preset != Preset::Fast) return CaseConfig{}.simulation.momentum_mix;
  return metric ? 0.0 : kBestMomentumMix;
}

bool preset_stop_from_event(Preset preset, bool metric, bool layers) {
  if (preset != Preset::Best && preset != Preset::Fast) return CaseConfig{}.simulation.stop_from_event;
  return !metric && !layers;
}

double preset_population_stop(Preset preset, bool metric) {
  if (preset != Preset::Best && preset != Preset::Fast) return CaseConfig{}.population.stop;
  return metric ? kBestMetricPopulationStop : kBestPopulationStop;
}

std::optional<double> preset_dt_structured(Preset preset, bool metric) {
  if (preset != Preset::Best && preset != Preset::Fast) return CaseConfig{}.simulation.dt_structured;
  if (metric) return std::nullopt;
  return kBestStructuredDt;
}

void apply_preset(CaseConfig& c, Preset preset) {
  c.preset = preset;
  const bool thesis = preset == Preset::Thesis;
  // One line per key whose default differs between thesis and the others; CaseConfig's member
  // initializers hold the long preset's values. Each line says what the thesis does instead.
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
  // The thesis meshes its input exactly; the others heal it at the mesh's resolution first
  // (docs/geometry-input.md, "Healing").
  c.geometry.heal = !thesis;
  // The thesis keeps the initial node count for the whole run (population control is its ch. 7
  // future work).
  c.population.enabled = !thesis;
  // The thesis meshes the final node distribution as it is (no cleanup pass).
  c.cleanup.enabled = !thesis;
  // The thesis runs a fixed 2000 iterations (its report histories and Table 6.x); best stops once the
  // nodes have converged (sim/convergence.hpp), with simulation.iterations as the most it may take.
  c.simulation.stop = thesis ? StopRule::Iterations : StopRule::Converged;
  // Best's schedule (momentum, a compressed population schedule and rule, a 40-degree cleanup); the
  // thesis keeps long's values of those keys (no momentum; its rule, population control and cleanup
  // are off, but a file may switch them on).
  if (preset == Preset::Best || preset == Preset::Fast)
    apply_momentum_schedule(c);
  else
    apply_long_schedule(c);
}

}  // namespace pdmesh
