// The case file (case.toml; its keys: docs/cli.md, "Case files"): parsed, overridden from the
// command line and validated into a CaseConfig before anything runs or is written.
#pragma once
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "cleanup/cleanup.hpp"
#include "core/memory_budget.hpp"
#include "core/vec2.hpp"
#include "geometry/farfield.hpp"
#include "geometry/geometry.hpp"
#include "geometry/projection.hpp"
#include "init/initial_distribution.hpp"
#include "sim/population.hpp"
#include "spacing/background_field.hpp"
#include "spacing/refine_regions.hpp"

namespace pdmesh {

class SpacingField;

// Metric and Hessian: an anisotropic metric field (docs/metric-fields.md); the pipeline's isotropic q is
// derived from it (MetricSizeField, sqrt(h1 h2)).
enum class SpacingKind { Boundary, Expression, Mesh, Metric, Hessian };
// simulation.precision. Auto: float where the device lacks fp64 or runs it far slower (opencl/precision_probe).
enum class Precision { Double, Float, Auto };
// geometry.curves: the curve the points describe (docs/geometry-input.md, "Smooth curves").
enum class CurveKind { Polyline, Smooth };
// When the simulation ends: once the nodes have converged (sim/convergence.hpp) or after exactly
// simulation.iterations iterations (the thesis).
enum class StopRule { Converged, Iterations };

// Which defaults the keys a case file leaves out take (top-level key `preset`).
//   Best:   the settings that give the best meshes; what a geometry given alone runs with: heavy-ball
//           momentum, a compressed population schedule and stopping rule, and a 40-degree cleanup
//           (docs/cli.md, "Presets").
//   Thesis: Fackler's settings, so that the thesis case files reproduce chapter 6 (report/).
//   Long:   the slower schedule best replaced: no momentum, population control to 80 % of the run, the
//           rule every 100 iterations over a 400-iteration window, a 30-degree cleanup. Three times the
//           iterations for the same or a slightly better worst triangle on some geometries.
//   Fast:   an older name of best's schedule, kept so that files naming it still run; the same settings
//           as Best.
// The member initializers of CaseConfig below are the Long values (those of the library's option
// structs); apply_preset() (app/config/presets.cpp) changes the keys whose value differs in the other
// presets. Keys the file sets always win over the preset.
enum class Preset { Best, Thesis, Fast, Long };

// A zoom window: an extra picture NAME_VIEW.png of the region [x0, x1] x [y0, y1].
struct ViewWindow {
  std::string name;
  Box window;
};

// One "--set section.key=VALUE" (or a direct option translated into one). `label` is how
// messages name it, e.g. "--set simulation.iterations=abc" or "--iterations abc".
struct KeptNodes;

struct CaseOverride {
  std::string key;    // dotted key, e.g. "simulation.iterations"
  std::string value;  // TOML value syntax; a bare word that is not valid TOML is taken as a string
  std::string label;
  bool append = false;  // append the value to the array at `key` instead of replacing it (--view)
  // A command's default that yields to the case file: not applied where the file (or an earlier
  // override) already sets `key` or a key above it (pdmesh smooth's schedule).
  bool if_unset = false;
};

struct CaseConfig {
  std::filesystem::path source;  // the case file, or the geometry file when meshing one directly
  bool geometry_alone = false;   // meshing geometry files without a case file (case_for_geometry_files)
  std::string name;              // for titles; default: the case directory name (or geometry file stem)
  // Top-level key `preset`: "best" (a case file's default), "thesis", "long" or "fast". A CaseConfig
  // built in code holds the long preset's values until apply_preset() runs (a parsed one always has).
  Preset preset = Preset::Long;

