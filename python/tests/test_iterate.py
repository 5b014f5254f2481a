"""A run the stopping rule ends early: iterate() ends, the progress bar's last line says where the run
ended, and the README's example runs to its end. Also Geometry's documented dict form and a size
callable that returns None."""

from __future__ import annotations

import itertools
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import pdmesh
from conftest import SOURCE_DIR


def converging_mesher(rings, **keywords):
    """A run that converges long before its iteration limit (the best preset stops when settled)."""
    return pdmesh.Mesher(rings, device="host", seed=1, iterations=5000, **keywords)


def test_iterate_ends_once_the_run_has_converged(rings):
    m = converging_mesher(rings)
    # At most 5000 / 200 = 25 steps are possible; before the fix the loop never ended.
    states = list(itertools.islice(m.iterate(every=200), 100))
    assert len(states) < 100
    assert m.converged
    assert states[-1].iteration == m.iteration < m.iterations
    assert [s.iteration for s in states] == sorted({s.iteration for s in states})
    assert list(m.iterate(every=200)) == []  # nothing left to do
    m.run()  # and run() stays where it is
    assert m.iteration == states[-1].iteration


def test_progress_last_report_is_where_a_converged_run_ended(rings, capsys):
    seen = []
    m = converging_mesher(rings)
    m.run(progress=seen.append)
    assert m.converged
    assert seen[-1].converged and seen[-1].iteration == m.iteration and seen[-1].iterations == 5000
    assert not any(p.converged for p in seen[:-1])
    m2 = converging_mesher(rings)
    m2.run(progress=True)
    lines = [ln for ln in re.split(r"[\r\n]", capsys.readouterr().err) if ln.startswith("pdmesh: [")]
    assert lines and lines[-1].split("] ")[1].startswith(f"{m2.iteration}/5000 converged")


def test_readme_example_runs_to_its_end(tmp_path):
    readme = (SOURCE_DIR / "README.md").read_text()
    block = next(b for b in re.findall(r"```python\n(.*?)```", readme, re.S) if "m.iterate(" in b)
    (tmp_path / "cases").symlink_to(SOURCE_DIR / "cases")
    script = tmp_path / "example.py"
    script.write_text(block + "\nprint('README example: end', m.iteration, m.converged)\n")
    r = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True, timeout=1200)
    assert r.returncode == 0, r.stderr[-2000:]
    assert "README example: end" in r.stdout
    # One line per step of 200, then the end: never the same iteration twice.
    steps = [int(ln.split()[0]) for ln in r.stdout.splitlines() if re.match(r"^\d+ \S+$", ln)]
    assert steps and len(steps) == len(set(steps))


def test_geometry_from_a_geojson_dict(rings):
    square, circle = rings
    ring = lambda a: np.vstack([a, a[:1]]).tolist()
    g = pdmesh.Geometry({"type": "Polygon", "coordinates": [ring(square), ring(circle)]})
    assert g.area == pytest.approx(pdmesh.Geometry([square, circle]).area)
    multi = pdmesh.Geometry({"type": "MultiPolygon", "coordinates": [[ring(square)]]})
    assert multi.area == pytest.approx(4.0)
    with pytest.raises(pdmesh.InputError, match="type"):
        pdmesh.Geometry({"coordinates": []})


def test_size_callable_returning_none_is_named(rings):
    with pytest.raises(pdmesh.InputError, match=r"returned None \(NoneType\)"):
        pdmesh.Mesher(rings, lambda xy: None, device="host", iterations=1)
    with pytest.raises(pdmesh.InputError, match=r"None \(NoneType\)"):
        pdmesh.Mesher(rings, lambda xy: [None] * len(xy), device="host", iterations=1)
