"""Moving geometry (docs/motion.md): a case with ``[motion]`` meshed step by step, each step warm from
the previous one, with persistent node ids (``run_motion``); the same steps with poses that the
caller decides one at a time (``MovingMesher``, for a solver's loop); and the solution transfer
between two steps' meshes."""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import Any, Callable, Mapping, Sequence

import numpy as np

from . import _core, metric as _metric
from ._arrays import mesh_arrays
from .errors import InputError
from .geometry import Geometry
from .mesh import Mesh, _point_arrays
from .mesher import Case, _settings_for


@dataclass(frozen=True)
class MotionStep:
    """One step of a motion run: its mesh, and per point of the mesh its persistent node id (the same
    id as in the previous step for the same particle; new nodes get new ids)."""

    step: int
    t: float
    mesh: Mesh
    node_id: np.ndarray  #: (N,) int64, one per point of mesh
    ids_kept: float      #: share of the previous step's ids this step still has (1 at step 0)
    min_angle: float
    iterations: int
    wall_s: float


def run_motion(case: Case | str | os.PathLike, out: str | os.PathLike | None = None,
               on_step: Callable[[MotionStep], Any] | None = None, **keywords: Any) -> list[MotionStep]:
    """Runs every step of a case with ``[motion]`` (a Case or a case file; keywords override its keys
    as in Case). ``on_step`` is called after each step; with ``out`` the command's files are written
    there too (step_NNNN/mesh.vtu, motion.pvd, motion.json). Returns the steps."""
    if not isinstance(case, Case):
        case = Case(case, **keywords)
    elif keywords:
        raise TypeError("keywords go with a case file path, not with a Case")
    steps: list[MotionStep] = []

    def each(core: Any, r: dict) -> None:
        s = MotionStep(step=int(r["step"]), t=float(r["t"]), mesh=Mesh(core),
                       node_id=np.asarray(r["node_id"], dtype=np.int64), ids_kept=float(r["ids_kept"]),
                       min_angle=float(r["min_angle"]), iterations=int(r["iterations"]), wall_s=float(r["wall_s"]))
        steps.append(s)
        if on_step is not None:
            on_step(s)

    _core.motion_steps(case._config_obj, os.fspath(out) if out is not None else "", each)
    return steps


def _step_of(core: Any) -> MotionStep:
    r = core.record
    return MotionStep(step=int(r["step"]), t=float(r["t"]), mesh=Mesh(core.mesh), node_id=np.asarray(core.node_id),
                      ids_kept=float(r["ids_kept"]), min_angle=float(r["min_angle"]),
                      iterations=int(r["iterations"]), wall_s=float(r["wall_s"]))