  struct Geometry {
    std::vector<std::filesystem::path> files;  // resolved relative to the case file
    std::vector<std::string> curve_names;      // optional, in file/curve order
    // geometry.region_names: names of the geometry's regional attributes, ascending by attribute
    // (GeometryRegion::name); `where` is the case file's "FILE:LINE" of each, for the geometry's check.
    struct RegionName {
      double attribute = 0.0;
      std::string name, where;
    };
    std::vector<RegionName> region_names;
    double join_tolerance = 1e-9;
    double corner_angle = 30.0;  // degrees
    // geometry.hull (bool; absent: automatic): .poly files mesh the convex hull of their vertices.
    PolyHull hull = PolyHull::Automatic;
    // Curves given in memory (the Python API) instead of files; see case_for_curves().
    std::vector<RawCurve> given_curves;
    // Embedded points given in memory (the Python API): nodes the mesh must have
    // (docs/geometry-input.md, "Embedded constraints").
    std::vector<RawPoint> given_points;
    // Regional attributes given in memory (the Python API), each with its point, name and a label
    // for messages (GeometryRegion::file and line).
    std::vector<GeometryRegion> given_regions;
    CurveKind curves = CurveKind::Polyline;  // the same in both presets (docs/initialization.md, "Measured")
    // Healing at the mesh's resolution (geometry/heal.hpp); the preset sets it (off in the thesis).
    bool heal = true;
    // "equirectangular": lon/lat input meshed in metres, outputs written back in lon/lat
    // (geometry/projection.hpp, docs/geometry-input.md).
    ProjectionKind projection = ProjectionKind::None;
  } geometry;

  struct Spacing {
    SpacingKind field = SpacingKind::Boundary;
    std::string expression;  // muParser expression in x and y when field == Expression
    // field == Mesh: a .vtu or .msh triangle mesh (resolved relative to the case file, or to the current
    // directory when given by --set) and the name of its point-data array that holds q.
    std::filesystem::path file;
    std::string array = "q";
    // field == Metric: muParser expressions in x and y, either sizes (h1 along the direction `angle`,
    // in degrees from the x axis, h2 across it) or the components m11, m12, m22; or `file` (.vtu/.msh
    // with a 3-component point array `array`, default "metric"; or a Medit .mesh with the .sol `sol`,
    // default the same stem). Empty strings are keys not given.
    std::string h1, h2, angle, m11, m12, m22;
    std::filesystem::path sol;
    // field == Hessian: the L2-optimal metric of a function, given as an expression `function` in x and
    // y or as scalar data `array` (default "u") at the points of `file`, of complexity C = `complexity`,
    // clipped to sizes in [hmin, hmax] and to max_anisotropy (spacing/hessian_metric.hpp).
    // `spacing.array = ["a", "b"]` (Hessian with `file` only): every name, `array` the first; their
    // metrics intersected (intersected_hessian_metrics_on_mesh). Empty when spacing.array is one string.
    std::vector<std::string> arrays;
    std::string function;
    double complexity = 0.0;  // required for Hessian
    double hmin = 0.0;
    double hmax = std::numeric_limits<double>::infinity();
    double max_anisotropy = std::numeric_limits<double>::infinity();
    // field == Hessian: p of the L^p norm of the interpolation error the metric minimises (>= 1; 2 the
    // L2 norm; larger p puts more nodes where the error is largest, on steep features).
    double norm = 2.0;
    // The metric gradation beta (> 1, the size ratio per unit metric length; 0 = off), in metric space,
    // along a background mesh's edges: the file's, or a grid's for expressions and functions
    // (spacing/metric_gradation.hpp, app/config/case_spacing.cpp).
    double metric_gradation = 0.0;
    // field == Hessian with `function`: the central differences' step as a share of the geometry's
    // extent. The default resolves the function's own curvature; 2/1024 sees it as a fit to data on
    // a 1024 x 1024 grid would (docs/metric-fields.md, "Hessians and the L^p-optimal metric").
    double hessian_step = 1e-5;
    // spacing.size (--size): the base field is this size everywhere instead of eq. 3.6 (0 = not given;
    // only with field = boundary). The pipeline below still applies (docs/spacing.md).
    double size = 0.0;
    // [[refine]]: regions whose size the base field keeps to inside them (spacing/refine_regions.hpp).
    std::vector<RefineRegion> regions;
    bool metric() const { return field == SpacingKind::Metric || field == SpacingKind::Hessian; }
    // A field given by the caller (the Python API: a size callable), not a case key. When set it
    // replaces `field`; MeshInputs samples it once into a background field, so that nothing later
    // evaluates it per point.
    std::shared_ptr<const SpacingField> given;
    // The pipeline on top of the base field (docs/spacing.md): base x scale, min with the feature size
    // (rows_in_gap node spacings across every gap) and the curvature rule (q <= R theta), then the
    // gradation limit |grad q| <= gradation. 0 turns each off; the thesis preset turns all off.
    double scale = 1.0;
    // The nodes are placed and relaxed by relax_scale x the field (the pair force's sigma, boundary
    // placement, the fill, population control and the cleanup all see it), while the quality's
    // spacing conformance, the mesh's q and spacing.png report the field as asked: the relaxed lattice
    // packs its edges at about 0.91 sigma, so the best preset's value brings them to about q
    // (docs/spacing.md, "The node count"). 1 in the thesis and long presets.
    double relax_scale = 1.0;
    double gradation = 0.2;
    double rows_in_gap = 2.0;
    double curvature_angle = 10.0;  // degrees
    // The background quadtree's resolution, BackgroundOptions' defaults in every preset: refine while
    // the bilinear value is off by more than background_tolerance (relative), but not for accuracy
    // below background_min_side x q inside and background_boundary_min_side x q in leaves a boundary
    // segment touches.
    double background_tolerance = BackgroundOptions{}.tolerance;
    double background_min_side = BackgroundOptions{}.min_side_fraction;
    double background_boundary_min_side = BackgroundOptions{}.boundary_min_side_fraction;
  } spacing;

