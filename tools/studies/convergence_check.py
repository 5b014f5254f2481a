#!/usr/bin/env python3
"""Replays the convergence stopping rule (host/sim/convergence.cpp) over measurements written by
build/convergence_study, so that its options can be judged on many cases without rerunning them.

For each CSV (one run of simulation.iterations iterations, measured every few iterations) it prints
where the rule would stop and the mesh there (smallest angle, mean aspect ratio of the nodes'
triangulation, before any cleanup) against the run's last measurement, and whether that meets the
goal of docs/simulation.md ("When a run stops"): not worse than the full run's mesh by more than
0.5 degrees or 0.002.

    tools/studies/convergence_check.py RUN.csv... [--check-every 100] [--window 400] [--aspect 5e-4]
                               [--angle 0.25] [--min-iterations 400] [--grid]

--grid tries a range of options and prints, per option set, the misses and the iterations saved.
"""
import argparse
import csv
import itertools
import math
import os
import sys


def read_run(path):
    rows = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            rows.append({
                "iteration": int(r["iteration"]),
                "min_angle": float(r["min_angle"]),
                "aspect_ratio": float(r["aspect_ratio"]),
                "settled": r["settled"] == "1",
            })
    return rows


def converged_after(samples, iteration, settled, o):
    """The rule of ConvergenceMonitor::converged_after, over samples (dicts) up to `iteration`."""
    if not settled or iteration < o["min_iterations"]:
        return False
    if not samples or samples[-1]["iteration"] != iteration:
        return False
    start = iteration - o["window"]
    first_in = next((k for k, s in enumerate(samples) if s["iteration"] > start), len(samples))
    if first_in == 0 or samples[first_in - 1]["iteration"] != start:
        return False
    lo, hi, best_before, best_within = math.inf, -math.inf, -1.0, -1.0
    for k, s in enumerate(samples):
        finite = math.isfinite(s["min_angle"]) and math.isfinite(s["aspect_ratio"])
        if k >= first_in - 1:
            if not finite:
                return False
            lo = min(lo, s["aspect_ratio"])
            hi = max(hi, s["aspect_ratio"])
        if not finite:
            continue
        if k < first_in:
            best_before = max(best_before, s["min_angle"])
        else:
            best_within = max(best_within, s["min_angle"])
    return hi - lo <= o["aspect"] and best_within <= best_before + o["angle"]


def stop_of(rows, o):
    """The iteration the rule stops after (the last row's when it never does) and the row there."""
    samples = []
    last = rows[-1]["iteration"]
    for r in rows:
        if r["iteration"] % o["check_every"] != 0:
            continue
        samples.append(r)
        if r["iteration"] < last and converged_after(samples, r["iteration"], r["settled"], o):
            return r["iteration"], r
    return last, rows[-1]


def judge(rows, o):
    it, at = stop_of(rows, o)
    end = rows[-1]
    d_angle = at["min_angle"] - end["min_angle"]
    d_aspect = at["aspect_ratio"] - end["aspect_ratio"]
    ok = d_angle >= -0.5 and d_aspect <= 0.002
    return it, at, end, d_angle, d_aspect, ok


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("runs", nargs="+")
    p.add_argument("--check-every", type=int, default=100)
    p.add_argument("--window", type=int, default=400)
    p.add_argument("--aspect", type=float, default=5e-4)
    p.add_argument("--angle", type=float, default=0.25)
    p.add_argument("--min-iterations", type=int, default=400)
    p.add_argument("--grid", action="store_true")
    a = p.parse_args()
    runs = {os.path.basename(r)[:-4]: read_run(r) for r in a.runs}
    if not a.grid:
        o = dict(check_every=a.check_every, window=a.window, aspect=a.aspect, angle=a.angle,
                 min_iterations=a.min_iterations)
        print("| run | stop | min angle at stop / end | aspect ratio at stop / end | goal |")
        print("|---|---|---|---|---|")
        for name, rows in runs.items():
            it, at, end, da, dr, ok = judge(rows, o)
            print(f"| {name} | {it} | {at['min_angle']:.2f} / {end['min_angle']:.2f} ({da:+.2f}) | "
                  f"{at['aspect_ratio']:.4f} / {end['aspect_ratio']:.4f} ({dr:+.4f}) | {'met' if ok else 'MISSED'} |")
        return 0
    print("check_every window aspect angle min_it | misses | mean stop | runs stopped early")
    for ce, win, asp, ang, mi in itertools.product([50, 100], [200, 300, 400, 600], [2.5e-4, 5e-4, 1e-3, 2e-3],
                                                    [0.25, 0.5, 1.0, 2.0, 1e9], [200, 400]):
        if win % ce:
            continue
        o = dict(check_every=ce, window=win, aspect=asp, angle=ang, min_iterations=mi)
        misses, stops, early = [], [], 0
        for name, rows in runs.items():
            it, _, end, _, _, ok = judge(rows, o)
            stops.append(it)
            early += it < end["iteration"]
            if not ok:
                misses.append(name)
        print(f"{ce} {win} {asp:g} {ang:g} {mi} | {len(misses)} {','.join(misses)} | {sum(stops) / len(stops):.0f} | {early}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
