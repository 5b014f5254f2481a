// pdmesh._core.Mesher: one case's run held in memory, stepped in chunks through the command's own
// stages (MeshInputs, SpacingStage and check_node_limit, make_initial, simulate, mesh_and_measure),
// on one simulation backend, set up by the first step and kept for the later ones. The GIL is
// released while C++ works; about every `interval` seconds the run takes it back to check for
// signals (Ctrl-C) and to call the progress callable, and either can stop the run at the end of the
// current iteration, leaving the Mesher able to continue.
#include <atomic>
#include <chrono>
#include <cstring>
#include <exception>
#include <optional>
#include <stdexcept>

#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "app/config/environment.hpp"
#include "app/pipeline/backend_choice.hpp"
#include "app/pipeline/layer_periodic.hpp"
#include "app/pipeline/layer_pipeline.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "bindings.hpp"
#include "callable_spacing.hpp"
#include "core/errors.hpp"
#include "init/initial_distribution.hpp"
#include "opencl/devices.hpp"
#include "sim/simulation.hpp"

namespace pdmesh::py {

namespace {

using Clock = std::chrono::steady_clock;

class Mesher {
 public:
  Mesher(const CaseConfig& config, const std::string& out_dir, std::uint64_t max_nodes)
      : session_(std::make_shared<Session>()) {
    check_environment();  // as the command: a malformed variable is refused before anything is read or written
    CaseConfig& c = session_->config;
    c = config;
    if (max_nodes > 0) c.max_nodes = max_nodes;
    c.quiet = true;  // the Python layer reports progress itself
    c.write_outputs = !out_dir.empty();
    if (!out_dir.empty()) c.out_dir = out_dir;
    nb::gil_scoped_release release;
    std::lock_guard lock(session_->mutex);
    const auto start = Clock::now();
    session_->inputs = std::make_unique<MeshInputs>(c);
    // The size callable has been sampled into the inputs' background field; letting it go here keeps
    // no Python object alive from C++ (a callable that refers to its Mesher would make a cycle that
    // Python's collector cannot see).
    if (const auto* f = dynamic_cast<const CallableSpacing*>(c.spacing.given.get())) {
      size_calls_ = f->calls();
      size_points_ = f->points();
      size_seconds_ = f->seconds();
    }
    c.spacing.given.reset();
    // As the command: an explicit OpenCL device that is not there is refused before anything runs.
    if (c.simulation.iterations > 0 && c.simulation.device != "host" && c.simulation.device != "auto")
      (void)ocl::select_device(c.simulation.device);
    session_->spacing = std::make_unique<SpacingStage>(c, *session_->inputs);
    check_periodic_case(c);  // with the case's own tables ([[boundary_layer]] among them)
    if (!c.boundary_layers.empty()) run_on_core(c);
    if (!c.periodic.empty()) run_on_periodic(c);
    const MeshInputs& inputs = *session_->inputs;
    const SpacingStage& spacing = *session_->spacing;
    estimate_ = check_node_limit(c, inputs, spacing);
    InitialDistribution initial = make_initial(c, inputs, spacing);
    if (c.write_outputs) {
      prepare_output_directory(c);
      write_initial_outputs(c, inputs, initial);
    }
    nodes_ = std::make_shared<NodeSet>(std::move(initial.nodes));
    init_seconds_ = std::chrono::duration<double>(Clock::now() - start).count();
  }

