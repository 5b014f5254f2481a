"""Mesher.step() keeps the simulation backend its first step set up (on OpenCL the context and the
built program): later steps upload the state again but set nothing up."""

from __future__ import annotations

import pytest

import pdmesh
from pdmesh import _core


@pytest.mark.parametrize("device", ["host", "opencl"])
def test_steps_keep_the_backend_of_the_first(rings, device):
    before = _core._backend_setups()
    m = pdmesh.Mesher(rings, device=device, iterations=30, seed=1)
    assert _core._backend_setups() == before  # the first step sets it up
    for k in range(1, 4):
        m.step(5)
        assert m.iteration == 5 * k
        assert _core._backend_setups() - before == 1
    backend = m.backend
    assert backend.startswith("opencl:") if device == "opencl" else backend == "host"
    m.run()
    assert m.iteration == 30
    assert _core._backend_setups() - before == 1
    assert m.backend == backend


def test_each_mesher_sets_up_its_own_backend(rings):
    before = _core._backend_setups()
    a = pdmesh.Mesher(rings, device="host", iterations=10, seed=1)
    b = pdmesh.Mesher(rings, device="host", iterations=10, seed=1)
    a.step(5)
    b.step(5)
    a.step(10)
    b.step(10)
    assert _core._backend_setups() - before == 2
    assert (a.points == b.points).all()
