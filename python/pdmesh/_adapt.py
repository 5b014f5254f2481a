"""``adapt()``: one step of a solve-adapt loop, the domain re-meshed in the Hessian metric of a solution
(the command ``pdmesh adapt``, docs/metric-fields.md, "Adaptation to a solution")."""

from __future__ import annotations

import os
from typing import Any, Mapping, Sequence

import numpy as np

from . import _core, _settings, metric as _metric
from ._arrays import mesh_arrays
from .errors import InputError
from .geometry import Geometry
from .mesh import Mesh
from .mesher import Case, Mesher, _settings_for, _write_initial

# How messages name each key the command sets: by the argument of adapt() that gives it.
_ARGUMENTS = {
    "spacing.file": "solution",
    "spacing.array": "array",
    "spacing.complexity": "complexity",
    "spacing.hmin": "hmin",
    "spacing.hmax": "hmax",
    "spacing.max_anisotropy": "max_anisotropy",
    "spacing.norm": "norm",
    "spacing.metric_gradation": "gradation",
}


def _domain(domain: Any) -> Case | Geometry:
    """The domain as generate() takes it: a Case, a Geometry, rings, or a path (a case file, a case
    directory, a geometry or mesh file)."""
    if isinstance(domain, (str, os.PathLike)):
        path = os.fspath(domain)
        if os.path.isdir(path):
            path = os.path.join(path, "case.toml")
        return Case.from_toml(path) if path.lower().endswith(".toml") else Geometry.from_file(path)
    if isinstance(domain, (Case, Geometry)):
        return domain
    return Geometry(domain)


def _split(array: str | Sequence[str]) -> list[str]:
    """``array`` as a list of names: a string split at its commas (the command's ``--array u,v``), a
    list as given; InputError naming the argument for an empty name or a name that is not a string."""
    if isinstance(array, str):
        names = array.split(",")
        if not all(names):
            what = "is empty" if array == "" else "has an empty name between or beside its commas"
            raise InputError(f"array={array!r}: {what}; name the solution's point array(s): 'u' or 'u,v'")
        return names
    try:
        names = list(array)
    except TypeError:
        raise InputError(f"array: expected a point array's name or a list of names, got {array!r}") from None
    if not names or not all(isinstance(n, str) and n for n in names):
        raise InputError(f"array: expected a point array's name or a list of names, got {array!r}")
    return names


def _names(array: str | Sequence[str] | None, values: Any) -> list[str]:
    """The arrays to adapt to: ``array`` as a list, or the keys of ``values`` without it."""
    if array is None:
        if isinstance(values, Mapping) and values:
            return [str(k) for k in values]
        raise InputError("array: name the solution's point array(s) to adapt to (array='u' or array=['u', 'v'])")
    return _split(array)


def _solution_arrays(points: np.ndarray, values: Any, array: str | Sequence[str] | None) -> dict[str, np.ndarray]:
    """``values`` as name -> (N,) float64 arrays for the N points; InputError naming a wrong shape or length."""
    if values is None:
        raise InputError("values: a solution given as a Mesh or (points, triangles) needs its point values "
                         "(values={'u': u} or values=u with array='u')")
    if not isinstance(values, Mapping):
        if not isinstance(array, str) or "," in array:
            raise InputError(f"values: one array of values needs its name as array='NAME', got array={array!r}")
        values = {array: values}
    out = {}
    for name, v in values.items():
        try:
            a = np.asarray(v, dtype=np.float64)
        except (TypeError, ValueError) as e:
            raise InputError(f"values['{name}']: not an array of numbers: {e}") from None
        if a.shape != (len(points),):
            raise InputError(f"values['{name}']: one value per point, shape ({len(points)},), is needed; got shape "
                             f"{a.shape}")
        out[str(name)] = a
    return out


def _solution_mesh(solution: Any) -> tuple[np.ndarray, np.ndarray]:
    """The points and triangles of a Mesh or a (points, triangles) pair; InputError naming a wrong shape."""
    if isinstance(solution, Mesh):
        return np.asarray(solution.points, dtype=np.float64), np.asarray(solution.triangles)
    try:
        points, triangles = solution[0], solution[1]
    except (TypeError, IndexError, KeyError) as e:
        raise InputError(f"solution: expected a (points, triangles) pair: {e}") from None
    return mesh_arrays(points, triangles, "solution")