  // Runs iterations up to `target` (a total, counted from the start). Returns "done", or "cancelled"
  // when `progress` returned False; a signal's exception (KeyboardInterrupt) and the callable's own
  // exceptions are raised after the run has stopped, with the state of the last finished iteration kept.
  std::string step(std::int64_t target, nb::object progress, double interval) {
    if (failed_) throw SimulationError("this Mesher's run failed earlier; make a new one");
    const Busy busy(*this);
    // A run the stopping rule has ended is done: a later step (with another total, which changes when
    // population control counts as settled) must not start it again.
    if (target <= iterations_done() || converged_) return "done";
    // Copy on write: arrays handed to Python keep the node set they view alive and unchanged.
    if (nodes_.use_count() > 1) nodes_ = std::make_shared<NodeSet>(*nodes_);
    CaseConfig config = session_->config;
    config.simulation.iterations = target;
    std::atomic<bool> stop{false};
    std::exception_ptr pending;
    bool cancelled = false;
    const auto start = Clock::now();
    auto last = start;
    const auto every = std::chrono::duration<double>(interval);
    SimulateHooks hooks;
    hooks.stop = &stop;
    // The backend (for OpenCL its context and built program) is chosen by the first step, for the node
    // count then, and kept: a later step uploads the state again but sets nothing up.
    hooks.backend = [this, &config](const std::function<void(const std::string&)>& note) -> ChosenBackend& {
      if (!backend_) {
        backend_ = choose_backend_for(config.simulation.device, config.simulation.precision,
                                      static_cast<double>(nodes_->size()), note);
      }
      return *backend_;
    };
    int reported = -1;  // the last iteration the progress callable was given
    hooks.on_iteration = [&](const HistoryRow& row) {
      // Once stopping, the rest of a device window is replayed without asking again.
      if (stop.load()) return;
      const auto now = Clock::now();
      if (now - last < every && row.iteration < target) return;
      last = now;
      reported = row.iteration;
      nb::gil_scoped_acquire gil;
      try {
        if (PyErr_CheckSignals() != 0) throw nb::python_error();
        if (progress.is_valid() && !progress.is_none()) {
          nb::object r = progress(row.iteration, target, row.average_force, row.max_force, row.dt_gm,
                                  std::chrono::duration<double>(now - start).count());
          if (r.ptr() == Py_False) {
            cancelled = true;
            stop.store(true);
          }
        }
      } catch (...) {
        // Raised once the run has stopped cleanly (device queue finished, state consistent).
        pending = std::current_exception();
        stop.store(true);
      }
    };
    SimResult result;
    try {
      nb::gil_scoped_release release;
      std::lock_guard lock(session_->mutex);
      result = simulate(config, *session_->inputs, *session_->spacing, *nodes_, state_ ? &*state_ : nullptr, &hooks);
    } catch (...) {
      // The node set holds the last good state (SimCallbacks::on_failure), but the driver state
      // that goes with it is not kept: the Mesher can be triangulated, not continued.
      failed_ = true;
      throw;
    }
    state_ = std::move(result.state);
    seconds_ += result.stats.seconds;
    backend_name_ = result.stats.backend;
    converged_ = result.converged;
    if (pending) std::rethrow_exception(pending);
    // The last report is of the iteration the run ended at: a run the stopping rule ended before
    // `target` (never reported by the rule above) says so, rather than leaving an earlier row last.
    if (!cancelled && progress.is_valid() && !progress.is_none() && !state_->history.empty() &&
        (converged_ || reported != state_->iterations_done)) {
      const HistoryRow& row = state_->history.back();
      progress(row.iteration, target, row.average_force, row.max_force, row.dt_gm,
               std::chrono::duration<double>(Clock::now() - start).count(), converged_);
    }
    return cancelled ? "cancelled" : "done";
  }

  MeshHandle triangulate() {
    const Busy busy(*this);
    CaseConfig config = session_->config;
    config.simulation.iterations = iterations_done();
    std::shared_ptr<const NodeSet> nodes = nodes_;
    Mesh mesh;
    std::shared_ptr<const LayerParts> layers;
    auto periodic = std::make_shared<PeriodicPairs>();
    {
      nb::gil_scoped_release release;
      std::lock_guard lock(session_->mutex);
      if (session_->layered) {
        layers = with_layers(config, *nodes, mesh);
      } else {
        mesh = mesh_and_measure(config, *session_->inputs, *session_->spacing, *nodes);
      }
      // The pairs as the command writes them into mesh.msh: with layers, the core's and the layers'
      // end columns in the merged mesh (write_layered_outputs), else the core's (mesh_and_measure).
      const std::vector<PeriodicNodes> merged =
          layers ? merged_periodic_pairs(layers->mixed, session_->layered->layers->periodic_columns, *session_->inputs)
                 : std::vector<PeriodicNodes>{};
      const std::vector<PeriodicNodes>& pairs = layers ? merged : session_->inputs->periodic;
      if (!pairs.empty()) {
        periodic->links =
            layers ? link_periodic_nodes(boundary_of(layers->mixed), pairs) : link_periodic_nodes(mesh, pairs);
        for (const PeriodicNodes& p : pairs) periodic->transforms.push_back(p.transform);
      }
    }
    return MeshHandle{std::make_shared<const Mesh>(std::move(mesh)), session_, config.name, std::move(layers),
                      std::move(periodic)};
  }

  int iterations_done() const { return state_ ? state_->iterations_done : 0; }
  const std::shared_ptr<NodeSet>& nodes() const { return nodes_; }
  const std::optional<SimState>& state() const { return state_; }
  const CaseConfig& config() const { return session_->config; }
  double estimate() const { return estimate_; }
  std::size_t size_calls() const { return size_calls_; }
  std::size_t size_points() const { return size_points_; }
  double size_seconds() const { return size_seconds_; }
  double init_seconds() const { return init_seconds_; }
  double sim_seconds() const { return seconds_; }
  const std::string& backend() const { return backend_name_; }
  bool converged() const { return converged_; }