  // [farfield] (--farfield SHAPE:SIZE): a closed curve named "farfield" around the geometry
  // (geometry/farfield.hpp); size 0 = none.
  Farfield farfield;

  struct Boundary {
    BoundaryNodeRule nodes = BoundaryNodeRule::Spacing;  // thesis: Input (every geometry point is a node)
  } boundary;

  struct Init {
    InitMethod method = InitMethod::Structured;
    std::uint64_t seed = 1;
    std::uint64_t total = 0;  // 0 = no overloading
    // The hybrid fill's start density (InitOptions::density): 0 = the structured patterns' counts.
    double density = 0.0;
    // Which quads it applies to (InitOptions::density_where).
    DensityWhere density_where = DensityWhere::Inside;
    // The levels per octave of its lattice on q's levels (InitOptions::lattice_levels): 0 = the fill's own.
    int lattice_levels = 0;
    // The hybrid fill's lattice test: q flat within a factor 1 + this around a quad (InitOptions::hybrid_spread).
    double hybrid_spread = kHybridSpread;
    // The warm start: a node or mesh file whose interior points are the initial interior nodes
    // (init/warm_points.hpp, init/metric_fill.hpp warm_fill); empty: the usual fill.
    std::filesystem::path file;
    // The initial nodes as they are (pdmesh smooth of a mesh already at the target; init/kept_nodes.hpp),
    // set in memory, never by a key; null: the usual start. Beats `file`.
    std::shared_ptr<const KeptNodes> kept;
  } init;

