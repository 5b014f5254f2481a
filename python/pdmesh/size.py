"""Size fields (the desired node spacing q): a number, an expression, a vectorised callable, or data.

``generate(geo, size=...)`` and ``Mesher(geo, size=...)`` accept:

- ``None``: the case's field (by default thesis eq. 3.6, from the boundary segment lengths);
- a number: a uniform size;
- a string: a muParser expression in ``x`` and ``y`` (the case key ``spacing.expression``);
- a callable ``h(xy) -> sizes``: called with an (N, 2) float64 array, returning N sizes. It is called
  vectorised, once per sampling pass, while pdmesh samples it into its own background field
  (an adaptive quadtree); it is never called per point nor during the iterations;
- ``Background.read(path, array)``: sizes from data, a triangle mesh with a point-data array;
- a callable returning (N, 3) (m11, m12, m22) or (N, 2, 2) metrics, or ``Metric(callable, grid)``:
  an anisotropic metric field (pdmesh.metric).
"""

from __future__ import annotations

import numbers
import os
from typing import Any, Callable

import numpy as np

from .errors import InputError
from .metric import Metric, MetricResult, from_sizes, is_metric_shape, write_vtu


class Background:
    """Sizes read from a background mesh: a .vtu or .msh triangle mesh with a point-data scalar
    (default "q", what pdmesh writes into its own mesh files), interpolated linearly in the triangle
    that holds each point (the case keys ``spacing.field = "mesh"``, ``spacing.file``,
    ``spacing.array``; docs/spacing.md, "Spacing from data")."""

    def __init__(self, path: str | os.PathLike, array: str = "q"):
        self.path = os.path.abspath(os.fspath(path))
        self.array = str(array)

    @classmethod
    def read(cls, path: str | os.PathLike, array: str = "q") -> "Background":
        """The field of array ``array`` in mesh file ``path`` (read and checked when the run starts)."""
        return cls(path, array)

    def settings(self) -> dict[str, Any]:
        return {"spacing.field": "mesh", "spacing.file": self.path, "spacing.array": self.array}

    def __repr__(self) -> str:
        return f"Background.read({self.path!r}, {self.array!r})"


def sampler(function: Callable[[np.ndarray], Any]) -> Callable[[np.ndarray], np.ndarray]:
    """Wraps a user's size callable: one call per batch, the result as N contiguous float64 values
    (a scalar result means the same size everywhere). The core checks the values themselves."""

    def sample(xy: np.ndarray) -> np.ndarray:
        result = function(xy)
        # numpy turns None (and None inside a list) into nan: name what came back instead.
        if result is None:
            raise InputError("size: the callable returned None (NoneType); it must return the size at each point "
                             f"({len(xy)} numbers) or one number for all")
        raw = np.asarray(result)
        if raw.dtype == object:
            numbers_only = [isinstance(v, numbers.Real) and not isinstance(v, bool) for v in raw.reshape(-1)]
            if not all(numbers_only):
                bad = raw.reshape(-1)[numbers_only.index(False)]
                raise InputError(f"size: the callable returned {bad!r} ({type(bad).__name__}) among its sizes; "
                                 "each size must be a number")
        try:
            h = np.asarray(result, dtype=np.float64)
        except (TypeError, ValueError) as e:
            raise InputError(f"size: the callable returned a {type(result).__name__} that is not numbers ({e})") from None
        if h.ndim == 0:
            return np.full(len(xy), float(h))
        if is_metric_shape(h.shape, len(xy)):
            raise MetricResult()  # a metric callable: the run is set up again as a metric run
        if h.shape != (len(xy),):
            h = h.reshape(-1) if h.size == len(xy) else h
            if h.shape != (len(xy),):
                raise InputError(f"size: the callable returned shape {h.shape} for {len(xy)} points; "
                                 f"it must return one size per point, shape ({len(xy)},)")
        return np.ascontiguousarray(h)

    sample.function = function  # type: ignore[attr-defined]
    return sample


def resolve(size: Any) -> tuple[dict[str, Any], Callable | None]:
    """(case settings, sampler or None) for a ``size`` argument."""
    if size is None:
        return {}, None
    if isinstance(size, Background):
        return size.settings(), None
    if isinstance(size, Metric):
        return {}, size
    if isinstance(size, bool):
        raise InputError(f"size: {size!r} is not a size")
    if isinstance(size, numbers.Real):
        value = float(size)
        if not (np.isfinite(value) and value > 0):
            raise InputError(f"size: a size must be finite and > 0, got {value!r}")
        return {"spacing.expression": repr(value)}, None
    if isinstance(size, str):
        return {"spacing.expression": size}, None
    if callable(size):
        return {}, sampler(size)
    raise InputError(f"size: expected a number, an expression, a callable or a Background, got {type(size).__name__}")


__all__ = ["Background", "Metric", "from_sizes", "resolve", "sampler", "write_vtu"]
