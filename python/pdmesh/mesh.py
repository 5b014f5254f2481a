"""pdmesh.Mesh: a triangle mesh as numpy arrays (no copies), its boundary edges by curve name, its
quality, the command's writers and pictures, and adapters to meshio and matplotlib."""

from __future__ import annotations

import json
import math
import os
import tempfile
from dataclasses import dataclass
from typing import Any, Literal, Sequence

import numpy as np

from . import _core
from .errors import InputError



def _suffix_formats() -> dict[str, str]:
    """Mesh formats by file suffix, from the command's writers; a suffix two formats share goes to the
    first (.msh is Gmsh 4.1, format="msh22" for 2.2)."""
    table: dict[str, str] = {}
    for name, extensions in _core.mesh_formats():
        for extension in extensions:
            table.setdefault(extension, name)
    return table


_SUFFIX_FORMATS = _suffix_formats()
_PICTURES = (".png", ".svg")
# Jupyter: SVG for meshes up to this many triangles (each is an element), PNG beyond.
_SVG_REPR_LIMIT = 20_000


def _point_arrays(pairs: Any) -> dict[str, np.ndarray]:
    """The core's [(name, (N, k) values)] as name -> read-only (N,) (one component) or (N, k) arrays."""
    out = {}
    for name, values in pairs:
        a = np.asarray(values)
        a = a[:, 0] if a.shape[1] == 1 else a
        a.flags.writeable = False
        out[str(name)] = a
    return out


@dataclass(frozen=True, eq=False, repr=False)
class PeriodicPairs:
    """One periodic curve pair of a mesh (a ``[[periodic]]`` table, or a curve link of a file's
    ``$Periodic`` section): ``nodes[k] = (image point, source point)``, point indices into
    ``Mesh.points`` with the image point the transform of the source point. ``kind`` is "translate"
    (``translate`` = (dx, dy)) or "rotate" (``center``, ``angle_deg``, counter-clockwise); for a mesh
    a run made they are the table's transform as the run applied it, for a mesh read from a file they
    are read off ``affine`` (None when the file gives no affine matrix). ``affine`` is the 4 x 4 matrix
    of ``$Periodic`` (row-major, image = affine @ (x, y, 0, 1)); ``max_mismatch`` the largest distance
    between a transformed source point and its image point (0 for pdmesh's pairs)."""

    source: str
    image: str
    nodes: np.ndarray
    kind: Literal["translate", "rotate"] | None
    translate: tuple[float, float] | None
    center: tuple[float, float] | None
    angle_deg: float | None
    affine: np.ndarray | None
    max_mismatch: float

    def __repr__(self) -> str:
        if self.kind == "translate":
            how = f"translate {self.translate}"
        elif self.kind == "rotate":
            how = f"rotate {self.angle_deg:g} deg about {self.center}"
        else:
            how = "no affine"
        return f"<pdmesh.PeriodicPairs {self.source!r} -> {self.image!r}: {len(self.nodes)} pairs, {how}>"

    @classmethod
    def _from_core(cls, d: dict[str, Any]) -> "PeriodicPairs":
        affine = d["affine"]
        transform = d["transform"]
        kind: Literal["translate", "rotate"] | None = None
        translate = center = angle = None
        if transform is None and affine is not None:
            # A file's link: the affine matrix's rotation block and translation column.
            r, t = affine[:2, :2], affine[:2, 3]
            if np.array_equal(r, np.eye(2)):
                transform = {"translate": (float(t[0]), float(t[1]))}
            else:
                # x -> R x + t is the rotation about c with (I - R) c = t.
                c = np.linalg.solve(np.eye(2) - r, t)
                transform = {"rotate": {"center": (float(c[0]), float(c[1])),
                                        "angle_deg": math.degrees(math.atan2(r[1, 0], r[0, 0]))}}
        if transform is not None and "translate" in transform:
            kind, translate = "translate", tuple(transform["translate"])
        elif transform is not None:
            kind = "rotate"
            center, angle = tuple(transform["rotate"]["center"]), float(transform["rotate"]["angle_deg"])
        return cls(source=d["source"], image=d["image"], nodes=d["nodes"], kind=kind, translate=translate,
                   center=center, angle_deg=angle, affine=affine, max_mismatch=float(d["max_mismatch"]))


