"""Anisotropic metric fields from Python (docs/metric-fields.md, "From Python").

``size=`` takes a callable ``m(xy) -> metrics`` whose result for an (N, 2) array of points is an
(N, 3) array of (m11, m12, m22) or an (N, 2, 2) array of symmetric positive-definite matrices: the
metric M(x) whose unit mesh the run makes (an edge v has length sqrt(vᵀMv) = 1). Sizes h1 along a
direction at angle a and h2 across it are ``from_sizes(h1, h2, a)``.

pdmesh samples the callable once, vectorised, at the vertices of a ``grid`` x ``grid`` triangle grid
over the geometry's bounding box (``Metric(function, grid=...)``; a plain callable gets
``DEFAULT_GRID``), checks every value, and meshes with the metric interpolated log-Euclidean on that
grid: the case keys ``spacing.field = "metric"``, ``spacing.file``, ``spacing.array = "metric"`` on
a temporary .vtu that lives only while the run reads it. The grid must resolve the metric's
variation (a layer a few grid cells wide is smoothed).

``write_vtu(path, points, triangles, point_data)`` writes a triangle mesh with point data as pdmesh
reads it: a scalar solution for ``spacing.field = "hessian"`` with ``spacing.file`` and
``spacing.array``, or a metric.
"""

from __future__ import annotations

import os
import tempfile
from typing import Any, Callable

import numpy as np

from .errors import InputError

#: Grid cells per side of the bounding box a plain metric callable is sampled on.
DEFAULT_GRID = 512
#: Relative asymmetry |m12 - m21| / (|m11| + |m22|) an (N, 2, 2) result may have (rounding).
SYMMETRY_TOLERANCE = 1e-10


class Metric:
    """A metric callable with its sampling grid: ``size=pdmesh.size.Metric(m, grid=1024)``."""

    def __init__(self, function: Callable[[np.ndarray], Any], grid: int = DEFAULT_GRID):
        if not callable(function):
            raise InputError(f"size: Metric needs a callable, got {type(function).__name__}")
        if isinstance(grid, bool) or not isinstance(grid, (int, np.integer)) or not 2 <= int(grid) <= 4096:
            raise InputError(f"size: Metric grid must be an integer in [2, 4096], got {grid!r}")
        self.function = function
        self.grid = int(grid)

    def __repr__(self) -> str:
        return f"Metric({self.function!r}, grid={self.grid})"


class MetricResult(Exception):
    """Raised by the size sampler when a plain callable turns out to return metrics: the run is then
    set up again as a metric run (pdmesh.mesher). Internal; never reaches the user."""


def is_metric_shape(shape: tuple, n: int) -> bool:
    return shape == (n, 3) or shape == (n, 2, 2)


def from_sizes(h1: Any, h2: Any, angle: Any = 0.0) -> np.ndarray:
    """(N, 3) metrics with size h1 along the direction at ``angle`` (radians from the x axis) and h2
    across it: M = R diag(1/h1², 1/h2²) Rᵀ. Arrays broadcast."""
    h1, h2, angle = np.broadcast_arrays(np.asarray(h1, float), np.asarray(h2, float), np.asarray(angle, float))
    c, s = np.cos(angle), np.sin(angle)
    l1, l2 = 1.0 / (h1 * h1), 1.0 / (h2 * h2)
    return np.stack([l1 * c * c + l2 * s * s, (l1 - l2) * c * s, l1 * s * s + l2 * c * c], axis=-1).reshape(-1, 3)


def where(xy: np.ndarray, i: int) -> str:
    return f"({float(xy[i, 0])!r}, {float(xy[i, 1])!r})"


