"""Runs: ``generate()`` (one call, geometry in, mesh out), ``Mesher`` (a run held in memory that a
notebook can step, watch, interrupt, continue and triangulate at any point) and ``Case`` (the
command's case files)."""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any, Iterator, Mapping

import numpy as np

from . import _core, _progress, _settings, metric as _metric, size as _size
from .errors import Cancelled, InputError
from .geometry import Geometry
from .mesh import Mesh

# How often (seconds) a running step takes the GIL back to check for Ctrl-C and report progress.
CHECK_INTERVAL = 0.1


def _settings_for(size: Any, device: str | None, seed: int | None, settings: Mapping[str, Any] | None,
                  keywords: Mapping[str, Any]) -> tuple[list, Any]:
    size_settings, sampler = _size.resolve(size)
    pairs = _settings.flatten(size_settings)
    pairs += _settings.flatten({"device": device, "seed": seed})
    pairs += _settings.flatten(settings)
    pairs += _settings.flatten(keywords)
    return _settings.overrides(pairs), sampler


@dataclass(frozen=True)
class State:
    """A Mesher's state after a step (``Mesher.iterate`` yields these). The arrays are read-only
    views of the run's own memory (no copy); they stay valid and unchanged after later steps."""

    iteration: int
    points: np.ndarray   #: (N, 2) float64 node positions
    spacing: np.ndarray  #: (N,) float64 desired spacing q at each node
    kinds: np.ndarray    #: (N,) uint8: 0 fixed, 1 boundary, 2 interior
    average_force: float
    max_force: float


def _settings_dict(settings: Mapping[str, Any] | None) -> dict:
    return dict(settings) if settings is not None else {}


def _write_initial(initial: Any, directory: str) -> str:
    """The warm start's points, an (N, 2) array of finite numbers, as a node file in directory
    (docs/node-file.md: interior nodes, no curves); InputError naming the value otherwise."""
    try:
        points = np.asarray(initial, dtype=float)
    except (TypeError, ValueError) as e:
        raise InputError(f"initial: not an (N, 2) array of numbers: {e}") from None
    if points.ndim != 2 or points.shape[1] != 2 or points.shape[0] < 1:
        raise InputError(f"initial: an (N, 2) array of points with N >= 1 is needed, got shape {points.shape}")
    bad = np.flatnonzero(~np.isfinite(points).all(axis=1))
    if bad.size:
        i = int(bad[0])
        raise InputError(f"initial: point {i} is ({float(points[i, 0])!r}, {float(points[i, 1])!r}), not finite")
    path = os.path.join(directory, "initial.nodes")
    with open(path, "w", encoding="ascii") as f:
        f.write(f"# pdmesh nodes v1\n{len(points)}\n")
        f.writelines(f"{x:.17g} {y:.17g} interior -1 1\n" for x, y in points)
        f.write("curves 0\n")
    return path


