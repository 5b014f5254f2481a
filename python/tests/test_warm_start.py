"""generate(initial=points) and Mesher(initial=points): the warm start (case key init.file). The
given points that are inside and clear of the boundary and of each other are the initial interior
nodes, isotropic (by q) and in a metric (where the lattice then fills the gaps); bad arrays are an InputError naming the value."""

from __future__ import annotations

import numpy as np
import pytest

import pdmesh

SQUARE = [np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])]
INTERIOR = 2


def interior_points(mesher):
    return mesher.points[mesher.kinds == INTERIOR]


def test_the_initial_interior_nodes_are_the_given_points_that_clear():
    points = np.array([[0.5, 0.5], [0.52, 0.5], [0.3, 0.3], [1.5, 0.5], [0.5, 0.01], [0.0, 0.5]])
    mesher = pdmesh.Mesher(SQUARE, size=0.1, device="host", seed=1, initial=points)
    # (0.52, 0.5) is 0.2 q from (0.5, 0.5), (1.5, 0.5) outside, (0.5, 0.01) and (0.0, 0.5) on or next
    # to the boundary.
    assert np.array_equal(interior_points(mesher), points[[0, 2]])
    cold = pdmesh.Mesher(SQUARE, size=0.1, device="host", seed=1)
    assert len(interior_points(cold)) > 50


def test_a_warm_start_from_a_mesh_meshes_the_domain():
    first = pdmesh.generate(SQUARE, size=0.1, device="host", seed=1)
    warm = pdmesh.Mesher(SQUARE, size=0.1, device="host", seed=1, initial=first.points)
    # The previous mesh's interior points, all of them kept (they are spaced by the same q).
    before = interior_points(warm)
    assert 0.8 * (len(first.points) - 40) <= len(before) <= len(first.points)
    warm.run()
    mesh = warm.triangulate()
    p = mesh.points[mesh.triangles]
    area = 0.5 * ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                  - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1]))
    assert (area > 0).all()
    assert area.sum() == pytest.approx(1.0)


def test_a_metric_run_measures_the_clearance_in_the_metric():
    # Sizes 0.1 along x and 0.01 along y: (0.5, 0.51) is one metric unit from (0.5, 0.5), (0.52, 0.5)
    # 0.2 units, (0.5, 0.004) 0.4 units from the bottom side.
    points = np.array([[0.5, 0.5], [0.5, 0.51], [0.52, 0.5], [0.5, 0.004]])
    mesher = pdmesh.Mesher(SQUARE, device="host", seed=1, initial=points,
                           spacing={"field": "metric", "h1": "0.1", "h2": "0.01", "angle": "0"})
    interior = interior_points(mesher)
    assert np.array_equal(interior[:2], points[:2])
    # The lattice fills the rest, grown from the kept points and the boundary nodes: about the unit
    # mesh's 2C/√3 = 1155 nodes, none of them at a dropped point.
    assert 0.8 * 1155 < len(interior) < 1.2 * 1155
    assert not any((interior == p).all(axis=1).any() for p in points[2:])


@pytest.mark.parametrize("initial, message", [
    (np.zeros((4, 3)), r"initial: .*shape \(4, 3\)"),
    (np.zeros((0, 2)), r"initial: .*shape \(0, 2\)"),
    (np.array([[0.5, 0.5], [np.nan, 0.2]]), r"initial: point 1 is \(nan, 0.2\)"),
    ([["a", "b"]], r"initial: not an \(N, 2\) array"),
])
def test_bad_initial_points_are_input_errors(initial, message):
    with pytest.raises(pdmesh.InputError, match=message):
        pdmesh.generate(SQUARE, size=0.1, device="host", initial=initial)


def test_a_missing_init_file_is_an_input_error_naming_it(tmp_path):
    missing = tmp_path / "prev.nodes"
    with pytest.raises(pdmesh.InputError, match="prev.nodes"):
        pdmesh.generate(SQUARE, size=0.1, device="host", init={"file": str(missing)})
