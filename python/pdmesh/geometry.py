"""pdmesh.Geometry: the boundary curves to mesh, from files, numpy rings, curves, or anything with
a ``__geo_interface__`` (shapely polygons)."""

from __future__ import annotations

import os
from typing import Any, Iterable, Mapping, Sequence

import numpy as np

from . import _core
from . import _settings
from .errors import InputError


def _region_rows(regions: Any) -> tuple[np.ndarray, list[str]]:
    """(K, 3) x, y, attribute rows and their names (empty: none) of ``regions=``: a mapping name ->
    point (attributes 1, 2, ... in its order) or rows of x, y, attribute."""
    if isinstance(regions, Mapping):
        names = [str(k) for k in regions]
        for name in names:
            reserved = name in ("domain", "boundary_layer") or name.startswith("region_")
            if not name or any(c.isspace() or c == '"' for c in name) or reserved:
                raise InputError(f"regions: '{name}' is not a plain name (no blanks or quotes; not domain, "
                                 f"boundary_layer or region_...)")
        points = _as_xy([regions[k] for k in regions] if regions else np.zeros((0, 2)), "regions")
        rows = np.column_stack([points, np.arange(1, len(points) + 1, dtype=np.float64)])
        return rows, names
    rows = np.asarray(regions, dtype=np.float64)
    if rows.ndim == 1 and rows.shape[0] == 3:
        rows = rows[None, :]  # one region
    if rows.ndim != 2 or (len(rows) and rows.shape[1] != 3):
        raise InputError(f"regions: expected a mapping name -> (x, y) or (K, 3) rows of x, y, attribute; "
                         f"got shape {rows.shape}")
    if not np.all(np.isfinite(rows)):
        raise InputError("regions: the rows hold a value that is not finite")
    if np.any(rows[:, 2] == 0):
        raise InputError("regions: attribute 0 means no region")
    return rows.reshape(-1, 3), []


def _as_xy(a: Any, what: str) -> np.ndarray:
    try:
        xy = np.ascontiguousarray(np.asarray(a, dtype=np.float64))
    except (TypeError, ValueError) as e:
        raise InputError(f"{what}: not an array of numbers ({e})") from None
    if xy.ndim != 2 or xy.shape[1] not in (2, 3):
        raise InputError(f"{what}: expected an (N, 2) array of x, y, got shape {xy.shape}")
    return np.ascontiguousarray(xy[:, :2])