 private:
  // Marks the Mesher busy while a step or a triangulation runs with the GIL released: a second call
  // from another thread would replace the node set under the first (checked and set under the GIL).
  class Busy {
   public:
    explicit Busy(Mesher& m) : m_(m) {
      if (m_.busy_) throw std::runtime_error("this Mesher is already running (in another thread)");
      m_.busy_ = true;
    }
    ~Busy() { m_.busy_ = false; }
    Busy(const Busy&) = delete;
    Busy& operator=(const Busy&) = delete;

   private:
    Mesher& m_;
  };

  // As `pdmesh mesh` with [[boundary_layer]]: the layers are built on the case as given (its stages
  // move to session_->layered), and `c` and the session's stages become the core's case on the
  // layer fronts, which the steps then run.
  void run_on_core(CaseConfig& c) {
    auto l = std::make_unique<LayeredSession>();
    l->config = c;
    l->inputs = std::move(session_->inputs);
    l->spacing = std::move(session_->spacing);
    l->layers = build_layers(l->config, *l->inputs, *l->spacing);
    c = l->layers->core;
    session_->layered = std::move(l);
    session_->inputs = layered_core_inputs(*session_->layered->layers, *session_->layered->inputs);
    session_->spacing = std::make_unique<SpacingStage>(c, *session_->inputs);
  }

  // As `pdmesh mesh` with [[periodic]]: the case's stages move to session_->periodic, and `c` and the
  // session's stages become the case on the periodic nodes, which the steps then run (the mesh stage
  // writes the pairs as the command does).
  void run_on_periodic(CaseConfig& c) {
    auto p = std::make_unique<PeriodicSession>();
    p->inputs = std::move(session_->inputs);
    p->spacing = std::move(session_->spacing);
    p->periodic = build_periodic(c, *p->inputs, *p->spacing);
    c = p->periodic->core;
    session_->inputs = periodic_core_inputs(*p->periodic, *p->inputs);
    session_->periodic = std::move(p);
    session_->spacing = std::make_unique<SpacingStage>(c, *session_->inputs);
  }

  // The core's cleaned mesh of `nodes` (without the nodes the simulation snapped onto a front) merged
  // with the layer cells, as the command writes it: `mesh` gets every point and triangle; with an
  // output directory, the command's layered outputs are written there.
  std::shared_ptr<const LayerParts> with_layers(const CaseConfig& config, const NodeSet& nodes, Mesh& mesh) {
    const LayeredSession& l = *session_->layered;
    auto parts = std::make_shared<LayerParts>();
    parts->core = mesh_layered_core(config, *session_->inputs, *session_->spacing, nodes, *l.layers);
    if (config.write_outputs) {
      RunPhases phases(false);
      CaseConfig outer = l.config;
      outer.simulation.iterations = config.simulation.iterations;
      write_layered_outputs(outer, *l.inputs, *l.layers, *session_->inputs, parts->core, phases);
    }
    parts->mixed = merged_layer_mesh(*l.inputs, *l.layers, *session_->inputs, parts->core);
    parts->walls = wall_curves(l.config);
    const MixedMesh& m = parts->mixed;
    mesh.points = m.points;
    mesh.boundary_edges = m.boundary_edges;
    mesh.curve_names = m.curve_names;
    // The input's curve groups and regions, as the command's layered files keep them (Mesh.curve_groups,
    // Mesh.regions per triangle, the layer's included).
    mesh.curve_groups = m.curve_groups;
    mesh.region_names = m.region_names;
    for (std::size_t k = 0; k < m.cells.size(); ++k) {
      const auto& v = m.cells[k];
      if (v[3] >= 0) {
        parts->quads.push_back(v);
      } else {
        mesh.triangles.push_back({v[0], v[1], v[2]});
        parts->triangle_layer.push_back(m.layer[k]);
        if (!m.region.empty()) mesh.region.push_back(m.region[k]);
      }
    }
    if (mesh.region.empty()) mesh.region_names.clear();
    return parts;
  }