class Mesher:
    """One run held in memory: the geometry, the spacing field and the nodes.

    ``Mesher(geo, size=None, device=None, seed=None, settings=None, **keywords)`` reads the geometry,
    samples the spacing field and places the initial nodes; ``run()``, ``step(n)`` and
    ``iterate(every=50)`` move them; ``triangulate()`` meshes them at any point. A step interrupted by
    Ctrl-C (KeyboardInterrupt) or cancelled (progress returned False: ``pdmesh.Cancelled``) stops at
    the end of an iteration (on an OpenCL device, of the device's window of at most 32); the Mesher then continues from there, on the host device to the same
    result as a run that was never interrupted. ``geo`` is a Geometry, anything Geometry() accepts,
    or a Case. Keywords are case-file settings (see ``generate``). With ``out`` (a directory) the
    run also writes the command's outputs there. ``max_nodes`` refuses (LimitError) a case whose
    node-count estimate is larger (the command's --max-nodes, default 20,000,000).
    """

    def __init__(self, geo: Any, size: Any = None, *, device: str | None = None, seed: int | None = None,
                 settings: Mapping[str, Any] | None = None, out: str | os.PathLike | None = None,
                 max_nodes: int | None = None, initial: Any = None, **keywords: Any):
        if initial is None:
            self._start(geo, size, device, seed, settings, out, max_nodes, keywords)
            return
        # The warm start: the points go to the core as a node file (case key init.file), read while
        # it places the initial nodes.
        with _metric.temporary_directory() as directory:
            path = _write_initial(initial, directory)
            settings = {**_settings_dict(settings), "init.file": path}
            self._start(geo, size, device, seed, settings, out, max_nodes, keywords)

    def _start(self, geo: Any, size: Any, device: str | None, seed: int | None, settings: Any,
               out: str | os.PathLike | None, max_nodes: int | None, keywords: dict) -> None:
        overrides, sampler = _settings_for(size, device, seed, settings, keywords)
        if not isinstance(geo, (Case, Geometry)):
            geo = Geometry(geo)
        config = geo._with(overrides) if isinstance(geo, Case) else geo._config(overrides)
        if max_nodes is not None and int(max_nodes) < 1:
            raise InputError(f"max_nodes must be >= 1, got {max_nodes}")
        out_dir = os.fspath(out) if out is not None else ""
        if isinstance(sampler, _metric.Metric):
            self._core = self._metric_core(geo, config, sampler, overrides, out_dir, max_nodes)
            return
        if sampler is not None:
            config = config.with_size_callable(sampler)  # sampled, then let go, by the core's Mesher
        try:
            self._core = _core.Mesher(config, out_dir, int(max_nodes or 0))
        except _metric.MetricResult:
            # The callable's first batch came back as (N, 3) or (N, 2, 2) metrics.
            self._core = self._metric_core(geo, config, _metric.Metric(sampler.function), overrides, out_dir,
                                           max_nodes)

    @staticmethod
    def _metric_core(geo: Any, config: Any, metric: "_metric.Metric", overrides: list, out_dir: str,
                     max_nodes: int | None) -> Any:
        """The core run of a metric callable: sampled on a grid over the geometry's bounding box into a
        temporary metric .vtu, which the core reads while it sets the run up."""
        with _metric.temporary_directory() as directory:
            keys = _metric.sample_to_file(metric.function, config.geometry()["extents"], metric.grid, directory)
            pairs = overrides + _settings.overrides(_settings.flatten(keys))
            config = geo._with(pairs) if isinstance(geo, Case) else geo._config(pairs)
            return _core.Mesher(config, out_dir, int(max_nodes or 0))

    @property
    def name(self) -> str:
        return self._core.name

    @property
    def iteration(self) -> int:
        """Iterations done so far."""
        return self._core.iterations_done

    @property
    def converged(self) -> bool:
        """Whether the stopping rule (simulation.stop = "converged") has ended the run: further
        steps, run() and iterate() leave it where it is."""
        return self._core.converged

    @property
    def iterations(self) -> int:
        """The case's iteration count (simulation.iterations), where run() stops."""
        return self._core.iterations

    @property
    def points(self) -> np.ndarray:
        """(N, 2) float64 node positions now: a read-only view, no copy."""
        return self._core.points

    @property
    def spacing(self) -> np.ndarray:
        """(N,) float64 desired spacing q at each node: a read-only view, no copy."""
        return self._core.spacing

    @property
    def kinds(self) -> np.ndarray:
        """(N,) uint8 node kinds (0 fixed, 1 boundary, 2 interior): a read-only view, no copy."""
        return self._core.kinds

    @property
    def history(self) -> dict[str, np.ndarray]:
        """Per iteration: average and maximum |F|, average kinetic energy, dt_GM, snaps (history.csv)."""
        return self._core.history

    @property
    def backend(self) -> str:
        """Where the last step ran: "reference" (the host) or "opencl:P:D (device, precision, ...)"."""
        return self._core.backend

    @property
    def size_calls(self) -> int:
        """How often a size callable was called (once per sampling pass); 0 without one."""
        return self._core.size_calls

    @property
    def size_points(self) -> int:
        """How many points the size callable was given in all its calls."""
        return self._core.size_points

    @property
    def timings(self) -> dict[str, float]:
        """Seconds spent: initialization (geometry, spacing, initial nodes), of which sampling the
        size callable (its calls and the hand-over of the arrays), and simulation."""
        return {"init": self._core.init_seconds, "size": self._core.size_seconds, "simulation": self._core.sim_seconds}

    def state(self) -> State:
        h = self._core.history
        last = len(h["iteration"]) - 1
        return State(self.iteration, self.points, self.spacing, self.kinds,
                     float(h["average_force"][last]) if last >= 0 else float("nan"),
                     float(h["max_force"][last]) if last >= 0 else float("nan"))

    def step(self, iterations: int = 1, progress: Any = None) -> State:
        """Runs `iterations` more iterations (see run() for `progress`)."""
        return self._run_to(self.iteration + int(iterations), progress)

    def run(self, iterations: int | None = None, progress: Any = None) -> State:
        """Runs to `iterations` in all (default: the case's simulation.iterations). ``progress``: True
        draws a bar on stderr; a callable gets a pdmesh.Progress about every 0.1 s and may return
        False to cancel (pdmesh.Cancelled; the Mesher can go on)."""
        return self._run_to(self.iterations if iterations is None else int(iterations), progress)

    def iterate(self, every: int = 50, iterations: int | None = None, progress: Any = None) -> Iterator[State]:
        """Steps `every` iterations at a time up to `iterations` (default: the case's), yielding the
        state after each step: ``for s in m.iterate(every=50): plot(s.points)``."""
        if every < 1:
            raise InputError(f"iterate: every must be >= 1, got {every}")
        target = self.iterations if iterations is None else int(iterations)
        # A run whose stopping rule (simulation.stop = "converged") has ended it before `target`
        # stays where it is: no further step would move it.
        while self.iteration < target and not self.converged:
            before = self.iteration
            state = self._run_to(min(target, self.iteration + every), progress)
            # The stopping rule may end the run where it stands (a run that converged exactly at the
            # last step's end): that state was yielded already.
            if self.iteration == before:
                return
            yield state

    def _run_to(self, target: int, progress: Any) -> State:
        report, bar = _progress.callback(progress)
        try:
            status = self._core.step(target, report, CHECK_INTERVAL)
        finally:
            if bar is not None:
                bar.close()
        if status == "cancelled":
            raise Cancelled(f"cancelled by the progress callable after iteration {self.iteration}", self)
        return self.state()

    def triangulate(self) -> Mesh:
        """The mesh of the nodes as they are now (boundary edges kept, outside triangles removed)."""
        return Mesh(self._core.triangulate())

    def __repr__(self) -> str:
        return f"<pdmesh.Mesher {self.name!r}: {self._core.size} nodes, iteration {self.iteration}/{self.iterations}>"