def _solution_file(solution: Any, values: Any, array: Any, directory: str) -> tuple[str, list[str], list[str]]:
    """The solution file the core reads, the arrays to adapt to, and the file's point arrays."""
    if isinstance(solution, (str, os.PathLike)):
        path = os.fspath(solution)
        if values is not None:
            raise InputError(f"values: a solution file ({path}) brings its own point data; give values only with a "
                             "Mesh or (points, triangles)")
        if not os.path.isfile(path):
            raise InputError(f"solution: cannot read '{path}': no such file")
        return path, _names(array, None), list(_core.point_array_names(path))
    if not isinstance(solution, Mesh) and not (isinstance(solution, tuple) and len(solution) == 2):
        raise InputError("solution: expected a .vtu or .msh file with point data, a pdmesh.Mesh or a "
                         f"(points, triangles) pair of arrays, got {type(solution).__name__}")
    points, triangles = _solution_mesh(solution)
    arrays = _solution_arrays(points, values, array)
    path = os.path.join(directory, "solution.vtu")
    _metric.write_vtu(path, points, triangles, arrays)
    return path, _names(array, arrays), list(arrays)


def _text(value: Any, argument: str) -> str | None:
    return None if value is None else _settings.toml_value(value, argument)


# The point arrays the command's solution.vtu leaves out (transfer_point_arrays): a mesh's own data.
_NOT_TRANSFERRED = ("kind", "q", "node_id")


def _check_outputs(config: Any, out: str, solution: Any, label: str, transfer: bool) -> None:
    """What the command checks before it writes anything: that the run writes a mesh file for
    solution.vtu to follow, and that solution.vtu is not the solution file."""
    if not transfer:
        return
    if _core.adapt_mesh_file(config, out) is None:
        formats = ", ".join(config.formats)
        raise InputError(f"output.formats = [{formats}] writes no mesh file (msh, msh22, vtu, su2, mesh or "
                         "triangle) for solution.vtu to follow: add one, or give transfer=False")
    written = os.path.join(out, "solution.vtu")
    if isinstance(solution, (str, os.PathLike)) and os.path.exists(written) and os.path.samefile(label, written):
        raise InputError(f"solution={label} is {written}, which this run writes: give another out")


def _setup(directory: str, domain: Any, solution: Any, array: Any, *, complexity: Any, values: Any, hmin: Any,
           hmax: Any, gradation: Any, max_anisotropy: Any, norm: Any, device: str | None, seed: int | None,
           settings: Mapping[str, Any] | None, max_nodes: int | None, initial: Any, out: str, transfer: bool,
           keywords: Mapping[str, Any]) -> tuple[Mesher, Any, str]:
    """The Mesher of the adaptation (writing the command's files in ``out`` when given), its case and
    the solution file it reads (in ``directory`` for a solution in memory)."""
    if complexity is None:
        raise InputError("complexity: the metric's complexity C (> 0) is needed")
    geo = _domain(domain)
    if max_nodes is not None and int(max_nodes) < 1:
        raise InputError(f"max_nodes must be >= 1, got {max_nodes}")
    path, names, present = _solution_file(solution, values, array, directory)
    file_given = isinstance(solution, (str, os.PathLike))
    label = os.fspath(solution) if file_given else "the solution"
    for name in names:
        if name not in present:
            raise InputError(f"array={name!r}: {label} has no point array '{name}' (point arrays: "
                             f"{', '.join(present) if present else 'none'})")
    if transfer and all(name in _NOT_TRANSFERRED for name in present):
        raise InputError(f"solution: {label} has no point data to transfer (point arrays: {', '.join(present)}; "
                         f"{', '.join(_NOT_TRANSFERRED)} are a mesh's own): give transfer=False")
    keys = _core.adapt_settings(path, names, _text(complexity, "complexity"), _text(hmin, "hmin"),
                                _text(hmax, "hmax"), _text(gradation, "gradation"),
                                _text(max_anisotropy, "max_anisotropy"), _text(norm, "norm"))
    # The command's keys, in its order, labelled by the arguments that gave them; then the caller's.
    pairs = []
    for key, value, _ in keys:
        argument = _ARGUMENTS.get(key)
        if argument is None:
            shown = "pdmesh.adapt (the case's [spacing] is replaced)"
        elif argument == "solution":
            shown = f"solution={label}" if file_given else "solution"
        else:
            shown = f"{argument}={value}"
        pairs.append((key, value, shown))
    if initial is not None:
        warm = _write_initial(initial, directory)
        settings = {**(dict(settings) if settings is not None else {}), "init.file": warm}
    overrides, _ = _settings_for(None, device, seed, settings, keywords)
    config = geo._with(pairs + overrides) if isinstance(geo, Case) else geo._config(pairs + overrides)
    if config.motion["enabled"]:
        raise InputError(f"{domain}: pdmesh.adapt meshes one domain; the case has [motion]")
    if out:
        _check_outputs(config, out, solution, label, transfer)
    mesher = Mesher.__new__(Mesher)
    mesher._core = _core.Mesher(config, out, int(max_nodes or 0))
    return mesher, config, path