  std::shared_ptr<Session> session_;
  std::shared_ptr<NodeSet> nodes_;
  std::optional<SimState> state_;
  double estimate_ = 0.0;
  std::size_t size_calls_ = 0;
  std::size_t size_points_ = 0;
  double size_seconds_ = 0.0;
  double init_seconds_ = 0.0;
  double seconds_ = 0.0;
  std::optional<ChosenBackend> backend_;  // set up by the first step
  std::string backend_name_;
  bool failed_ = false;
  bool busy_ = false;
  bool converged_ = false;  // the stopping rule ended the run (SimResult::converged of the last step)
};

// The history rows as columns (copies: a history is small next to the nodes).
nb::dict history_columns(const std::vector<HistoryRow>& rows) {
  auto column = [&rows](auto member) {
    auto* v = new std::vector<double>();
    for (const HistoryRow& r : rows) v->push_back(static_cast<double>(r.*member));
    nb::capsule owner(v, [](void* p) noexcept { delete static_cast<std::vector<double>*>(p); });
    return nb::ndarray<nb::numpy, double>(v->data(), {v->size()}, owner);
  };
  nb::dict d;
  d["iteration"] = column(&HistoryRow::iteration);
  d["average_force"] = column(&HistoryRow::average_force);
  d["max_force"] = column(&HistoryRow::max_force);
  d["average_kinetic"] = column(&HistoryRow::average_kinetic);
  d["dt_gm"] = column(&HistoryRow::dt_gm);
  d["snapped"] = column(&HistoryRow::snapped);
  return d;
}

}  // namespace

void bind_mesher(nb::module_& m) {
  m.def("_backend_setups", &backend_setups,
        "How many simulation backends this process has set up (choose_backend); for tests.");
  nb::class_<Mesher>(m, "Mesher", "One case's run in memory (use pdmesh.Mesher).")
      .def(nb::init<const CaseConfig&, const std::string&, std::uint64_t>(), nb::arg("config"), nb::arg("out_dir") = "",
           nb::arg("max_nodes") = 0,
           "Reads the geometry, builds the spacing field and the initial distribution; with out_dir, writes the "
           "command's outputs there as the run goes; max_nodes > 0 replaces the --max-nodes limit.")
      .def("step", &Mesher::step, nb::arg("target"), nb::arg("progress").none(), nb::arg("interval") = 0.1,
           "Runs up to `target` iterations in all; 'done' or 'cancelled'.")
      .def("triangulate", &Mesher::triangulate, "The mesh of the current nodes.")
      .def_prop_ro("iterations_done", &Mesher::iterations_done)
      .def_prop_ro("iterations", [](const Mesher& s) { return s.config().simulation.iterations; })
      .def_prop_ro("name", [](const Mesher& s) { return s.config().name; })
      .def_prop_ro("estimate", &Mesher::estimate, "The hexagonal-packing node-count estimate.")
      .def_prop_ro("size_calls", &Mesher::size_calls, "How often the size callable was called.")
      .def_prop_ro("size_points", &Mesher::size_points, "How many points the size callable was given in all.")
      .def_prop_ro("size_seconds", &Mesher::size_seconds, "Seconds spent sampling the size callable.")
      .def_prop_ro("init_seconds", &Mesher::init_seconds)
      .def_prop_ro("sim_seconds", &Mesher::sim_seconds)
      .def_prop_ro("backend", &Mesher::backend)
      .def_prop_ro("converged", &Mesher::converged, "Whether the stopping rule has ended the run.")
      .def_prop_ro("size", [](const Mesher& s) { return s.nodes()->size(); })
      .def_prop_ro(
          "points",
          [](const Mesher& s) {
            const auto& n = s.nodes();
            return shared_view<double, 2>(n->size() ? &n->x[0].x : nullptr, n->size(), n);
          },
          nb::rv_policy::automatic, "(N, 2) float64 node positions, read-only, no copy.")
      .def_prop_ro(
          "spacing",
          [](const Mesher& s) { return shared_view<double, 1>(s.nodes()->q.data(), s.nodes()->size(), s.nodes()); },
          nb::rv_policy::automatic, "(N,) float64 desired spacing q at each node, read-only, no copy.")
      .def_prop_ro(
          "kinds",
          [](const Mesher& s) {
            static_assert(sizeof(NodeKind) == 1);
            const auto* k = reinterpret_cast<const std::uint8_t*>(s.nodes()->kind.data());
            return shared_view<std::uint8_t, 1>(k, s.nodes()->size(), s.nodes());
          },
          nb::rv_policy::automatic, "(N,) uint8 node kinds: 0 fixed, 1 boundary, 2 interior; read-only, no copy.")
      .def_prop_ro("history", [](const Mesher& s) {
        return history_columns(s.state() ? s.state()->history : std::vector<HistoryRow>{});
      });
}

}  // namespace pdmesh::py
