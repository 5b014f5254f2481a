"""Shared fixtures of the pdmesh Python tests: the repository's cases, a small circle-in-square
geometry, and the `pdmesh` command (the C++ binary when ctest names it, else `python -m pdmesh`)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

SOURCE_DIR = Path(os.environ.get("PDMESH_SOURCE_DIR", Path(__file__).resolve().parents[2]))


def circle_in_square(n_side: int = 12, n_circle: int = 24, radius: float = 0.3) -> tuple[np.ndarray, np.ndarray]:
    """A square [-1, 1]^2 (counter-clockwise) and a circular hole, as open rings (no repeated point)."""
    t = np.linspace(-1.0, 1.0, n_side + 1)[:-1]
    square = np.concatenate([np.c_[t, -np.ones_like(t)], np.c_[np.ones_like(t), t],
                             np.c_[-t, np.ones_like(t)], np.c_[-np.ones_like(t), -t]])
    a = np.linspace(0.0, 2.0 * np.pi, n_circle, endpoint=False)
    circle = radius * np.c_[np.cos(a), np.sin(a)]
    return square, circle


def write_crv(path: Path, rings) -> Path:
    """The rings as a .crv file, each closed (first point repeated), with 17 significant digits."""
    lines = []
    for ring in rings:
        closed = np.vstack([ring, ring[:1]])
        lines.append(str(len(closed)))
        lines += [f"{x:.17g} {y:.17g}" for x, y in closed]
    path.write_text("\n".join(lines) + "\n")
    return path


def read_nodes(path: Path) -> np.ndarray:
    """The positions of a node file (docs/node-file.md), exactly."""
    lines = [ln for ln in path.read_text().splitlines()[1:] if ln.strip() and not ln.startswith("#")]
    n = int(lines[0])
    return np.array([[float(v) for v in ln.split()[:2]] for ln in lines[1:1 + n]])


class CancelAt:
    """A progress callable that records the iterations it was shown and cancels at iteration `k`."""

    def __init__(self, k: int):
        self.k = k
        self.seen: list[int] = []

    def __call__(self, p) -> bool:
        self.seen.append(p.iteration)
        return p.iteration < self.k


@pytest.fixture
def cancel_at():
    return CancelAt


@pytest.fixture
def rings():
    return circle_in_square()


@pytest.fixture
def command():
    """Runs the pdmesh command line; returns the CompletedProcess (text)."""
    binary = os.environ.get("PDMESH_BINARY")
    prefix = [binary] if binary and Path(binary).exists() else [sys.executable, "-m", "pdmesh"]

    def run(*args, check=True):
        r = subprocess.run([*prefix, *map(str, args)], capture_output=True, text=True)
        if check and r.returncode != 0:
            raise AssertionError(f"pdmesh {' '.join(map(str, args))} exited {r.returncode}:\n{r.stderr}")
        return r

    return run