  struct Simulation {
    std::int64_t iterations = 2000;  // with stop = Converged the most the run may take
    StopRule stop = StopRule::Converged;
    // The convergence rule's tolerances (sim/convergence.hpp ConvergenceOptions): the most the mean
    // aspect ratio of the triangulated nodes may change over the rule's window, and the most the
    // smallest angle may rise above its earlier best in it (degrees).
    double stop_aspect = 5e-4;
    double stop_angle = 0.25;
    // The rule's measurement interval, window and earliest stop (ConvergenceOptions::check_every,
    // window, min_iterations), in iterations.
    int stop_every = 100;
    int stop_window = 400;
    int stop_min = 400;
    // ConvergenceOptions::from_last_event: the drift window starts no earlier than the first measurement
    // after population control's last event.
    bool stop_from_event = false;
    // SimOptions::metric_anneal: a metric run under the stopping rule multiplies dt_GM by this before
    // every iteration from population control's last event on (metric_anneal_from); 1 = off.
    double metric_anneal = 0.99;
    // Initial global maximum time step per init method; empty = the automatic rule.
    std::optional<double> dt_structured;
    std::optional<double> dt_random;
    double cutoff = 1.5;
    double lj_a = 15.0;
    std::string device = "auto";            // auto | host | opencl | opencl:P:D
    Precision precision = Precision::Auto;  // the host reference always computes in double
    // true: r0 is the nearest neighbour in any direction ("any_direction"); false: in the force
    // direction, thesis eq. 5.3 ("force_direction", the default).
    bool r0_any_direction = false;
    // Stiffness bound on each node's time step (docs/simulation.md, "Stability"): 0 = off, the
    // thesis' rule exactly; c in (0, 1] keeps every step within the forward-Euler stability limit.
    double stability_factor = 1.0;
    double momentum = 0.0;  // SimOptions::momentum (heavy-ball beta in [0, 1); 0 = off)
    // SimOptions::momentum_mix in [0, 1): the carried move turned towards the force; 0 = off (the
    // initializer: thesis and long; best: preset_momentum_mix).
    double momentum_mix = 0.0;
    // SimOptions::verlet_skin of a device run, in [0, 4]; empty = "auto" (auto_verlet_skin: by the
    // momentum and the node count). Never changes a result, only the rebuilds and the rows' memory.
    std::optional<double> verlet_skin;
    // A hexagonal start is a lattice like the structured one: it takes the structured value.
    std::optional<double> dt_for(InitMethod m) const { return m == InitMethod::Random ? dt_random : dt_structured; }
  } simulation;

  // Node insertion and removal during the run (sim/population.hpp, docs/cli.md "[population]"). Best:
  // on; thesis: off (the thesis keeps the initial node count).
  PopulationOptions population{.enabled = true};
  // The final cleanup after the last iteration (docs/cleanup.md): repairs the triangles whose
  // smallest angle is below min_angle by smoothing, flips and local topology operations.
  struct Cleanup {
    bool enabled = true;
    double min_angle = 30.0;       // degrees, in (0, 60)
    std::int64_t iterations = 16;  // outer iterations (smoothing sweeps + a topology pass)
    bool topology = true;          // false: smoothing and flips only (the node count stays)
    bool split_boundary = true;    // false: no new boundary nodes (boundary nodes only slide)
    // The topology passes' work bound: max(min_trials, trials_per_triangle x triangles) trials
    // (CleanupOptions' defaults; best lowers both).
    double trials_per_triangle = CleanupOptions{}.trials_per_triangle;
    std::int64_t min_trials = static_cast<std::int64_t>(CleanupOptions{}.min_trials);
    // CleanupOptions::settled_aspect_drop: the repairs end once an iteration changes the mean aspect
    // ratio by less than this and nothing else (0, every preset's: they run to `iterations`).
    double settle = CleanupOptions{}.settled_aspect_drop;
    // CleanupOptions::sharp_corners and polish (off in every preset; pdmesh smooth turns both on).
    bool sharp_corners = false;
    std::int64_t polish = 0;
    // CleanupOptions::threads: the sweeps' threads (0: the hardware's); the mesh is the same for any.
    std::int64_t threads = 0;
    // CleanupOptions::small_strip_vertices: meshes of at least 4 x this many vertices and below
    // 200,000 sweep in 4 strips (0: serial sweeps below 200,000 vertices).
    std::int64_t small_strip_vertices = 0;
  } cleanup;