class Geometry:
    """The boundary of the domain: curves that join at their ends into closed loops; the domain is
    their even-odd interior (holes need no marking).

    ``Geometry(rings, names=None)`` takes closed rings, (N, 2) arrays (a ring whose last point is
    not its first is closed for you), one curve each. ``Geometry.from_file(*paths)`` reads
    .crv/.dat/.poly/.geojson/.json/.shp files, ``Geometry.from_curves(curves)`` takes open
    polylines that join at their end points (as the curves of a .crv file), and ``Geometry.from_geo_interface(obj)`` (or passing
    a shapely Polygon/MultiPolygon to the constructor) takes the rings of a GeoJSON-like polygon.
    A GeoJSON-like dict (``{"type": "Polygon", "coordinates": [...]}``) is taken as by
    ``from_geo_interface``. ``names`` names the curves (the boundary markers of the mesh files and ``Mesh.boundary_edges``).

    Embedded constraints: ``constraints=[...]`` (in the constructor and ``from_curves``) adds
    polylines, (N, 2) arrays, open or closed, that lie inside the domain and become chains of mesh
    edges (roads, levees, cracks, material interfaces; a closed one bounds a subdomain, not a hole);
    ``points=`` an (M, 2) array of points that become mesh nodes. ``names`` then names the boundary
    curves first, then the constraints (docs/geometry-input.md, "Embedded constraints").

    Regions: ``regions={"steel": (x, y), "copper": (x, y)}`` tags the part of the domain that holds
    each point (bounded by the boundary and closed constraints) with attributes 1, 2, ... in that
    order, named by the keys; or a (K, 3) array of x, y, attribute rows without names. The mesh's
    ``regions`` and ``region_names`` give them per triangle, and the mesh files carry them
    (docs/mesh-formats.md, "Regions"). A point outside the domain or on a curve is an InputError.
    """

    def __init__(self, rings: Iterable[Any] | Any, names: Sequence[str] | None = None, *,
                 constraints: Iterable[Any] | None = None, points: Any = None, regions: Any = None):
        # A GeoJSON-like mapping ({"type": "Polygon", "coordinates": ...}) as a shapely polygon.
        if hasattr(rings, "__geo_interface__") or isinstance(rings, Mapping):
            other = Geometry.from_geo_interface(rings, names)
            self._init(other._files, other._curves, other._names, other._label)
            self._embed(constraints, points, regions)
            return
        if isinstance(rings, np.ndarray) and rings.ndim == 2:
            rings = [rings]  # one ring given as an (N, 2) array
        curves = []
        for k, ring in enumerate(rings):
            xy = _as_xy(ring, f"rings[{k}]")
            if len(xy) >= 2 and not np.array_equal(xy[0], xy[-1]):
                xy = np.vstack([xy, xy[:1]])
            curves.append(xy)
        self._init(None, curves, names, "rings")
        self._embed(constraints, points, regions)

    def _init(self, files, curves, names, label) -> None:
        self._files = files
        self._curves = curves
        self._label = label
        self._names = list(names) if names is not None else None
        self._info = None
        self._constraints: list[np.ndarray] = []
        self._points = np.zeros((0, 2))
        self._regions = np.zeros((0, 3))
        self._region_names: list[str] = []

    def _embed(self, constraints: Iterable[Any] | None, points: Any, regions: Any = None) -> None:
        if constraints is not None:
            if isinstance(constraints, np.ndarray) and constraints.ndim == 2:
                constraints = [constraints]  # one polyline given as an (N, 2) array
            self._constraints = [_as_xy(c, f"constraints[{k}]") for k, c in enumerate(constraints)]
        if points is not None:
            xy = np.asarray(points, dtype=np.float64)
            if xy.ndim == 1 and xy.shape[0] in (2, 3):
                xy = xy[None, :]  # one point
            self._points = _as_xy(xy if len(xy) else np.zeros((0, 2)), "points")
        if regions is not None:
            self._regions, self._region_names = _region_rows(regions)
        if (self._constraints or len(self._points) or len(self._regions)) and self._files is not None:
            raise InputError("constraints=, points= and regions= go with curves given in memory, not with geometry "
                             "files")

    @classmethod
    def from_file(cls, *paths: str | os.PathLike, names: Sequence[str] | None = None) -> "Geometry":
        """Curves read from .crv/.dat/.poly/.geojson/.json/.shp files, in file order (the command's
        readers); a .msh/.vtu/.su2/.mesh/.ele mesh file's cells are a domain (docs/geometry-input.md)."""
        if not paths:
            raise InputError("Geometry.from_file: no geometry file given")
        g = cls.__new__(cls)
        g._init([os.fspath(p) for p in paths], None, names, None)
        return g

    @classmethod
    def from_curves(cls, curves: Iterable[Any], names: Sequence[str] | None = None, *,
                    constraints: Iterable[Any] | None = None, points: Any = None, regions: Any = None) -> "Geometry":
        """Open polylines, (N, 2) arrays, joined where their end points coincide (like a .crv file);
        ``constraints``, ``points`` and ``regions`` as in the constructor."""
        g = cls.__new__(cls)
        g._init(None, [_as_xy(c, f"curves[{k}]") for k, c in enumerate(curves)], names, "curves")
        g._embed(constraints, points, regions)
        return g

    @classmethod
    def from_geo_interface(cls, obj: Any, names: Sequence[str] | None = None) -> "Geometry":
        """The rings of a Polygon or MultiPolygon given by ``__geo_interface__`` (shapely) or as a
        GeoJSON-like mapping: every exterior and interior ring becomes one closed curve."""
        geo = obj.__geo_interface__ if hasattr(obj, "__geo_interface__") else obj
        if isinstance(obj, Mapping) and "type" not in obj:
            raise InputError(f"a geometry dict needs a 'type' (Polygon or MultiPolygon) and its 'coordinates'; "
                             f"got the keys {sorted(map(str, obj))}")
        if not isinstance(geo, Mapping) or "type" not in geo:
            raise InputError(f"{type(obj).__name__} has no GeoJSON-like __geo_interface__")
        if geo["type"] == "Polygon":
            polygons = [geo["coordinates"]]
        elif geo["type"] == "MultiPolygon":
            polygons = list(geo["coordinates"])
        else:
            raise InputError(f"__geo_interface__ type '{geo['type']}': a Polygon or MultiPolygon is needed")
        rings = [ring for polygon in polygons for ring in polygon]
        return cls(rings, names)

    # The case the geometry makes with `settings` (dotted keys with TOML values, see _settings).
    def _config(self, settings: list[tuple[str, str, str]]):
        extra = []
        if self._names is not None:
            extra = _settings.overrides([("geometry.curve_names", list(self._names))])
        if self._files is not None:
            return _core.case_for_files(self._files, extra + settings)
        labels = [f"{self._label}[{k}]" for k in range(len(self._curves))]
        labels += [f"constraints[{k}]" for k in range(len(self._constraints))]
        flags = [0] * len(self._curves) + [1] * len(self._constraints)
        return _core.case_for_curves(self._curves + self._constraints, labels, self._label, extra + settings, flags,
                                     np.ascontiguousarray(self._points, dtype=np.float64), "points",
                                     np.ascontiguousarray(self._regions, dtype=np.float64), self._region_names)

    def _geometry(self) -> dict:
        if self._info is None:
            self._info = self._config([]).geometry()
        return self._info

    @property
    def files(self) -> list[str] | None:
        """The geometry files, when read from files."""
        return None if self._files is None else list(self._files)

    @property
    def curves(self) -> dict[str, np.ndarray]:
        """Every curve by name, (N, 2) float64, as validated (ends joined)."""
        info = self._geometry()
        return dict(zip(info["names"], info["curves"]))

    @property
    def rings(self) -> list[np.ndarray]:
        """The closed loops as (N, 2) rings (first point repeated at the end)."""
        return [loop["ring"] for loop in self._geometry()["loops"]]

    @property
    def area(self) -> float:
        """The even-odd area of the domain."""
        return float(self._geometry()["area"])

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax)."""
        return tuple(self._geometry()["extents"])

    @property
    def __geo_interface__(self) -> dict:
        """A GeoJSON-like Polygon (or MultiPolygon): outer loops counter-clockwise, holes clockwise,
        each hole in the outer loop that holds it (shapely.geometry.shape() reads it)."""
        loops = self._geometry()["loops"]
        outers = [i for i, loop in enumerate(loops) if loop["depth"] % 2 == 0]
        holes: dict[int, list[int]] = {i: [] for i in outers}
        for i, loop in enumerate(loops):
            if loop["depth"] % 2 == 1:
                parent = next((o for o in outers if loops[o]["depth"] == loop["depth"] - 1
                               and _inside(loop["ring"][0], loops[o]["ring"])), None)
                if parent is not None:
                    holes[parent].append(i)

        def oriented(i: int, ccw: bool) -> list:
            ring = loops[i]["ring"]
            if (loops[i]["signed_area"] > 0) != ccw:
                ring = ring[::-1]
            return ring.tolist()

        polygons = [[oriented(o, True)] + [oriented(h, False) for h in holes[o]] for o in outers]
        if len(polygons) == 1:
            return {"type": "Polygon", "coordinates": polygons[0]}
        return {"type": "MultiPolygon", "coordinates": polygons}

    def __repr__(self) -> str:
        if self._files is not None:
            return f"Geometry.from_file({', '.join(map(repr, self._files))})"
        return f"Geometry({len(self._curves)} {self._label})"


def _inside(p: np.ndarray, ring: np.ndarray) -> bool:
    """Even-odd point-in-ring test (a hole's vertex never lies on its parent's boundary)."""
    x, y = p
    a, b = ring[:-1], ring[1:]
    crosses = (a[:, 1] > y) != (b[:, 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xs = a[:, 0] + (y - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return bool(np.count_nonzero(crosses & (x < xs)) % 2)
