"""``smooth()``: pdmesh as a smoother of a mesh made elsewhere (the command ``pdmesh smooth``,
docs/smoothing.md)."""

from __future__ import annotations

import os
from typing import Any, Mapping

import numpy as np

from . import _core, metric as _metric
from ._arrays import mesh_arrays
from .errors import InputError
from .mesh import Mesh
from .mesher import Case, Mesher, _settings_for
from .geometry import Geometry


def _write_msh(points: Any, triangles: Any, path: str) -> None:
    """(points, triangles) arrays as a Gmsh 2.2 ASCII file; InputError naming a wrong shape or index."""
    p, t = mesh_arrays(points, triangles, "mesh")
    with open(path, "w", encoding="ascii") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n")
        f.write(f"{len(p)}\n")
        f.writelines(f"{i + 1} {x:.17g} {y:.17g} 0\n" for i, (x, y) in enumerate(p))
        f.write(f"$EndNodes\n$Elements\n{len(t)}\n")
        f.writelines(f"{k + 1} 2 2 0 1 {a + 1} {b + 1} {c + 1}\n" for k, (a, b, c) in enumerate(t.tolist()))
        f.write("$EndElements\n")


def _mesh_file(mesh: Any, directory: str) -> tuple[str, str]:
    """The file the core reads the mesh from, and how messages name it."""
    if isinstance(mesh, (str, os.PathLike)):
        path = os.fspath(mesh)
        return path, path
    path = os.path.join(directory, "input.msh")
    if isinstance(mesh, Mesh):
        mesh.write(path)
        return path, "mesh"
    if isinstance(mesh, tuple) and len(mesh) == 2:
        _write_msh(mesh[0], mesh[1], path)
        return path, "mesh"
    raise InputError("mesh: expected a mesh file path, a pdmesh.Mesh or a (points, triangles) pair of arrays, "
                     f"got {type(mesh).__name__}")


def smooth(mesh: Any, geometry: Any = None, *, field: str = "mesh", device: str | None = None, seed: int | None = None,
           progress: Any = False, settings: Mapping[str, Any] | None = None, out: str | os.PathLike | None = None,
           max_nodes: int | None = None, **keywords: Any) -> Mesh:
    """Improves a triangle mesh made elsewhere, keeping its sizing (the command ``pdmesh smooth``).

    ``mesh``: a mesh file (.msh, .vtu, .su2, Medit .mesh, Triangle .ele/.node), a pdmesh.Mesh, or a
    ``(points, triangles)`` pair of arrays ((N, 2) floats, (M, 3) 0-based node indices).
    ``geometry``: the domain, as ``generate`` takes it (a Geometry, rings, a Case, a case or geometry
    file path); None (the default): the mesh's own cells are the domain, its boundary names the curves
    (docs/geometry-input.md, "A mesh as the geometry"). ``field``: "mesh" (the spacing is the mesh's own local edge lengths) or "case" (the
    case's field). The mesh is checked first: an inverted or zero-area triangle, a boundary node off
    the curves or a mesh of another geometry is an InputError naming the first offending element.
    The other arguments are ``generate``'s; settings apply after the smoothing defaults
    (docs/smoothing.md). Returns the smoothed Mesh, as ``generate`` does."""
    if field not in ("mesh", "case"):
        raise InputError(f"field must be 'mesh' or 'case', got {field!r}")
    by_mesh = field == "mesh"
    if isinstance(geometry, (str, os.PathLike)):
        path = os.fspath(geometry)
        if os.path.isdir(path):
            path = os.path.join(path, "case.toml")
        geometry = Case.from_toml(path) if path.lower().endswith(".toml") else Geometry.from_file(path)
    elif geometry is not None and not isinstance(geometry, (Case, Geometry)):
        geometry = Geometry(geometry)
    if max_nodes is not None and int(max_nodes) < 1:
        raise InputError(f"max_nodes must be >= 1, got {max_nodes}")
    overrides, sampler = _settings_for(None, device, seed, settings, keywords)
    pairs = [tuple(s) for s in _core.smooth_settings(by_mesh)] + overrides
    with _metric.temporary_directory() as directory:
        path, label = _mesh_file(mesh, directory)
        if geometry is None:
            geometry = Geometry.from_file(path)
        config = geometry._with(pairs) if isinstance(geometry, Case) else geometry._config(pairs)
        config = config.for_smoothing(path, label, by_mesh)
        mesher = Mesher.__new__(Mesher)
        mesher._core = _core.Mesher(config, os.fspath(out) if out is not None else "", int(max_nodes or 0))
    mesher.run(progress=progress)
    return mesher.triangulate()