class Mesh:
    """A triangle mesh. ``points`` (N, 2) float64 and ``triangles`` (M, 3) int32 (0-based,
    counter-clockwise) are read-only views of the mesh's own memory: no copy is made. A mesh with
    boundary layers (``boundary_layer=``) also has ``quads`` (K, 4) and ``triangle_layer`` (which
    triangles are layer cells); its quality is the core's, as the command's table."""

    def __init__(self, core: Any):
        self._core = core
        self._edges = None
        self._periodic: list[PeriodicPairs] | None = None
        self._point_data: dict[str, np.ndarray] | None = None

    @classmethod
    def read(cls, path: str | os.PathLike) -> "Mesh":
        """Reads a mesh file (.msh 2.2/4.1, .vtu, .su2, Medit .mesh, Triangle .ele), as ``pdmesh
        quality`` does: a layered run's quads too (``quads``; ``triangle_layer`` from the .msh file's
        "boundary_layer" group, the .vtu file's cell data or the .mesh file's reference named
        "boundary_layer", all 0 from .su2, which cannot say).

        A .vtu's point arrays (every encoding the reader takes) and a .msh's ``$NodeData`` views (2.2
        and 4.1; of several blocks of one name, the time steps of a solution, the last) come with it:
        ``q`` with one value per point is ``spacing`` (pdmesh writes its spacing field there), a
        .vtu's ``kind`` is ``kinds``, and every other array is in ``point_data`` by name, float64
        (int64 for a .vtu's integer arrays), in file order (a view that skips some nodes has NaN
        there). The other formats carry none."""
        return cls(_core.read_mesh(os.fspath(path)))

    @property
    def points(self) -> np.ndarray:
        return self._core.points

    @property
    def triangles(self) -> np.ndarray:
        return self._core.triangles

    @property
    def quads(self) -> np.ndarray:
        """(K, 4) int32 counter-clockwise quadrangles: the boundary layers' cells with
        ``elements="quads"``, or a file's quads (empty otherwise)."""
        return self._core.quads

    @property
    def triangle_layer(self) -> np.ndarray:
        """(M,) uint8 per triangle: 1 for a boundary-layer cell, 0 for the core (empty without
        boundary layers or quads)."""
        return self._core.triangle_layer

    @property
    def kinds(self) -> np.ndarray:
        """(N,) uint8 per point: 0 fixed (a critical point), 1 boundary, 2 interior. Read from a
        file: a .vtu's ``kind``, or a Medit .mesh's ``Corners`` and ``RequiredVertices`` (fixed) and
        edges (boundary); empty where the file gives neither."""
        return self._core.kinds

    @property
    def regions(self) -> np.ndarray:
        """(M,) float64 per triangle: the regional attribute of its region (a .poly's regions), empty
        without regions. ``write`` writes them (MSH physical surfaces ``region_<a>``, VTU cell data
        ``region``, the .ele attribute, Medit triangle references) and ``read`` takes them back, a
        Medit reference no comment names (mmg2d's output) as the attribute itself
        (docs/mesh-formats.md, "Regions")."""
        return self._core.regions

    @property
    def region_names(self) -> dict[float, str]:
        """The names of ``regions``' attributes that have one: a mesh file's named regions (MSH
        physical surfaces, Medit reference comments, the VTU field data ``region_names``) or the
        case's ``geometry.region_names``. ``write`` names those regions so; an attribute without a
        name is written as ``region_<a>``."""
        return dict(self._core.region_names)

    @property
    def curve_groups(self) -> dict[int, tuple[str, list[str]]]:
        """The curves' physical groups by tag: (name, curve names), from a mesh file's groups (MSH
        physical lines, the VTU field data ``curve_tags``) or kept from a mesh file used as the
        geometry. ``write`` writes each as one group with that tag (docs/mesh-formats.md, "Physical
        tags"); empty for geometry from curve files."""
        return {tag: (name, list(curves)) for tag, (name, curves) in self._core.curve_groups.items()}

    @property
    def spacing(self) -> np.ndarray:
        """(N,) float64: the spacing field q at each point, written as point data "q" (.vtu, .msh) and
        read back from it by ``read``; empty where a file has no one-component array "q"."""
        return self._core.spacing

    @property
    def point_data(self) -> dict[str, np.ndarray]:
        """Point arrays by name, (N,) or (N, k) for k components, float64 or int64 (a file's integer
        arrays, a motion step's ``node_id``), read-only: the solution
        carried over by ``pdmesh.adapt`` (its ``transfer``), a motion step's ``node_id``, a file's
        point arrays (``read``: all but ``q`` and a .vtu's ``kind``); empty otherwise. ``write``
        writes them into a .vtu as point data and into a .msh as ``$NodeData`` views (not a layered
        mesh's), which ``read`` gives back bit for bit (but for a non-finite value in a .vtu,
        written as +-1e300, as the .vtu writer writes every value VTK's reader could not take)."""
        if self._point_data is None:
            self._point_data = _point_arrays(self._core.point_data)
        return dict(self._point_data)

    @property
    def curve_names(self) -> list[str]:
        return list(self._core.curve_names)

    @property
    def boundary_edges(self) -> dict[str, np.ndarray]:
        """Boundary edges by curve name: (K, 2) int32 point indices, in curve order."""
        if self._edges is None:
            self._edges = self._core.boundary_edges()
        return self._edges

    @property
    def periodic(self) -> list[PeriodicPairs]:
        """The periodic pairs, one ``PeriodicPairs`` per ``[[periodic]]`` table in the case's order
        (the ``$Periodic`` section of the run's mesh.msh), or per curve link of a ``.msh`` file read
        with ``Mesh.read``; an empty list for a mesh without them."""
        if self._periodic is None:
            self._periodic = [PeriodicPairs._from_core(d) for d in self._core.periodic_links()]
        return list(self._periodic)

    @property
    def periodic_nodes(self) -> np.ndarray:
        """(K, 2) int32: every (image point, source point) pair of ``periodic``, table after table;
        (0, 2) for a mesh without periodic pairs (not an error)."""
        pairs = [np.asarray(p.nodes) for p in self.periodic if len(p.nodes)]
        return np.concatenate(pairs) if pairs else np.zeros((0, 2), dtype=np.int32)

    def quality(self, per_triangle: bool = True) -> dict[str, Any]:
        """The quality.json content (thesis tables 6.2-6.6 measures, histograms and spacing
        conformance edge/q), and with ``per_triangle`` a "per_triangle" dict of (M,) arrays:
        min_angle, max_angle, aspect_ratio, skewness, condition_number, min_jacobian."""
        summary = json.loads(self._core.quality_json())
        if per_triangle:
            summary["per_triangle"] = self._core.triangle_metrics()
        return summary

    def write(self, path: str | os.PathLike, format: str | None = None,
              open_boundaries: Sequence[str] = (), walls: Sequence[str] = ()) -> list[str]:
        """Writes the mesh with the command's writers, the format from the suffix (.msh Gmsh 4.1,
        .vtu, .su2, .node/.ele/.poly Triangle, .14 ADCIRC/SCHISM, .2dm SMS, .mesh Medit, .cgns CGNS;
        .png/.svg a picture) or ``format`` (msh, msh22, vtu, su2, triangle, fort14, 2dm, mesh, cgns,
        openfoam: the directory ``STEM_openfoam/constant/polyMesh`` beside ``path``). ``open_boundaries``:
        the curves fort14 writes as open boundaries (the others are land); ``walls``: the curves whose
        OpenFOAM patches are of type wall and whose CGNS boundary conditions are BCWall (a layered
        mesh's wall curves are walls too). Atomic, as the command's files. Returns the paths written."""
        path = os.fspath(path)
        suffix = os.path.splitext(path)[1].lower()
        if format is None and suffix in _PICTURES:
            self.picture(path)
            return [path]
        if format is None:
            if suffix not in _SUFFIX_FORMATS:
                known = ", ".join([*_SUFFIX_FORMATS, *_PICTURES])
                raise InputError(f"{path}: unknown mesh suffix '{suffix}' ({known}; or give format=)")
            format = _SUFFIX_FORMATS[suffix]
        names = list(self.boundary_edges)
        for key, given in (("open_boundaries", open_boundaries), ("walls", walls)):
            for name in given:
                if name not in names:
                    raise InputError(f"{key}: unknown curve '{name}' (the geometry's curves: {', '.join(names)})")
        return list(self._core.write(path, format, [str(n) for n in open_boundaries], [str(n) for n in walls]))

    def picture(self, path: str | os.PathLike, color_by: str | None = None, title: str | None = None,
                window: Sequence[float] | None = None, long_side: int = 1600) -> None:
        """Draws the mesh (the command's mesh.png/.svg): boundary edges thicker, triangles filled by
        a quality metric with ``color_by``, or by region with a legend (``color_by="region"``);
        ``window`` = (x0, y0, x1, y1) zooms."""
        if title is None:
            title = f"{self._core.name} - mesh ({len(self.triangles)} triangles)"
        self._core.picture(os.fspath(path), color_by or "none", title,
                           None if window is None else [float(v) for v in window], int(long_side))

    def to_meshio(self):
        """A meshio.Mesh (the ``io`` extra): triangles, the quads of boundary layers, and one "line"
        block per boundary curve with a cell set named after the curve; with boundary layers, cell
        data "boundary_layer" (1 for a layer cell). The Gmsh tags of the command's mesh.msh come
        along, so that ``meshio.write("m.msh", m, file_format="gmsh")`` works and keeps the curves and
        the periodic pairs: "gmsh:physical" and "gmsh:geometrical" cell data (curve c: entity and
        physical group c + 1; triangles surface 1, physical "domain"; quads surface 2, physical
        "boundary_layer"), "gmsh:dim_tags" point data (``_gmsh_dim_tags``), field_data naming the
        groups, and ``gmsh_periodic`` with the pairs of ``periodic``."""
        try:
            import meshio
        except ImportError as e:
            raise ImportError("Mesh.to_meshio needs meshio: pip install 'pdmesh[io]'") from e
        cells = [("triangle", np.asarray(self.triangles))]
        layered = len(self.triangle_layer) > 0
        if len(self.quads):
            cells.append(("quad", np.asarray(self.quads)))
        areas = len(cells)
        sets: dict[str, list[np.ndarray]] = {}
        edges = self.boundary_edges
        for name, e in edges.items():
            cells.append(("line", np.asarray(e)))
        for k, name in enumerate(edges):
            sets[name] = [np.arange(len(c[1])) if j == areas + k else np.zeros(0, dtype=int)
                          for j, c in enumerate(cells)]
        data: dict[str, list[np.ndarray]] = {}
        if layered:
            layer = [np.asarray(self.triangle_layer, dtype=np.int32)]
            if len(self.quads):
                layer.append(np.ones(len(self.quads), dtype=np.int32))
            data["boundary_layer"] = layer + [np.zeros(len(e), dtype=np.int32) for e in edges.values()]
        # The tags mesh.msh gives (io/msh_writer, io/mixed_mesh): curve c is entity c + 1 of dimension
        # 1 with physical tag c + 1, which $Periodic names; the surfaces' groups follow the curves'.
        curve_tag = {name: k + 1 for k, name in enumerate(self.curve_names)}
        ncurves = len(self.curve_names)
        entity = [1, 2][:areas] + [curve_tag[name] for name in edges]
        physical = [ncurves + 1, ncurves + 2][:areas] + [curve_tag[name] for name in edges]
        data["gmsh:physical"] = [np.full(len(c[1]), t, dtype=np.int32) for c, t in zip(cells, physical)]
        data["gmsh:geometrical"] = [np.full(len(c[1]), t, dtype=np.int32) for c, t in zip(cells, entity)]
        field = {name: np.array([tag, 1]) for name, tag in curve_tag.items()}
        field["domain"] = np.array([ncurves + 1, 2])
        if len(self.quads):
            field["boundary_layer"] = np.array([ncurves + 2, 2])
        dim_tags = self._gmsh_dim_tags(edges, curve_tag)
        periodic = [[1, (curve_tag[p.image], curve_tag[p.source]),
                     None if p.affine is None else np.asarray(p.affine, dtype=float).ravel(),
                     np.asarray(p.nodes, dtype=np.int64)] for p in self.periodic]
        return meshio.Mesh(np.asarray(self.points), cells, point_data={"gmsh:dim_tags": dim_tags}, cell_sets=sets,
                           cell_data=data, field_data=field, gmsh_periodic=periodic or None)

    def _gmsh_dim_tags(self, edges: dict[str, np.ndarray], curve_tag: dict[str, int]) -> np.ndarray:
        """(N, 2) int32 (dimension, entity) per point for meshio's msh writer, which declares in
        $Entities (with their physical groups) only the entities that hold a point: a point on a curve
        lies in that curve's entity (a corner in the later curve's; a curve left without a point then
        takes its first one), a point of a quad in surface 2, the others in surface 1."""
        dim_tags = np.tile(np.array([2, 1], dtype=np.int32), (len(self.points), 1))
        if len(self.quads):
            dim_tags[np.unique(np.asarray(self.quads)), 1] = 2
        on_curve = {name: np.unique(e) for name, e in edges.items()}
        for name, nodes in on_curve.items():
            dim_tags[nodes] = (1, curve_tag[name])
        for name, nodes in on_curve.items():
            held = (dim_tags[nodes, 0] == 1) & (dim_tags[nodes, 1] == curve_tag[name])
            if len(nodes) and not held.any():
                dim_tags[nodes[0]] = (1, curve_tag[name])
        return dim_tags

    def plot(self, ax: Any = None, color_by: str | None = None, boundary: bool = True, **triplot: Any):
        """Draws the mesh with matplotlib (the ``plot`` extra) into ``ax`` (a new one if None):
        triplot edges, boundary curves thicker in colours with a legend, or triangles filled by a
        quality metric with ``color_by``. Returns the axes."""
        try:
            import matplotlib.pyplot as plt
        except ImportError as e:
            raise ImportError("Mesh.plot needs matplotlib: pip install 'pdmesh[plot]'") from e
        if ax is None:
            _, ax = plt.subplots(figsize=(8, 8))
        x, y = self.points[:, 0], self.points[:, 1]
        if color_by:
            per_triangle = self.quality()["per_triangle"]
            if color_by not in per_triangle:
                raise InputError(f"color_by: unknown metric '{color_by}' ({', '.join(per_triangle)})")
            values = per_triangle[color_by]
            shaded = ax.tripcolor(x, y, self.triangles, facecolors=values, cmap="viridis")
            ax.figure.colorbar(shaded, ax=ax, label=color_by)
        triplot.setdefault("color", "black")
        triplot.setdefault("linewidth", 0.3)
        ax.triplot(x, y, self.triangles, **triplot)
        if boundary:
            for name, e in self.boundary_edges.items():
                seg = self.points[e]
                xs = np.column_stack([seg[:, 0, 0], seg[:, 1, 0], np.full(len(e), np.nan)]).ravel()
                ys = np.column_stack([seg[:, 0, 1], seg[:, 1, 1], np.full(len(e), np.nan)]).ravel()
                ax.plot(xs, ys, linewidth=1.5, label=name)
            if self.boundary_edges:
                ax.legend(loc="best", fontsize="small")
        ax.set_aspect("equal")
        return ax

    def _render(self, suffix: str, long_side: int) -> bytes:
        fd, path = tempfile.mkstemp(suffix=suffix)
        os.close(fd)
        try:
            self.picture(path, long_side=long_side)
            with open(path, "rb") as f:
                return f.read()
        finally:
            os.unlink(path)

    def _repr_png_(self) -> bytes:
        return self._render(".png", 800)

    def _repr_svg_(self) -> str | None:
        if len(self.triangles) > _SVG_REPR_LIMIT:
            return None  # Jupyter then shows the PNG
        return self._render(".svg", 800).decode("utf-8")

    def __repr__(self) -> str:
        quads = f", {len(self.quads)} quads" if len(self.quads) else ""
        return (f"<pdmesh.Mesh {self._core.name!r}: {len(self.points)} points, {len(self.triangles)} triangles"
                f"{quads}, curves {self.curve_names}>")
