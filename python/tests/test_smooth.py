"""pdmesh.smooth(): a mesh made elsewhere, given in memory or as a file, improved with its sizing kept
(docs/smoothing.md); refused meshes are an InputError naming the first offending element."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

import pdmesh

SQUARE = [np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])]


def square_mesh(n: int, jitter: float, seed: int = 3):
    """The unit square in n x n cells of two triangles, interior nodes moved by up to jitter cells."""
    h = 1.0 / n
    i, j = np.meshgrid(np.arange(n + 1), np.arange(n + 1))
    p = np.c_[i.ravel() * h, j.ravel() * h]
    interior = (i.ravel() % n != 0) & (j.ravel() % n != 0)
    rng = np.random.default_rng(seed)
    p[interior] += jitter * h * rng.uniform(-1.0, 1.0, (interior.sum(), 2))
    tris = []
    for b in range(n):
        for a in range(n):
            k = a + (n + 1) * b
            tris += [(k, k + 1, k + n + 2), (k, k + n + 2, k + n + 1)]
    return p, np.array(tris)


def min_angle(mesh) -> float:
    p = mesh.points[mesh.triangles]
    worst = 180.0
    for k in range(3):
        u = p[:, (k + 1) % 3] - p[:, k]
        v = p[:, (k + 2) % 3] - p[:, k]
        ang = np.degrees(np.arctan2(np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]), (u * v).sum(1)))
        worst = min(worst, float(ang.min()))
    return worst


def test_smooth_lifts_a_jittered_mesh_given_in_memory():
    points, triangles = square_mesh(16, 0.25)
    mesh = pdmesh.smooth((points, triangles), SQUARE, device="host")
    assert isinstance(mesh, pdmesh.Mesh)
    assert min_angle(mesh) >= 38.0
    assert 0.95 <= len(mesh.points) / len(points) <= 1.05


def mean_aspect_ratio(mesh) -> float:
    """The mean of R / (2 r) over the triangles (pdmesh quality's aspect ratio)."""
    p = mesh.points[mesh.triangles]
    la, lb, lc = (np.linalg.norm(p[:, (k + 1) % 3] - p[:, (k + 2) % 3], axis=1) for k in range(3))
    u, v = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    area = 0.5 * np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
    return float(np.mean(la * lb * lc * 0.5 * (la + lb + lc) / (8.0 * area * area)))


def test_smooth_keeps_a_mesh_at_the_target_and_never_makes_it_worse():
    points, triangles = square_mesh(10, 0.03)
    given = SimpleNamespace(points=points, triangles=triangles)
    assert min_angle(given) > 40.0  # at the cleanup's target: the nodes are kept and polished
    mesh = pdmesh.smooth((points, triangles), SQUARE, device="host")
    assert len(mesh.points) == len(points)
    assert len(mesh.triangles) == len(triangles)
    assert min_angle(mesh) >= min_angle(given) - 1e-9
    assert mean_aspect_ratio(mesh) <= mean_aspect_ratio(given) + 1e-12


def test_smooth_reads_a_mesh_file_and_a_mesh_object(tmp_path):
    points, triangles = square_mesh(12, 0.3)
    path = tmp_path / "input.msh"
    first = pdmesh.smooth((points, triangles), SQUARE, device="host")
    first.write(path)
    again = pdmesh.smooth(str(path), SQUARE, device="host", field="case")
    assert min_angle(again) >= 38.0
    # A pdmesh.Mesh in memory, smoothed again with its own spacing: the count stays.
    twice = pdmesh.smooth(first, SQUARE, device="host")
    assert 0.95 <= len(twice.points) / len(first.points) <= 1.05


def test_smooth_refuses_an_inverted_triangle_and_a_node_off_the_curves():
    points, triangles = square_mesh(4, 0.0)
    triangles[5] = triangles[5][[0, 2, 1]]
    triangles[9] = triangles[9][[0, 2, 1]]
    with pytest.raises(pdmesh.InputError, match=r"mesh: triangle 5 \(nodes 2 \(0.5, 0\).* is inverted"):
        pdmesh.smooth((points, triangles), SQUARE, device="host")
    points, triangles = square_mesh(8, 0.0)
    points[3, 1] = -0.05
    with pytest.raises(pdmesh.InputError, match=r"mesh: boundary node 3 \(0.375, -0.05\) lies 0.05 from"):
        pdmesh.smooth((points, triangles), SQUARE, device="host")
    with pytest.raises(pdmesh.InputError, match="field must be"):
        pdmesh.smooth((points, triangles), SQUARE, field="other")


def test_smooth_without_a_geometry_takes_the_mesh_itself_as_its_domain(tmp_path):
    points, triangles = square_mesh(12, 0.3)
    mesh = pdmesh.smooth((points, triangles), device="host")
    assert min_angle(mesh) >= 38.0
    p = mesh.points[mesh.triangles]
    u, v = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    assert abs(0.5 * float(np.sum(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])) - 1.0) < 1e-12
    path = tmp_path / "input.msh"
    mesh.write(path)
    again = pdmesh.smooth(str(path), device="host")
    assert 0.95 <= len(again.points) / len(mesh.points) <= 1.05
