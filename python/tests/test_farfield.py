"""Far field and refinement regions from Python: farfield=("circle", 20) meshes around a body with a
curve named farfield, [[refine]] tables as refine=[...] bring the edges inside to about their size, and
bad values raise the command's InputError naming the key and value."""

from __future__ import annotations

import numpy as np
import pytest

import pdmesh
from conftest import SOURCE_DIR

AIRFOIL = SOURCE_DIR / "cases" / "naca0012" / "airfoil.crv"


def test_farfield_tuple_meshes_around_the_airfoil():
    mesh = pdmesh.generate(str(AIRFOIL), farfield=("circle", 20), device="host", iterations=0)
    assert "farfield" in mesh.boundary_edges
    ring = mesh.points[mesh.boundary_edges["farfield"].ravel()]
    radius = np.hypot(ring[:, 0] - 0.5, ring[:, 1])
    assert radius.max() == pytest.approx(20.0, rel=1e-9)
    assert radius.min() >= 20.0 * (1.0 - 1e-3)


def test_farfield_too_small_is_an_input_error():
    # The error names the far field as given, once.
    given = r'^farfield=\{ shape = "circle", size = 0.3 \}: a circle far field of size 0.3 .*above 0.5037'
    with pytest.raises(pdmesh.InputError, match=given):
        pdmesh.generate(str(AIRFOIL), farfield={"shape": "circle", "size": 0.3}, device="host", iterations=0)


def test_refine_region_sets_the_size_inside(rings):
    disc = {"shape": "disc", "centre": [0.6, 0.6], "radius": 0.25, "size": 0.03}
    mesh = pdmesh.generate(rings, settings={"spacing.size": 0.12}, refine=[disc], device="host", seed=1)
    t = mesh.triangles
    edges = np.unique(np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1), axis=0)
    a, b = mesh.points[edges[:, 0]], mesh.points[edges[:, 1]]
    mid = 0.5 * (a + b)
    inside = np.hypot(mid[:, 0] - 0.6, mid[:, 1] - 0.6) < 0.2
    assert inside.sum() > 20
    assert 0.8 * 0.03 <= np.linalg.norm(b - a, axis=1)[inside].mean() <= 1.1 * 0.03


def test_bad_region_names_key_and_value(rings):
    with pytest.raises(pdmesh.InputError, match=r"refine\[0\]\.box = \[1, 0, 0, 1\]"):
        pdmesh.generate(rings, refine=[{"shape": "box", "box": [1, 0, 0, 1], "size": 0.1}], iterations=0)