  // [[boundary_layer]] (docs/boundary-layers.md): layered cells grown from the named wall curves, the
  // particle core meshed on their fronts. None by default (the outputs are then those of the core alone).
  struct BoundaryLayer {
    std::vector<std::string> curves;  // names from geometry.curve_names (or the files' curve names)
    std::string curves_where;         // where curves was given ("case.toml:12:10", "--set ..."), for errors
    double first_height = 0.0;        // given, or from y_plus (flat-plate estimate, first_height_for_y_plus)
    double y_plus = 0.0, reynolds = 0.0, reference_length = 0.0;  // 0 unless y_plus is given
    double growth = 1.2;
    double thickness = 0.0;  // or layers (exactly one of the two)
    int layers = 0;
    bool quads = false;  // elements = "quads": true quadrilaterals (mixed cells); "triangles": each split in 2
  };
  std::vector<BoundaryLayer> boundary_layers;

  // [[periodic]] (docs/geometry-input.md, "Periodic curves"): the image curve carries the source
  // curve's boundary nodes under a translation or a rotation (app/pipeline/periodic_pipeline).
  struct Periodic {
    std::string source, image;  // curves = [source, image]: names from geometry.curve_names or the files'
    std::string where;          // where the table was given ("case.toml:12:1"), for errors
    enum class Kind { Infer, Translate, Rotate } kind = Kind::Infer;
    std::array<double, 2> translate{0.0, 0.0};
    std::array<double, 2> center{0.0, 0.0};
    double angle_deg = 0.0;  // counter-clockwise, source to image
    // Kind::Translate by the translation inferred from the input's curves (the layered core's case,
    // whose trimmed curves keep the transform the layers were tied by).
    bool inferred = false;
  };
  std::vector<Periodic> periodic;

  // [motion] (docs/motion.md): the named curves move rigidly, the mesh follows them in `steps` steps.
  // Absent (enabled false) by default: a normal run.
  struct Motion {
    bool enabled = false;
    std::vector<std::string> curves;  // names from geometry.curve_names (or the files')
    std::string rotate = "0";         // degrees about pivot, counter-clockwise, muParser in t
    std::array<double, 2> pivot{0.0, 0.0};
    std::array<std::string, 2> translate{"0", "0"};  // x(t), y(t)
    std::int64_t steps = 0;                          // t = k / steps, k = 0 .. steps
    std::int64_t iterations = 30;                    // the warm relaxation of each later step, at most
    double blend = 4.0;                              // carried-node blending radius, in body sizes
  } motion;

  struct Output {
    std::vector<std::string> formats{"msh", "vtu", "png"};
    bool tree_overlay = false;
    std::vector<ViewWindow> views;
    // mesh.png fill: none, a per-triangle quality metric, or "region" (the regions with a legend)
    std::string color_by = "none";
    bool spacing_picture = false;  // DIR/spacing.png: the final spacing field (--plot-spacing)
    // Curves written as open boundaries in fort14 (the rest are land); checked against the curve names.
    std::vector<std::string> open_boundaries;
    // Curves whose OpenFOAM patches are of type wall; checked against the curve names. A layered run's
    // wall curves ([[boundary_layer]] curves) are walls too (wall_curves()).
    std::vector<std::string> walls;
    bool wants(const std::string& format) const;
    // Every name output.formats accepts: the mesh formats (io/mesh_formats.hpp), then png and svg.
    static const std::vector<std::string>& format_names();
  } output;

