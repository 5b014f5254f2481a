"""Long runs: progress is reported, a cancel is honoured at the next check, and SIGINT during a run
raises KeyboardInterrupt with the Mesher able to continue to the result of an uninterrupted run."""

from __future__ import annotations

import os
import signal
import threading
import time

import numpy as np
import pytest

import pdmesh
import pdmesh.mesher


def test_progress_is_reported(rings):
    seen = []
    mesh = pdmesh.generate(rings, device="host", iterations=300, progress=seen.append)
    assert len(mesh.triangles) > 0
    assert seen and all(isinstance(p, pdmesh.Progress) for p in seen)
    assert seen[-1].iteration == seen[-1].iterations == 300  # the last iteration is always reported
    assert [p.iteration for p in seen] == sorted({p.iteration for p in seen})
    assert all(p.average_force > 0 and p.dt > 0 for p in seen)


def test_progress_bar_on_stderr(rings, capsys):
    pdmesh.generate(rings, device="host", iterations=20, progress=True)
    err = capsys.readouterr().err
    assert "pdmesh: [" in err and "20/20" in err


def test_cancel_is_honoured_at_the_next_check(rings, monkeypatch, cancel_at):
    monkeypatch.setattr(pdmesh.mesher, "CHECK_INTERVAL", 0.0)  # a check after every iteration
    m = pdmesh.Mesher(rings, device="host", iterations=200, seed=1)
    stop = cancel_at(25)
    with pytest.raises(pdmesh.Cancelled) as e:
        m.run(progress=stop)
    assert e.value.mesher is m
    assert stop.seen[-1] == 25 and m.iteration == 25
    m.run()  # and it goes on
    assert m.iteration == 200


def test_exception_in_progress_stops_the_run_and_propagates(rings):
    m = pdmesh.Mesher(rings, device="host", iterations=50)

    def broken(p):
        raise RuntimeError("from the callback")

    with pytest.raises(RuntimeError, match="from the callback"):
        m.run(progress=broken)
    assert 0 < m.iteration <= 50
    m.run()
    assert m.iteration == 50


def test_sigint_raises_keyboard_interrupt_and_the_mesher_continues(rings):
    settings = dict(size=0.04, device="host", iterations=1000, seed=4)
    reference = pdmesh.Mesher(rings, **settings)
    reference.run()

    m = pdmesh.Mesher(rings, **settings)
    killers = []

    def interrupt_from_another_thread(p):
        # While the C++ run holds no GIL, a SIGINT only trips Python's flag; the run's next check
        # (PyErr_CheckSignals, 0.1 s later) turns it into KeyboardInterrupt.
        if not killers:
            killers.append(threading.Thread(target=os.kill, args=(os.getpid(), signal.SIGINT)))
            killers[0].start()

    with pytest.raises(KeyboardInterrupt):
        m.run(progress=interrupt_from_another_thread)
    killers[0].join()
    assert 0 < m.iteration < 1000, m.iteration
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # no handler of ours left behind
    m.run()
    assert m.iteration == reference.iteration  # where the uninterrupted run stopped (converged or 1000)
    assert np.array_equal(m.points, reference.points)  # bit-identical to the uninterrupted run
    assert np.array_equal(m.triangulate().triangles, reference.triangulate().triangles)


def test_iterate_yields_views_that_stay_valid(rings):
    m = pdmesh.Mesher(rings, device="host", iterations=90, seed=2)
    states = list(m.iterate(every=30))
    assert [s.iteration for s in states] == [30, 60, 90]
    assert not states[0].points.flags.writeable
    assert not np.array_equal(states[0].points, states[2].points)  # copy-on-write: old views kept
    assert np.array_equal(states[2].points, m.points)
    assert states[2].points.ctypes.data == m.points.ctypes.data  # the latest state is the run's memory
    one_go = pdmesh.Mesher(rings, device="host", iterations=90, seed=2)
    one_go.run()
    assert np.array_equal(one_go.points, m.points)  # stepping in chunks changes nothing on the host
    mid = pdmesh.Mesher(rings, device="host", iterations=90, seed=2)
    mid.step(45)
    assert len(mid.triangulate().triangles) > 0  # a mesh of the state at any point
    assert len(m.history["iteration"]) == 90


def test_a_second_step_from_another_thread_is_refused(rings, monkeypatch):
    monkeypatch.setattr(pdmesh.mesher, "CHECK_INTERVAL", 0.0)
    m = pdmesh.Mesher(rings, device="host", iterations=20, seed=3)
    refused = []

    def attempt():
        try:
            m.step(1)
        except RuntimeError as e:
            refused.append(str(e))

    def progress(p):
        if p.iteration == 5:  # the run is paused in its check: the Mesher is busy
            t = threading.Thread(target=attempt)
            t.start()
            t.join()

    m.run(progress=progress)
    assert refused == ["this Mesher is already running (in another thread)"]
    assert m.iteration == 20


def test_other_threads_run_while_the_core_works(rings):
    # Between two progress calls only C++ runs on the main thread: a Python thread can run inside
    # such a window (well away from its ends) only if the core released the GIL.
    m = pdmesh.Mesher(rings, size=0.03, device="host", iterations=1000, seed=3)
    stamps, calls, done = [], [], threading.Event()

    def tick():
        n = 0
        while not done.is_set():
            n += 1
            if n % 1000 == 0:
                stamps.append(time.perf_counter())

    def progress(p):
        start = time.perf_counter()
        calls.append((start, start))

    t = threading.Thread(target=tick)
    t.start()
    try:
        m.run(progress=progress)
    finally:
        done.set()
        t.join()
    windows = [(a[1] + 0.01, b[0] - 0.01) for a, b in zip(calls, calls[1:]) if b[0] - a[1] > 0.05]
    assert windows, "the run was too short to have two progress calls 0.05 s apart"
    assert any(lo < s < hi for lo, hi in windows for s in stamps)