def adapt_mesher(domain: Any, solution: Any, array: str | Sequence[str] | None = None, *, complexity: Any,
                 values: Any = None, hmin: Any = None, hmax: Any = None, gradation: Any = None,
                 max_anisotropy: Any = None, norm: Any = None, device: str | None = None, seed: int | None = None,
                 settings: Mapping[str, Any] | None = None, max_nodes: int | None = None, initial: Any = None,
                 **keywords: Any) -> Mesher:
    """The Mesher of ``adapt()`` before it runs (its arguments less ``progress``, ``transfer`` and
    ``out``): to step or watch the re-mesh, or read its ``iteration`` and ``converged`` after
    ``run()``. Its ``triangulate()`` gives the mesh without the solution on it: ``pdmesh.transfer``
    carries it over."""
    # The core reads the solution and the warm start while it sets the run up; the files go after.
    with _metric.temporary_directory() as directory:
        mesher, _, _ = _setup(directory, domain, solution, array, complexity=complexity, values=values, hmin=hmin,
                              hmax=hmax, gradation=gradation, max_anisotropy=max_anisotropy, norm=norm,
                              device=device, seed=seed, settings=settings, max_nodes=max_nodes, initial=initial,
                              out="", transfer=False, keywords=keywords)
    return mesher


def adapt(domain: Any, solution: Any, array: str | Sequence[str] | None = None, *, complexity: Any,
          values: Any = None, hmin: Any = None, hmax: Any = None, gradation: Any = None, max_anisotropy: Any = None,
          norm: Any = None, transfer: bool = True, out: str | os.PathLike | None = None, device: str | None = None,
          seed: int | None = None, progress: Any = False, settings: Mapping[str, Any] | None = None,
          max_nodes: int | None = None, initial: Any = None, **keywords: Any) -> Mesh:
    """Re-meshes a domain in the Hessian metric of a solution and carries the solution over (the
    command ``pdmesh adapt``).

    ``domain``: what ``generate`` takes (a Geometry, rings, a Case, a case file, a case directory, a
    geometry or mesh file); its case's ``[spacing]`` is replaced, as the command replaces it, by
    ``spacing.field = "hessian"`` on the solution with the metric's keys below; its other settings stay.
    ``solution``: a .vtu or .msh file with point data, or a pdmesh.Mesh or ``(points, triangles)`` pair
    with ``values``: a dict name -> (N,) array, or one (N,) array named by ``array``.
    ``array``: the point array to adapt to, a comma-separated list of them (``"u,v"``, as ``--array
    u,v``) or a list of names (their metrics intersected); default: the keys of ``values``.
    ``complexity`` (C > 0: about 1.15 C vertices), ``hmin``, ``hmax``, ``gradation``
    (spacing.metric_gradation), ``max_anisotropy`` and ``norm`` are the command's options of those
    names. ``transfer`` (default True): the solution's point arrays (a file's all but kind, q and
    node_id; the keys of ``values``) interpolated linearly onto the new mesh's points, the values of
    the command's solution.vtu bit for bit, in the returned mesh's ``point_data`` (name -> (N,) or
    (N, k) array); False: none (``--no-transfer``). ``out``: a directory where the command's files
    are written, as ``pdmesh adapt --out DIR`` writes them (the mesh files of output.formats,
    quality.json and the rest, and solution.vtu unless transfer is False), atomically, by the same
    writers. The other arguments are ``generate``'s; settings and keywords apply after the command's
    keys, as ``--set`` does. The same inputs give the command's mesh.msh. Returns the new Mesh.
    """
    out_dir = os.fspath(out) if out is not None else ""
    with _metric.temporary_directory() as directory:
        mesher, config, path = _setup(directory, domain, solution, array, complexity=complexity, values=values,
                                      hmin=hmin, hmax=hmax, gradation=gradation, max_anisotropy=max_anisotropy,
                                      norm=norm, device=device, seed=seed, settings=settings, max_nodes=max_nodes,
                                      initial=initial, out=out_dir, transfer=bool(transfer), keywords=keywords)
        mesher.run(progress=progress)
        mesh = mesher.triangulate()
        if not transfer:
            return mesh
        if out_dir:
            # The command's solution.vtu, on the mesh file the run wrote read back; its arrays are the
            # mesh's point data.
            arrays = _core.write_adapted_solution(config, out_dir, path)
        else:
            arrays = _core.transfer_file(path, [], np.ascontiguousarray(mesh.points))
    return Mesh(mesh._core.with_point_data(arrays))