  // Command-line only (not case-file keys).
  std::filesystem::path out_dir;
  bool quiet = false;
  bool check = false;  // run the mesh invariant checker and fail when it finds a problem
  std::uint64_t max_nodes = 20'000'000;
  // --max-memory: what the run may allocate, checked by every stage before it allocates in proportion
  // to the input or the node count (default: a share of the machine's memory, core/memory_budget.hpp).
  MemoryLimit max_memory = default_memory_limit();
  std::optional<std::filesystem::path> resume;        // --resume: continue from this checkpoint (file or directory)
  std::optional<std::filesystem::path> timings_file;  // --timings: the phase times as JSON
  // The `pdmesh mesh` command line as given (argv), for the commands a stopped run prints; empty
  // for runs not started by the command.
  std::vector<std::string> command_line;
  std::int64_t stop_after = 0;  // --stop-after (testing aid): act as if interrupted after this iteration; 0 = off
  // false (the Python API): the stages compute only; nothing is written into out_dir.
  bool write_outputs = true;
};

// The first cell height for a target y+ on a flat plate (docs/boundary-layers.md): White's turbulent
// skin friction Cf = 0.026 / Re^(1/7), u_tau = U sqrt(Cf / 2), y = y+ L / (Re sqrt(Cf / 2)).
double first_height_for_y_plus(double y_plus, double reynolds, double reference_length);

// Every valid dotted key, for docs and suggestions.
const std::vector<std::string>& case_file_keys();

// Parses and validates a case file. Throws InputError "FILE:LINE:COL: ..." on TOML syntax errors,
// unknown keys (with the nearest valid key suggested), wrong types and out-of-range values.
CaseConfig load_case_file(const std::filesystem::path& case_file, const std::vector<CaseOverride>& overrides = {});

// The same from TOML text; `source` names it in messages and anchors relative paths.
CaseConfig parse_case_text(std::string_view text, const std::filesystem::path& source,
                           const std::vector<CaseOverride>& overrides = {});

// A case for one geometry file (.crv, .dat, .poly) with every other key at its default.
CaseConfig case_for_geometry_file(const std::filesystem::path& geometry_file,
                                  const std::vector<CaseOverride>& overrides = {});
// The same for several geometry files that together make one geometry (curves taken in file order);
// the case is named after the first file's stem.
CaseConfig case_for_geometry_files(const std::vector<std::filesystem::path>& geometry_files,
                                   const std::vector<CaseOverride>& overrides = {});

// The curves an OpenFOAM mesh's patches of type wall hold: output.walls and every [[boundary_layer]]'s curves.
std::vector<std::string> wall_curves(const CaseConfig& config);

// A case for curves given in memory (the Python API) with every key at its default but those the
// overrides set; `source` names the geometry in messages and the case (its name) unless `name` is set.
// geometry.files may not be set (InputError); geometry.curve_names names the curves as for files.
CaseConfig case_for_curves(std::vector<RawCurve> curves, const std::string& source,
                           const std::vector<CaseOverride>& overrides = {});

// Sets every key whose default differs between presets to `preset`'s value (and config.preset).
void apply_preset(CaseConfig& config, Preset preset);
// "best" or "thesis".
const char* to_string(Preset preset);
// spacing.relax_scale's default under `preset` for a fill by `method` (best: 1.09 for the structured
// and random fills, 1.03 for the hexagonal one; thesis and long: 1). A case that sets the key keeps
// its value.
double preset_relax_scale(Preset preset, InitMethod method);
// simulation.stop_angle's default under `preset` for a metric run (`metric`: spacing.metric()) or an
// isotropic one (best: 6 degrees isotropic, 3 in a metric; thesis and long: 0.25 for both). A case
// that sets the key keeps its value.
double preset_stop_angle(Preset preset, bool metric);
// simulation.stop_aspect, simulation.momentum_mix, population.stop and simulation.dt_initial.structured under
// `preset` for a metric run or an isotropic one (best: 1.5e-3, 0.2, 0.15 and 0.016 isotropic; 7e-4, 0, 0.2
// and the automatic rule in a metric; thesis and long: CaseConfig's initializers for both). A case that
// sets the key keeps its value.
double preset_stop_aspect(Preset preset, bool metric);
double preset_momentum_mix(Preset preset, bool metric);
double preset_population_stop(Preset preset, bool metric);
std::optional<double> preset_dt_structured(Preset preset, bool metric);
// simulation.stop_from_event's default under `preset` for a metric run or an isotropic one, with
// boundary layers (`layers`) or without (best: true for an isotropic run without layers, else false;
// thesis and long: false). A case that sets the key keeps its value.
bool preset_stop_from_event(Preset preset, bool metric, bool layers);

// Splits "section.key=VALUE" into an override; throws InputError when there is no '=' or key.
CaseOverride parse_set_option(const std::string& text);

// Levenshtein distance, used to suggest the nearest valid key.
std::size_t edit_distance(std::string_view a, std::string_view b);

}  // namespace pdmesh
