"""Checking a triangle mesh given as arrays, for the functions that take ``(points, triangles)``."""

from __future__ import annotations

from typing import Any

import numpy as np

from .errors import InputError


def mesh_arrays(points: Any, triangles: Any, what: str) -> tuple[np.ndarray, np.ndarray]:
    """``points`` as an (N, 2) float64 array (N >= 3) and ``triangles`` as an (M, 3) integer array
    (M >= 1) of 0-based indices into them; InputError naming ``what``, the shape or the first bad
    triangle otherwise."""
    try:
        p = np.asarray(points, dtype=np.float64)
        t = np.asarray(triangles)
    except (TypeError, ValueError) as e:
        raise InputError(f"{what}: (points, triangles) must be arrays: {e}") from None
    if p.ndim != 2 or p.shape[1] != 2 or p.shape[0] < 3:
        raise InputError(f"{what}: points must be an (N, 2) array with N >= 3, got shape {p.shape}")
    if t.ndim != 2 or t.shape[1] != 3 or t.shape[0] < 1 or not np.issubdtype(t.dtype, np.integer):
        raise InputError(f"{what}: triangles must be an (M, 3) integer array with M >= 1, got shape {t.shape}")
    bad = np.flatnonzero(((t < 0) | (t >= len(p))).any(axis=1))
    if bad.size:
        k = int(bad[0])
        raise InputError(f"{what}: triangle {k} {t[k].tolist()} names a node that is not one of the {len(p)} "
                         "points")
    return p, t
