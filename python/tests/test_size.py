"""Size fields: a vectorised callable is called with (N, 2) arrays once per sampling pass (never per
point, never during the iterations); numbers and expressions are case keys."""

from __future__ import annotations

import numpy as np
import pytest

import pdmesh


class Recorder:
    """A size callable that records the shape of every call."""

    def __init__(self):
        self.shapes = []

    def __call__(self, xy):
        self.shapes.append(xy.shape)
        assert xy.dtype == np.float64 and xy.flags.c_contiguous
        return 0.04 + 0.1 * np.abs(np.hypot(xy[:, 0], xy[:, 1]) - 0.3)


def test_callable_is_called_once_per_sampling_pass(rings):
    h = Recorder()
    m = pdmesh.Mesher(rings, size=h, device="host", iterations=30, seed=1)
    calls = len(h.shapes)
    sampled = sum(n for n, _ in h.shapes)
    assert all(len(s) == 2 and s[1] == 2 for s in h.shapes)
    assert m.size_calls == calls
    # One call per refinement level of the background quadtree: a handful, not one per sample point.
    assert 1 <= calls <= 24, f"{calls} calls for {sampled} points"
    assert sampled >= 1000
    m.run()
    m.triangulate()
    assert len(h.shapes) == calls  # nothing more during the iterations or the triangulation


def test_callable_shapes_the_mesh(rings):
    fine = pdmesh.generate(rings, size=lambda xy: np.full(len(xy), 0.05), device="host", iterations=30)
    coarse = pdmesh.generate(rings, size=0.1, device="host", iterations=30)
    # Four times the density at most; after 30 iterations (before population control's first event)
    # the counts are the structured fill's 1/4/5/9-node patterns at 1.09 x each size (the best
    # preset's spacing.relax_scale), whose steps lose more of the fine run: measured 1249 / 435 = 2.87
    # (1904 / 540 = 3.53 at relax_scale 1).
    assert len(fine.points) > 2.5 * len(coarse.points)
    edges = fine.points[fine.triangles[:, [0, 1]]]
    length = np.hypot(*(edges[:, 1] - edges[:, 0]).T)
    assert 0.035 < np.median(length) < 0.065


def test_scalar_result_and_expression(rings):
    a = pdmesh.generate(rings, size=lambda xy: 0.08, device="host", iterations=20, seed=2)
    b = pdmesh.generate(rings, size="0.08", device="host", iterations=20, seed=2)
    c = pdmesh.generate(rings, size=0.08, device="host", iterations=20, seed=2)
    assert np.array_equal(b.points, c.points)
    # The callable is sampled into the background field, so it is close to, not equal to, the expression.
    assert abs(len(a.points) - len(b.points)) <= 0.02 * len(b.points)


def test_background_mesh_field_from_a_written_mesh(rings, tmp_path):
    # A run's mesh carries its field as point data "q": read back as a background mesh it gives the
    # same field, so the same node count (within the interpolation's difference).
    first = pdmesh.generate(rings, size=lambda xy: 0.05 + 0.05 * np.abs(xy[:, 0]), device="host", iterations=30)
    assert first.spacing.shape == (len(first.points),) and first.spacing.min() > 0.04
    first.write(tmp_path / "field.vtu")
    bg = pdmesh.size.Background.read(tmp_path / "field.vtu")
    assert bg.settings() == {"spacing.field": "mesh", "spacing.file": str(tmp_path / "field.vtu"), "spacing.array": "q"}
    again = pdmesh.generate(rings, size=bg, device="host", iterations=30)
    assert abs(len(again.points) - len(first.points)) <= 0.05 * len(first.points)
    with pytest.raises(pdmesh.InputError, match="h"):
        pdmesh.generate(rings, size=pdmesh.size.Background.read(tmp_path / "field.vtu", "h"))
    with pytest.raises(pdmesh.InputError, match="missing.vtu"):
        pdmesh.generate(rings, size=pdmesh.size.Background.read(tmp_path / "missing.vtu"))