def _number(value: Any, name: str) -> float:
    """value as a finite float, or InputError naming it."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(f"{name} = {v!r} is not finite")
    return v


def _pair(value: Any, name: str) -> tuple[float, float]:
    """value as two finite floats (x, y), or InputError naming it."""
    try:
        items = list(value)
    except TypeError:
        items = []
    if len(items) != 2:
        raise InputError(f"{name} must be a pair of numbers (x, y), got {value!r}")
    return _number(items[0], f"{name}[0]"), _number(items[1], f"{name}[1]")


class MovingMesher:
    """A mesh that moves with some of its curves, posed by the caller one step at a time: the steps of
    ``[motion]`` (docs/motion.md) for a solver that decides the motion as it goes.

    ``MovingMesher(geo, moving, pivot, rotate=0, translate=(0, 0), ...)`` reads the geometry (what
    ``Mesher`` takes: a Geometry, rings, a Case or a case file), places the ``moving`` curves (names)
    at the start pose and meshes it cold: step 0. Then ``move(rotate, translate)`` sets the moving
    curves' next pose (absolute, from their place as read: degrees counter-clockwise about ``pivot``,
    then the translation) and ``step()`` meshes it warm from the previous step: the nodes carried with
    the body, relaxed, repopulated and cleaned, with persistent ``node_id``. A case with ``[motion]``
    gives the defaults of ``moving`` and ``pivot`` (its ``rotate``/``translate``/``steps`` are not
    used), and ``warm_iterations``/``blend`` default to its motion.iterations/motion.blend (30, 4).
    With ``out`` the steps' files are written there as the command writes them (step_NNNN/,
    motion.pvd, motion.json). ``size``, ``device``, ``seed``, ``settings`` and keywords as in
    ``Mesher``; a size callable is not taken (each step rebuilds the geometry's inputs).
    """

    def __init__(self, geo: Any, moving: Sequence[str] | None = None, pivot: Sequence[float] | None = None, *,
                 rotate: float = 0.0, translate: Sequence[float] = (0.0, 0.0), size: Any = None,
                 device: str | None = None, seed: int | None = None, settings: Mapping[str, Any] | None = None,
                 out: str | os.PathLike | None = None, warm_iterations: int | None = None,
                 blend: float | None = None, **keywords: Any):
        overrides, sampler = _settings_for(size, device, seed, settings, keywords)
        if sampler is not None:
            raise InputError("MovingMesher: size must be a number, an expression or a Background, not a callable")
        if isinstance(geo, (str, os.PathLike)):
            path = os.fspath(geo)
            geo = Case(path) if path.lower().endswith(".toml") else Geometry.from_file(path)
        if not isinstance(geo, (Case, Geometry)):
            geo = Geometry(geo)
        config = geo._with(overrides) if isinstance(geo, Case) else geo._config(overrides)
        motion = config.motion
        if moving is None:
            moving = motion["curves"] if motion["enabled"] else []
        if isinstance(moving, str):
            moving = [moving]
        if pivot is None:
            pivot = motion["pivot"] if motion["enabled"] else (0.0, 0.0)
        self._pivot = _pair(pivot, "pivot")
        angle, shift = _number(rotate, "rotate"), _pair(translate, "translate")
        self._target = (angle, shift)
        self._core = _core.MotionStepper(config, [str(n) for n in moving], self._pivot, angle, shift,
                                         -1 if warm_iterations is None else int(warm_iterations),
                                         float("nan") if blend is None else float(blend),
                                         os.fspath(out) if out is not None else "")
        self._last = _step_of(self._core)

    def move(self, rotate: float | None = None, translate: Sequence[float] | None = None) -> None:
        """Sets the moving curves' pose for the next step: ``rotate`` degrees counter-clockwise about the
        pivot, then ``translate`` (x, y), both absolute (from the curves as read); one left out keeps
        its last value. Nothing is meshed until ``step()``."""
        angle, shift = self._target
        self._target = (angle if rotate is None else _number(rotate, "move: rotate"),
                        shift if translate is None else _pair(translate, "move: translate"))

    def step(self, t: float | None = None) -> MotionStep:
        """Meshes the next step at the pose of the last ``move()`` (warm from the previous step) and
        returns it; ``t`` is its time in the records and motion.pvd (default: the step's number)."""
        angle, shift = self._target
        k = self._last.step + 1
        self._core.step(angle, shift, float(k) if t is None else float(t))
        self._last = _step_of(self._core)
        return self._last

    @property
    def last(self) -> MotionStep:
        """The last step (step 0 after construction)."""
        return self._last

    @property
    def mesh(self) -> Mesh:
        """The last step's mesh (point data ``node_id`` in its .vtu)."""
        return self._last.mesh

    @property
    def node_id(self) -> np.ndarray:
        """(N,) int64 persistent ids of the last step's points."""
        return self._last.node_id

    @property
    def record(self) -> dict[str, float]:
        """The last step's row of motion.json: step, t, wall_s, cpu_s, iterations, nodes, ids_kept,
        min_angle, inverted, carry_substeps, spacing_s, simulation_s, cleanup_s."""
        return dict(self._core.record)

    @property
    def pose(self) -> tuple[float, tuple[float, float]]:
        """The last step's pose: (degrees, (x, y))."""
        return float(self._core.rotate), tuple(self._core.translate)

    @property
    def pivot(self) -> tuple[float, float]:
        return self._pivot

    @property
    def backend(self) -> str:
        """Where the simulation runs (chosen for step 0 and kept)."""
        return self._core.backend

    def __repr__(self) -> str:
        return f"<pdmesh.MovingMesher: step {self._last.step}, {len(self._last.node_id)} nodes>"


def _transfer_points(points: Any) -> np.ndarray:
    """The target points: a Mesh's, or an (M, 2) array; InputError naming ``points`` otherwise."""
    if isinstance(points, Mesh):
        points = points.points
    try:
        p = np.ascontiguousarray(points, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise InputError(f"points: not an (M, 2) array of numbers: {e}") from None
    if p.ndim != 2 or p.shape[1] != 2:
        raise InputError(f"points: an (M, 2) array of points (or a Mesh) is needed, got shape {p.shape}")
    return p


def _value_rows(values: Any, n: int, name: str) -> np.ndarray:
    """values as a contiguous (n,) or (n, k) float64 array; InputError naming ``name`` otherwise."""
    try:
        v = np.ascontiguousarray(values, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise InputError(f"{name}: not an array of numbers: {e}") from None
    if v.ndim not in (1, 2) or v.shape[0] != n or (v.ndim == 2 and v.shape[1] < 1):
        raise InputError(f"{name}: one row per point of the source, shape ({n},) or ({n}, k), is needed; got shape "
                         f"{v.shape}")
    return v


def transfer(source: Any, values: Any, points: Any) -> Any:
    """Point values of ``source`` interpolated linearly at ``points``: in the triangle that holds each
    point, or at the nearest boundary point for a point outside the mesh (where the body was). The
    same code as ``pdmesh transfer`` and the solution.vtu of ``pdmesh adapt``.

    ``source``: a Mesh, a ``(points, triangles)`` pair, or a .vtu or .msh file with point data.
    ``values``: an (N,) or (N, k) array of values at the source's N points (returns (M,) or (M, k));
    a dict name -> such arrays (returns a dict); or names of the source's own point arrays (a file's,
    or a Mesh's ``point_data``): one name returns its array, a list of names or None (all: a file's
    but kind, q and node_id) a dict. ``points``: an (M, 2) array, or a Mesh (its points)."""
    p = _transfer_points(points)
    if isinstance(source, (str, os.PathLike)):
        path = os.fspath(source)
        if not os.path.isfile(path):
            raise InputError(f"source: cannot read '{path}': no such file")
        if values is not None and not isinstance(values, str) and not _names_only(values):
            raise InputError(f"values: a source file ({path}) brings its own point data; give the names of its "
                             "arrays (a name, a list of names, or None for all)")
        names = [] if values is None else [values] if isinstance(values, str) else list(values)
        arrays = _point_arrays(_core.transfer_file(path, names, p))
        return arrays[values] if isinstance(values, str) else arrays
    if isinstance(source, Mesh):
        if values is None or isinstance(values, str) or _names_only(values):
            own = source.point_data
            names = list(own) if values is None else [values] if isinstance(values, str) else list(values)
            if not names:
                raise InputError("values: the source Mesh has no point_data; give the values at its points")
            for name in names:
                if name not in own:
                    raise InputError(f"values={name!r}: the source Mesh has no point array '{name}' (point_data: "
                                     f"{', '.join(own) if own else 'none'})")
            values = own[values] if isinstance(values, str) else {name: own[name] for name in names}
        n = len(source.points)

        def one(v: Any, name: str) -> np.ndarray:
            v = _value_rows(v, n, name)
            v2 = v.reshape(-1, 1) if v.ndim == 1 else v
            out = np.asarray(_core.transfer(source._core, v2, p), dtype=float).reshape(len(p), v2.shape[1])
            return out[:, 0] if v.ndim == 1 else out

        if isinstance(values, Mapping):
            return {str(k): one(v, f"values[{k!r}]") for k, v in values.items()}
        return one(values, "values")
    if not (isinstance(source, tuple) and len(source) == 2):
        raise InputError("source: expected a pdmesh.Mesh, a (points, triangles) pair of arrays or a .vtu or .msh "
                         f"file with point data, got {type(source).__name__}")
    points0, triangles = mesh_arrays(source[0], source[1], "source")
    if values is None or isinstance(values, str) or _names_only(values):
        raise InputError("values: a (points, triangles) source needs the values at its points (an (N,) or (N, k) "
                         "array, or a dict name -> array)")
    named = dict(values) if isinstance(values, Mapping) else {"values": values}
    arrays = {str(k): _value_rows(v, len(points0), f"values[{k!r}]" if isinstance(values, Mapping) else "values")
              for k, v in named.items()}
    # Through a .vtu, as pdmesh.adapt carries a solution in memory: the same code and values.
    with _metric.temporary_directory() as directory:
        path = os.path.join(directory, "source.vtu")
        _metric.write_vtu(path, points0, triangles, arrays)
        moved = _point_arrays(_core.transfer_file(path, list(arrays), p))
    return moved if isinstance(values, Mapping) else moved["values"]


def _names_only(values: Any) -> bool:
    """Whether values is a non-empty list or tuple of strings (names of point arrays)."""
    return isinstance(values, (list, tuple)) and len(values) > 0 and all(isinstance(v, str) for v in values)
