"""Embedded constraints and points given in memory: Geometry(..., constraints=, points=) meshes them
as chains of edges and nodes; one outside the domain is an InputError naming it."""

from __future__ import annotations

import numpy as np
import pytest

import pdmesh

SETTINGS = dict(device="host", seed=3)
SQUARE = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)


def test_constraints_and_points_become_edges_and_nodes():
    crack = np.array([[0.2, 0.3], [0.5, 0.4], [0.8, 0.3]])
    levee = np.array([[1.0, 0.7], [0.6, 0.7]])
    points = np.array([[0.3, 0.8], [0.8, 0.15]])
    g = pdmesh.Geometry([SQUARE], names=["square", "crack", "levee"], constraints=[crack, levee], points=points)
    mesh = pdmesh.generate(g, **SETTINGS)
    assert set(mesh.boundary_edges) == {"square", "crack", "levee"}
    for p in np.vstack([crack, levee, points]):
        assert (np.all(mesh.points == p, axis=1)).any(), p
    # The crack's edges lie on it and add up to its length: a chain from end to end.
    edges = mesh.boundary_edges["crack"]
    a, b = mesh.points[edges[:, 0]], mesh.points[edges[:, 1]]
    length = np.hypot(*(crack[1:] - crack[:-1]).T).sum()
    assert np.hypot(*(b - a).T).sum() == pytest.approx(length, rel=1e-12)
    # Triangles on both sides: the square's whole area is meshed.
    p = mesh.points[mesh.triangles]
    area = 0.5 * ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                  - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1]))
    assert area.sum() == pytest.approx(1.0, rel=1e-12)
    assert mesh.quality()["included_angle"]["min"] >= 30.0


def test_constraint_outside_is_refused():
    g = pdmesh.Geometry([SQUARE], constraints=[np.array([[0.5, 0.5], [1.5, 0.5]])])
    with pytest.raises(pdmesh.InputError, match="constraints\\[0\\].*leaves the domain"):
        pdmesh.generate(g, **SETTINGS)
    g = pdmesh.Geometry([SQUARE], points=[[2.0, 2.0]])
    with pytest.raises(pdmesh.InputError, match="points:0.*lies outside the domain"):
        pdmesh.generate(g, **SETTINGS)


def test_regions_tag_the_parts_a_closed_constraint_bounds(tmp_path):
    # A closed constraint (an inclusion) inside the square: its inside is "steel", the rest "matrix".
    inclusion = np.array([[0.3, 0.3], [0.7, 0.3], [0.7, 0.7], [0.3, 0.7], [0.3, 0.3]])
    g = pdmesh.Geometry([SQUARE], names=["square", "interface"], constraints=[inclusion],
                        regions={"matrix": (0.1, 0.1), "steel": (0.5, 0.5)})
    mesh = pdmesh.generate(g, **SETTINGS)
    assert mesh.region_names == {1.0: "matrix", 2.0: "steel"}
    centroids = mesh.points[mesh.triangles].mean(axis=1)
    inside = np.all((centroids > 0.3) & (centroids < 0.7), axis=1)
    assert inside.any() and (~inside).any()
    assert np.all(mesh.regions[inside] == 2.0) and np.all(mesh.regions[~inside] == 1.0)
    mesh.write(tmp_path / "m.msh")
    back = pdmesh.Mesh.read(tmp_path / "m.msh")
    assert sorted(back.region_names.values()) == ["matrix", "steel"]
    # Rows of x, y, attribute: regions without names.
    rows = pdmesh.generate(pdmesh.Geometry([SQUARE], constraints=[inclusion], regions=[[0.5, 0.5, 7.0]]),
                           **SETTINGS)
    assert set(rows.regions.tolist()) == {0.0, 7.0} and rows.region_names == {}


def test_a_region_sized_by_its_name(tmp_path):
    # The inclusion "steel" at a tenth of the matrix's size: its triangles small, the matrix's corners coarse.
    inclusion = np.array([[0.3, 0.3], [0.7, 0.3], [0.7, 0.7], [0.3, 0.7], [0.3, 0.3]])
    g = pdmesh.Geometry([SQUARE], constraints=[inclusion], regions={"matrix": (0.1, 0.1), "steel": (0.5, 0.5)})
    mesh = pdmesh.generate(g, settings={"spacing.size": 0.1}, refine=[{"shape": "region", "region": "steel",
                                                                       "size": 0.01}], device="host", seed=1)
    edges = np.linalg.norm(mesh.points[mesh.triangles] - mesh.points[np.roll(mesh.triangles, 1, axis=1)], axis=2)
    steel, matrix = mesh.regions == 2.0, mesh.regions == 1.0
    assert 0.007 < edges[steel].mean() < 0.013
    assert edges[matrix].max() > 0.06
    with pytest.raises(pdmesh.InputError, match=r'refine\[0\]\.region = "iron": no region of the geometry'):
        pdmesh.generate(g, refine=[{"shape": "region", "region": "iron", "size": 0.01}], iterations=0)


def test_region_points_outside_or_on_a_curve_are_refused():
    inclusion = np.array([[0.3, 0.3], [0.7, 0.3], [0.7, 0.7], [0.3, 0.7], [0.3, 0.3]])
    with pytest.raises(pdmesh.InputError, match=r"regions:0: region point \(2, 2\) lies outside the domain"):
        pdmesh.generate(pdmesh.Geometry([SQUARE], regions={"steel": (2.0, 2.0)}), **SETTINGS)
    with pytest.raises(pdmesh.InputError, match=r"regions:1: region point \(0.5, 0.3\) lies on curve"):
        pdmesh.generate(pdmesh.Geometry([SQUARE], constraints=[inclusion],
                                        regions={"a": (0.1, 0.1), "b": (0.5, 0.3)}), **SETTINGS)
    with pytest.raises(pdmesh.InputError, match="not a plain name"):
        pdmesh.Geometry([SQUARE], regions={"two words": (0.5, 0.5)})
    with pytest.raises(pdmesh.InputError, match="attribute 0"):
        pdmesh.Geometry([SQUARE], regions=[[0.5, 0.5, 0.0]])
    with pytest.raises(pdmesh.InputError, match="not with geometry files"):
        pdmesh.Geometry.from_file("a.crv")._embed(None, None, {"a": (0, 0)})
