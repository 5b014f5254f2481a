"""The optional extras (tools/setup.sh --tests installs them into .venv): meshio, matplotlib, shapely."""

from __future__ import annotations

import numpy as np
import pytest

import pdmesh

SETTINGS = dict(device="host", seed=1, iterations=20)


def test_to_meshio_keeps_the_curves(rings, tmp_path):
    meshio = pytest.importorskip("meshio")
    mesh = pdmesh.generate(pdmesh.Geometry(rings, names=["outer", "hole"]), **SETTINGS)
    m = mesh.to_meshio()
    assert np.array_equal(m.points, mesh.points)
    assert m.cells[0].type == "triangle" and np.array_equal(m.cells[0].data, mesh.triangles)
    assert [c.type for c in m.cells[1:]] == ["line", "line"]
    assert set(m.cell_sets) == {"outer", "hole"}
    assert len(m.cell_sets["hole"][2]) == len(mesh.boundary_edges["hole"])
    meshio.write(tmp_path / "m.vtu", m)
    back = meshio.read(tmp_path / "m.vtu")
    assert np.allclose(back.points[:, :2], mesh.points)


def test_plot_draws_the_mesh_and_its_curves(rings, tmp_path):
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    mesh = pdmesh.generate(pdmesh.Geometry(rings, names=["outer", "hole"]), **SETTINGS)
    ax = mesh.plot(color_by="min_angle")
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["outer", "hole"]
    ax.figure.savefig(tmp_path / "plot.png")
    assert (tmp_path / "plot.png").read_bytes()[:4] == b"\x89PNG"
    with pytest.raises(pdmesh.InputError, match="unknown metric"):
        mesh.plot(color_by="angle")


def test_shapely_polygon_in_and_out():
    shapely = pytest.importorskip("shapely")
    from shapely.geometry import Point, Polygon, shape

    polygon = Polygon([(0, 0), (2, 0), (2, 1), (0, 1)], [list(Point(0.5, 0.5).buffer(0.2, 8).exterior.coords)])
    geo = pdmesh.Geometry(polygon)
    assert geo.area == pytest.approx(polygon.area, rel=1e-12)
    assert shape(geo).area == pytest.approx(polygon.area, rel=1e-12)
    mesh = pdmesh.generate(polygon, size=0.1, **SETTINGS)
    assert len(mesh.boundary_edges) == 2
    centroids = mesh.points[mesh.triangles].mean(axis=1)
    assert all(polygon.contains(Point(c)) for c in centroids[::10])
