"""Moving geometry (docs/motion.md): a case with ``[motion]`` meshed step by step, each step warm from
the previous one, with persistent node ids; and the solution transfer between two steps' meshes."""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from . import _core
from .mesh import Mesh
from .mesher import Case


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


def transfer(source: Mesh, values: Any, points: Any) -> np.ndarray:
    """Point values of ``source`` ((N,) or (N, k)) interpolated linearly at ``points`` (M, 2): in the
    triangle that holds each point, or at the nearest boundary point for a point outside the mesh
    (where the body was). The same as ``pdmesh transfer``; returns (M,) or (M, k)."""
    v = np.ascontiguousarray(values, dtype=float)
    flat = v.ndim == 1
    v2 = v.reshape(-1, 1) if flat else v
    p = np.ascontiguousarray(points, dtype=float).reshape(-1, 2)
    out = np.asarray(_core.transfer(source._core, v2, p), dtype=float).reshape(len(p), v2.shape[1])
    return out[:, 0] if flat else out