def check_metrics(result: Any, xy: np.ndarray) -> np.ndarray:
    """The callable's result for points ``xy`` as a contiguous (N, 3) float64 array of (m11, m12,
    m22), or InputError naming the point and the value: a wrong shape, a value that is not a finite
    number, an (N, 2, 2) matrix that is not symmetric, a matrix that is not positive-definite."""
    n = len(xy)
    if result is None:
        raise InputError(f"size: the metric callable returned None; it must return ({n}, 3) or ({n}, 2, 2) metrics")
    try:
        m = np.asarray(result, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise InputError(f"size: the metric callable returned a {type(result).__name__} that is not numbers ({e})") \
            from None
    if not is_metric_shape(m.shape, n):
        raise InputError(f"size: the metric callable returned shape {m.shape} for {n} points; "
                         f"it must return ({n}, 3) (m11, m12, m22) or ({n}, 2, 2)")
    bad = ~np.isfinite(m.reshape(n, -1)).all(axis=1)
    if bad.any():
        i = int(np.argmax(bad))
        raise InputError(f"size: the metric callable returned {m[i].tolist()} at {where(xy, i)}; "
                         "every component must be a finite number")
    if m.ndim == 3:
        asym = np.abs(m[:, 0, 1] - m[:, 1, 0]) > SYMMETRY_TOLERANCE * (np.abs(m[:, 0, 0]) + np.abs(m[:, 1, 1]))
        if asym.any():
            i = int(np.argmax(asym))
            raise InputError(f"size: the metric callable returned {m[i].tolist()} at {where(xy, i)}; "
                             "a metric must be symmetric (m12 = m21)")
        m = np.stack([m[:, 0, 0], 0.5 * (m[:, 0, 1] + m[:, 1, 0]), m[:, 1, 1]], axis=1)
    # Positive-definite as the core tests it (spacing/metric.hpp's check_metric): m11 > 0 and
    # sqrt(m11) sqrt(m22) > |m12|, which no finite input overflows.
    with np.errstate(invalid="ignore"):
        spd = (m[:, 0] > 0) & (m[:, 2] > 0) & (np.sqrt(m[:, 0]) * np.sqrt(m[:, 2]) > np.abs(m[:, 1]))
    if not spd.all():
        i = int(np.argmin(spd))
        raise InputError(f"size: the metric callable returned (m11, m12, m22) = {tuple(m[i].tolist())} at "
                         f"{where(xy, i)}; a metric must be symmetric positive-definite "
                         "(m11 > 0, m11 m22 > m12²)")
    return np.ascontiguousarray(m)


def grid_mesh(extents: Any, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The (n+1)² vertices and 2n² counter-clockwise triangles of an n x n grid over extents
    (xmin, ymin, xmax, ymax), widened by half a cell on every side so that the box's edge lies inside."""
    x0, y0, x1, y1 = (float(v) for v in extents)
    dx, dy = (x1 - x0) / n, (y1 - y0) / n
    xs = np.linspace(x0 - 0.5 * dx, x1 + 0.5 * dx, n + 1)
    ys = np.linspace(y0 - 0.5 * dy, y1 + 0.5 * dy, n + 1)
    X, Y = np.meshgrid(xs, ys)
    points = np.c_[X.ravel(), Y.ravel()]
    k = (np.arange(n)[None, :] + (n + 1) * np.arange(n)[:, None]).ravel()
    triangles = np.concatenate([np.c_[k, k + 1, k + n + 2], np.c_[k, k + n + 2, k + n + 1]])
    return points, triangles


def write_vtu(path: str | os.PathLike, points: Any, triangles: Any, point_data: dict[str, Any]) -> None:
    """A VTK unstructured grid of triangles with point data (name -> (N,) or (N, k) values), in
    binary appended encoding (raw, little-endian), as pdmesh's readers take it."""
    points = np.ascontiguousarray(points, dtype=np.float64)
    triangles = np.ascontiguousarray(triangles, dtype=np.int64)
    if points.ndim != 2 or points.shape[1] != 2 or triangles.ndim != 2 or triangles.shape[1] != 3:
        raise InputError(f"write_vtu: points must be (N, 2) and triangles (M, 3), got {points.shape} and "
                         f"{triangles.shape}")
    n, m = len(points), len(triangles)
    blocks = [np.c_[points, np.zeros(n)].astype("<f8"), triangles.astype("<i8"),
              (3 * np.arange(1, m + 1)).astype("<i8"), np.full(m, 5, dtype="u1")]
    names = [("Float64", "Points", 3), ("Int64", "connectivity", 1), ("Int64", "offsets", 1), ("UInt8", "types", 1)]
    data_xml = []
    for name, values in point_data.items():
        v = np.ascontiguousarray(values, dtype="<f8")
        if v.shape[0] != n:
            raise InputError(f"write_vtu: point data '{name}' has {v.shape[0]} values for {n} points")
        blocks.append(v)
        data_xml.append((name, 1 if v.ndim == 1 else v.shape[1]))
    raw, offsets, offset = [], [], 0
    for b in blocks:
        payload = b.tobytes()
        offsets.append(offset)
        raw.append(np.uint64(len(payload)).tobytes() + payload)
        offset += 8 + len(payload)

    def array(type_, name, k, off):
        return (f'<DataArray type="{type_}" Name="{name}" NumberOfComponents="{k}" format="appended" '
                f'offset="{off}"/>')

    xml = ['<?xml version="1.0"?>',
           '<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">',
           "<UnstructuredGrid>", f'<Piece NumberOfPoints="{n}" NumberOfCells="{m}">',
           "<Points>", array(*names[0], offsets[0]), "</Points>", "<Cells>",
           array(*names[1], offsets[1]), array(*names[2], offsets[2]), array(*names[3], offsets[3]), "</Cells>",
           "<PointData>"]
    xml += [array("Float64", name, k, offsets[4 + i]) for i, (name, k) in enumerate(data_xml)]
    xml += ["</PointData>", "</Piece>", "</UnstructuredGrid>", '<AppendedData encoding="raw">']
    path = os.fspath(path)
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(("\n".join(xml) + "\n_").encode())
        for chunk in raw:
            f.write(chunk)
        f.write(b"\n</AppendedData>\n</VTKFile>\n")
    os.replace(tmp, path)


def sample_to_file(function: Callable[[np.ndarray], Any], extents: Any, grid: int, directory: str) -> dict[str, str]:
    """Samples ``function`` once on the grid over extents, checks the metrics and writes them to a
    .vtu in ``directory``; returns the case settings of that metric field."""
    points, triangles = grid_mesh(extents, grid)
    metrics = check_metrics(function(points.copy()), points)
    path = os.path.join(directory, "metric.vtu")
    write_vtu(path, points, triangles, {"metric": metrics})
    return {"spacing.field": "metric", "spacing.file": path, "spacing.array": "metric"}


def temporary_directory() -> tempfile.TemporaryDirectory:
    return tempfile.TemporaryDirectory(prefix="pdmesh-metric-")


__all__ = ["DEFAULT_GRID", "Metric", "check_metrics", "from_sizes", "grid_mesh", "write_vtu"]
