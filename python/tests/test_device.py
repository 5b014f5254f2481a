"""The device-resident run (OpenCL; PoCL's CPU device in CI) through the API: a cancel stops it at
the end of the checked iteration, once the device queue has finished, and the Mesher goes on."""

from __future__ import annotations

import numpy as np
import pytest

import pdmesh
import pdmesh.mesher


def test_device_run_cancels_and_continues(rings, monkeypatch, cancel_at):
    monkeypatch.setattr(pdmesh.mesher, "CHECK_INTERVAL", 0.0)
    m = pdmesh.Mesher(rings, device="opencl", iterations=40, seed=1)
    stop = cancel_at(15)
    with pytest.raises(pdmesh.Cancelled) as info:
        m.run(progress=stop)
    # The device runs iterations in windows without waiting for the host (at most 32, kWindowLength in
    # host/opencl/device_window.hpp): the run stops at the end of the window holding iteration 15, with
    # the state of the iteration it stopped at, and the callable is not asked again after it said stop.
    assert stop.seen[-1] == 15
    assert 15 <= m.iteration < 15 + 32
    assert f"after iteration {m.iteration}" in str(info.value)
    assert m.backend.startswith("opencl:")
    assert np.isfinite(m.points).all()
    m.run()
    assert m.iteration == 40
    mesh = m.triangulate()
    assert len(mesh.triangles) > 500 and set(mesh.boundary_edges) == {"curve0", "curve1"}
