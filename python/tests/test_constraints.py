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