def generate(geometry: Any, size: Any = None, *, device: str | None = None, seed: int | None = None,
             progress: Any = False, settings: Mapping[str, Any] | None = None, max_nodes: int | None = None,
             **keywords: Any) -> Mesh:
    """Meshes a geometry: places the nodes by the particle simulation and triangulates them.

    ``geometry``: a Geometry, a list of (N, 2) rings, a shapely polygon, or a path (a case file or a
    geometry file). ``size``: see pdmesh.size (None: the boundary field of thesis eq. 3.6).
    ``device``: "auto", "host", "opencl" or "opencl:P:D". ``seed``: init.seed. ``progress``: True
    for a bar on stderr, or a callable (see Mesher.run). Any case-file key as a keyword:
    ``iterations=500``, ``method="random"``, a section as a dict (``simulation={"cutoff": 1.6}``),
    or ``settings={"simulation.cutoff": 1.6}``; the values are checked exactly as the command
    checks a case file. A geometry alone runs with preset "best", as the command does.
    ``boundary_layer={"curves": ["upper", "lower"], "first_height": 1e-5, "growth": 1.2,
    "thickness": 0.05, "elements": "quads"}`` (or a list of such dicts, one per curve set; the keys
    of the case file's [[boundary_layer]], docs/boundary-layers.md) grows layers from those curves
    and meshes the core on their fronts: the mesh then has ``quads`` and ``triangle_layer``.
    ``max_nodes``: see Mesher. ``initial``: a warm start, an (N, 2) array of points (e.g. the previous
    mesh's ``points`` in an adaptation loop) whose interior points are the initial interior nodes
    (the case key init.file; docs/metric-fields.md, "Adaptation to a solution").
    """
    if isinstance(geometry, (str, os.PathLike)):
        path = os.fspath(geometry)
        geometry = Case.from_toml(path) if path.lower().endswith(".toml") else Geometry.from_file(path)
    mesher = Mesher(geometry, size, device=device, seed=seed, settings=settings, max_nodes=max_nodes, **keywords)
    mesher.run(progress=progress)
    return mesher.triangulate()


class Case:
    """A case file (TOML) as the command reads it: ``Case.from_toml("cases/naca0012/case.toml").run()``."""

    def __init__(self, path: str | os.PathLike, settings: Mapping[str, Any] | None = None, **keywords: Any):
        """The same as Case.from_toml(path, settings, **keywords)."""
        self._path = os.fspath(path)
        self._overrides = _settings.overrides(_settings.flatten(settings) + _settings.flatten(keywords))
        self._config_obj = _core.load_case(self._path, self._overrides)

    @classmethod
    def from_toml(cls, path: str | os.PathLike, settings: Mapping[str, Any] | None = None,
                  **keywords: Any) -> "Case":
        """Reads and validates a case file; settings and keywords override its keys as in generate()."""
        return cls(path, settings, **keywords)

    def _with(self, overrides: list) -> Any:
        if not overrides:
            return self._config_obj
        return _core.load_case(self._path, self._overrides + overrides)

    @property
    def name(self) -> str:
        return self._config_obj.name

    @property
    def preset(self) -> str:
        return self._config_obj.preset

    @property
    def iterations(self) -> int:
        return self._config_obj.iterations

    @property
    def method(self) -> str:
        """The initial fill (init.method): "structured", "random", "hexagonal" or "hybrid"."""
        return self._config_obj.method

    @property
    def device(self) -> str:
        return self._config_obj.device

    @property
    def seed(self) -> int:
        return self._config_obj.seed

    @property
    def geometry(self) -> Geometry:
        """The case's geometry files, with the case's curve names."""
        return Geometry.from_file(*self._config_obj.geometry_files, names=self._config_obj.curve_names or None)

    def mesher(self, size: Any = None, **keywords: Any) -> Mesher:
        return Mesher(self, size, **keywords)

    def run(self, progress: Any = False, out: str | os.PathLike | None = None, **keywords: Any) -> Mesh:
        """Runs the case (its preset and settings); with ``out``, also writes the command's outputs
        there (as ``pdmesh mesh CASE --out DIR``). Keywords override settings as in generate()."""
        mesher = Mesher(self, out=out, **keywords)
        mesher.run(progress=progress)
        return mesher.triangulate()

    def __repr__(self) -> str:
        return f"Case.from_toml({self._path!r})"
