"""The device-resident run (OpenCL; PoCL's CPU device in CI) through the API: a cancel stops it at
the end of the checked iteration, once the device queue has finished, and the Mesher goes on."""

from __future__ import annotations

import numpy as np
import pytest

import pdmesh
import pdmesh.mesher


def test_device_run_cancels_and_continues(rings, monkeypatch):
    monkeypatch.setattr(pdmesh.mesher, "CHECK_INTERVAL", 0.0)
    m = pdmesh.Mesher(rings, device="opencl", iterations=40, seed=1)
    with pytest.raises(pdmesh.Cancelled):
        m.run(progress=lambda p: p.iteration < 15)
    assert m.iteration == 15
    assert m.backend.startswith("opencl:")
    assert np.isfinite(m.points).all()
    m.run()
    assert m.iteration == 40
    mesh = m.triangulate()
    assert len(mesh.triangles) > 500 and set(mesh.boundary_edges) == {"curve0", "curve1"}
