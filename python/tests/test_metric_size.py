"""Metric fields from Python: size= takes a callable returning (N, 3) or (N, 2, 2) metrics (or
pdmesh.size.Metric), sampled once on a grid, checked, and run as a metric run; bad metrics are an
InputError naming the point and the value."""

from __future__ import annotations

import numpy as np
import pytest

import pdmesh
from pdmesh import metric as pm

SQUARE = [np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])]


def layer(xy):
    """Issue 37's linear case made milder: h_x = 0.1, h_y = 0.01 + 0.2 |y - 0.5|."""
    return pm.from_sizes(0.1, 0.01 + 0.2 * np.abs(xy[:, 1] - 0.5), 0.0)


def edge_vectors(mesh):
    e = np.sort(np.concatenate([mesh.triangles[:, [0, 1]], mesh.triangles[:, [1, 2]], mesh.triangles[:, [2, 0]]]),
                axis=1)
    e = np.unique(e, axis=0)
    return mesh.points[e[:, 0]], mesh.points[e[:, 1]] - mesh.points[e[:, 0]]


def test_metric_callable_makes_a_stretched_unit_mesh():
    mesh = pdmesh.generate(SQUARE, size=layer, device="host", iterations=300, seed=1)
    start, v = edge_vectors(mesh)
    mid = start + 0.5 * v
    m = layer(mid)
    length = np.sqrt(m[:, 0] * v[:, 0] ** 2 + 2 * m[:, 1] * v[:, 0] * v[:, 1] + m[:, 2] * v[:, 1] ** 2)
    # Measured in the metric the edges are about unit long; in x and y they are not alike.
    assert 0.8 < np.median(length) < 1.25
    assert np.mean((length > 2 ** -0.5) & (length < 2 ** 0.5)) > 0.75
    near = np.abs(mid[:, 1] - 0.5) < 0.05
    assert np.median(np.abs(v[near, 0])) > 2.5 * np.median(np.abs(v[near, 1]))
    # The unit mesh's node count: about (2/sqrt3) C with C = ∫ sqrt(det M) = ∫∫ 1/(h_x h_y).
    c = 10.0 * 2 * np.log(1 + 0.2 * 0.5 / 0.01) / 0.2
    assert 0.8 < len(mesh.points) / (2 / np.sqrt(3) * c) < 1.3


def test_matrices_and_components_give_the_same_mesh():
    def matrices(xy):
        m = layer(xy)
        return np.stack([np.c_[m[:, 0], m[:, 1]], np.c_[m[:, 1], m[:, 2]]], axis=1)

    a = pdmesh.generate(SQUARE, size=layer, device="host", iterations=20, seed=3)
    b = pdmesh.generate(SQUARE, size=matrices, device="host", iterations=20, seed=3)
    c = pdmesh.generate(SQUARE, size=pdmesh.size.Metric(layer, grid=pm.DEFAULT_GRID), device="host", iterations=20,
                        seed=3)
    assert np.array_equal(a.points, b.points) and np.array_equal(a.points, c.points)


def test_metric_callable_is_sampled_once_on_its_grid():
    shapes = []

    def recorded(xy):
        shapes.append(xy.shape)
        return layer(xy)

    pdmesh.Mesher(SQUARE, size=pdmesh.size.Metric(recorded, grid=64), device="host", iterations=5)
    assert shapes == [(65 * 65, 2)]


def test_the_grid_must_resolve_the_field():
    # A band of size 0.02 in |y - 0.5| < 0.05 (size 0.1 elsewhere): a 3 x 3 grid's vertices all lie
    # outside it and miss it; a 256 x 256 grid resolves it and places the band's nodes.
    def band(xy):
        h = np.where(np.abs(xy[:, 1] - 0.5) < 0.05, 0.02, 0.1)
        return pm.from_sizes(h, h)

    coarse = pdmesh.generate(SQUARE, size=pdmesh.size.Metric(band, grid=3), device="host", iterations=0, seed=1)
    fine = pdmesh.generate(SQUARE, size=pdmesh.size.Metric(band, grid=256), device="host", iterations=0, seed=1)
    in_band = np.abs(fine.points[:, 1] - 0.5) < 0.04
    assert np.sum(in_band) > 3 * np.sum(np.abs(coarse.points[:, 1] - 0.5) < 0.04)
    assert len(fine.points) > len(coarse.points) + 150


@pytest.mark.parametrize(
    "result, message",
    [
        (lambda xy: np.tile([1.0, 2.0, 1.0], (len(xy), 1)),
         r"\(m11, m12, m22\) = \(1.0, 2.0, 1.0\) at .*positive-definite"),
        (lambda xy: np.tile([-4.0, 0.0, 1.0], (len(xy), 1)), r"\(-4.0, 0.0, 1.0\) at .*positive-definite"),
        (lambda xy: np.where(xy[:, :1] > 0.5, np.nan, 100.0) * np.array([1.0, 0.0, 1.0]),
         r"returned \[nan, nan, nan\] at \(0\.5.*finite number"),
        (lambda xy: np.tile([[100.0, 1.0], [2.0, 100.0]], (len(xy), 1, 1)),
         r"\[\[100.0, 1.0\], \[2.0, 100.0\]\].*symmetric"),
        (lambda xy: np.tile([100.0, np.inf, 100.0], (len(xy), 1)), r"\[100.0, inf, 100.0\].*finite"),
    ],
)
def test_bad_metrics_are_input_errors_naming_the_value(result, message):
    with pytest.raises(pdmesh.InputError, match=message):
        pdmesh.Mesher(SQUARE, size=result, device="host", iterations=5)


def test_bad_metric_shapes_and_grids():
    with pytest.raises(pdmesh.InputError, match=r"shape \(4225, 4\)"):
        pdmesh.Mesher(SQUARE, size=pdmesh.size.Metric(lambda xy: np.ones((len(xy), 4)), grid=64), device="host")
    with pytest.raises(pdmesh.InputError, match="returned None"):
        pdmesh.Mesher(SQUARE, size=pdmesh.size.Metric(lambda xy: None, grid=8), device="host")
    for grid in (1, 5000, 2.5, True):
        with pytest.raises(pdmesh.InputError, match="grid must be an integer"):
            pdmesh.size.Metric(layer, grid=grid)
    with pytest.raises(pdmesh.InputError, match="needs a callable"):
        pdmesh.size.Metric(3.0)


def test_from_sizes_rotates():
    m = pm.from_sizes(np.array([0.1]), np.array([0.01]), np.pi / 2)
    assert np.allclose(m, [[1e4, 0.0, 1e2]], rtol=1e-12, atol=1e-9)
    m = pm.from_sizes(1.0, 0.5, np.pi / 4)[0]
    assert np.isclose(m[0], m[2]) and np.isclose(m[0] + m[1], 1.0) and np.isclose(m[0] - m[1], 4.0)


def test_written_vtu_is_a_background_field(tmp_path):
    # write_vtu's scalar data read back by the core as a background size field: the same node count
    # as the expression it samples (the field is linear, so interpolation is exact).
    points, triangles = pm.grid_mesh((0.0, 0.0, 1.0, 1.0), 8)
    pm.write_vtu(tmp_path / "q.vtu", points, triangles, {"q": 0.05 + 0.05 * points[:, 0]})
    a = pdmesh.generate(SQUARE, size=pdmesh.size.Background.read(tmp_path / "q.vtu"), device="host", iterations=0,
                        seed=1)
    b = pdmesh.generate(SQUARE, size="0.05 + 0.05*x", device="host", iterations=0, seed=1)
    assert abs(len(a.points) - len(b.points)) <= 0.02 * len(b.points)
