#!/usr/bin/env python3
"""Measures the Python API against the command (issue 16's "Done when"):

1. overhead: the same case (default naca0012) run N times each, alternating, as
   (a) `build/pdmesh mesh CASE --out DIR --quiet`,
   (b) `python -c "pdmesh.Case.from_toml(CASE).run(out=DIR)"` (the same stages and the same files), and
   (c) `python -c "pdmesh.Case.from_toml(CASE).run()"` (in memory: no files, no pictures);
   wall and CPU time of the whole process (interpreter start and import included), min and median;
2. sampling: a size callable sampled at about --points points in all (a uniform field on the unit
   square): the time inside the sampling calls (arrays handed over both ways, the callable, the
   checks) and the callable's own time inside them.

Run from the repository root with the venv's Python after tools/setup.sh:
    .venv/bin/python tools/bench/bench_python.py [--case cases/naca0012/case.toml] [--device host] [--repeats 5]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np


def timed(cmd: list[str]) -> tuple[float, float]:
    """(wall seconds, CPU seconds user + system) of one run of cmd; CPU time is the steadier figure
    on a shared machine."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def overhead(case: str, device: str, repeats: int, binary: str) -> None:
    out = tempfile.mkdtemp(prefix="bench_python_")
    code = ("import pdmesh; pdmesh.Case.from_toml({case!r}).run(device={device!r}{out})")
    runs = {
        "command (files)": [binary, "mesh", case, "--out", os.path.join(out, "a"), "--quiet", "--device", device],
        "Python, Case.run(out=DIR) (files)": [sys.executable, "-c", code.format(
            case=case, device=device, out=f", out={os.path.join(out, 'b')!r}")],
        "Python, Case.run() (in memory)": [sys.executable, "-c", code.format(case=case, device=device, out="")],
    }
    wall: dict[str, list[float]] = {k: [] for k in runs}
    cpu: dict[str, list[float]] = {k: [] for k in runs}
    for cmd in runs.values():  # warm-up: kernel cache, page cache
        timed(cmd)
    for _ in range(repeats):
        for name, cmd in runs.items():
            w, c = timed(cmd)
            wall[name].append(w)
            cpu[name].append(c)
    base_wall = statistics.median(wall["command (files)"])
    base_cpu = statistics.median(cpu["command (files)"])
    print(f"\n{case}, --device {device}, {repeats} runs each, alternating (load average {os.getloadavg()[0]:.2f})")
    print("| run | wall min s | wall median s | vs command | CPU min s | CPU median s | vs command |")
    print("|---|---|---|---|---|---|---|")
    for name in runs:
        w, c = wall[name], cpu[name]
        print(f"| {name} | {min(w):.3f} | {statistics.median(w):.3f} | {100 * (statistics.median(w) / base_wall - 1):+.1f} % "
              f"| {min(c):.3f} | {statistics.median(c):.3f} | {100 * (statistics.median(c) / base_cpu - 1):+.1f} % |")


def sampling(points: int) -> None:
    import pdmesh

    square = np.array([(0, 0), (1, 0), (1, 1), (0, 1)], dtype=float)
    q = 1.0 / np.sqrt(points / 2.0)  # about 2 samples per node-sized background leaf
    inside = {"seconds": 0.0, "points": 0, "calls": 0}

    def h(xy):
        start = time.perf_counter()
        result = np.full(len(xy), q) * (1.0 + 0.0 * xy[:, 0])
        inside["seconds"] += time.perf_counter() - start
        inside["points"] += len(xy)
        inside["calls"] += 1
        return result

    m = pdmesh.Mesher([square], size=h, device="host", iterations=0)
    n, sampling_seconds = m.size_points, m.timings["size"]
    print(f"\nsize callable sampled at {n:,} points in {m.size_calls} calls ({len(m.points):,} nodes): "
          f"{sampling_seconds:.3f} s in the sampling calls ({1e9 * sampling_seconds / n:.0f} ns/point, "
          f"{sampling_seconds * 1e6 / n:.3f} s per 1M points), of which the callable's own numpy work "
          f"{inside['seconds']:.3f} s; the whole initialization {m.timings['init']:.2f} s "
          f"(load average {os.getloadavg()[0]:.2f})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--case", default="cases/naca0012/case.toml")
    parser.add_argument("--device", default="host")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--binary", default="build/pdmesh")
    parser.add_argument("--points", type=int, default=1_000_000)
    parser.add_argument("--skip-overhead", action="store_true")
    args = parser.parse_args()
    if not args.skip_overhead:
        overhead(args.case, args.device, args.repeats, args.binary)
    sampling(args.points)


if __name__ == "__main__":
    main()
