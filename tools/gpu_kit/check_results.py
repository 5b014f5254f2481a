#!/usr/bin/env python3
"""Checks a GPU kit results file (gpu_results.json, docs/devices.md "The GPU kit") against its schema
and prints its figures. Exit 0 when it is well-formed (and, with --expect-device or
--expect-no-device, when it says what was expected), 1 otherwise with the reasons.

  check_results.py [--expect-device | --expect-no-device] [--steps LIST] gpu_results.json
"""
import argparse
import json
import sys

STEP_STATUSES = {"ok", "failed", "timeout", "skipped"}


class Problems(list):
    def need(self, cond, what):
        if not cond:
            self.append(what)
        return cond


def is_num(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def num_or_null(v):
    return v is None or is_num(v)


def check_schema(r, p):
    p.need(r.get("format") == "pdmesh-gpu-kit-results", "format is not pdmesh-gpu-kit-results")
    p.need(r.get("version") == 1, "version is not 1")
    p.need(r.get("mode") in ("gpu", "local"), "mode is neither gpu nor local")
    p.need(isinstance(r.get("complete"), bool), "complete is not a boolean")
    for key in ("wall_s", "budget_s"):
        p.need(is_num(r.get(key)), f"{key} is not a number")
    for key in ("kit", "machine", "device", "tests"):
        p.need(isinstance(r.get(key), dict), f"{key} is not an object")
    for key in ("driver_search", "nvidia_smi"):
        p.need(r.get(key) is None or isinstance(r.get(key), dict), f"{key} is neither an object nor null")
    dev = r.get("device") or {}
    p.need(dev.get("found") in (True, False, None), "device.found is not a boolean")
    p.need(dev.get("reason") is None or isinstance(dev.get("reason"), str), "device.reason is not a string")
    tests = r.get("tests") or {}
    for key in ("passed", "failed"):
        p.need(isinstance(tests.get(key), int) and tests.get(key) >= 0, f"tests.{key} is not a count")
    p.need(isinstance(tests.get("unfinished"), list), "tests.unfinished is not a list")
    for e in tests.get("executables", []):
        p.need(isinstance(e.get("name"), str) and isinstance(e.get("passed"), int) and isinstance(e.get("failed"), int),
               f"tests.executables entry {e} lacks name, passed or failed")
    for row in r.get("bench", []) if p.need(isinstance(r.get("bench"), list), "bench is not a list") else []:
        p.need(isinstance(row.get("case"), str) and isinstance(row.get("backend"), str), f"bench row {row} lacks case or backend")
        p.need(isinstance(row.get("nodes"), int), f"bench row {row.get('case')} has no node count")
        p.need(num_or_null(row.get("ms_per_iteration")), f"bench row {row.get('case')}: ms_per_iteration is not a number")
        p.need(num_or_null(row.get("device_floor_ms")), f"bench row {row.get('case')}: device_floor_ms is not a number")
    for run in r.get("whole_runs", []) if p.need(isinstance(r.get("whole_runs"), list), "whole_runs is not a list") else []:
        p.need(isinstance(run.get("case"), str), f"whole run {run} has no case")
        p.need(num_or_null(run.get("wall_s")), f"whole run {run.get('case')}: wall_s is not a number")
        phases = run.get("phases")
        p.need(isinstance(phases, dict) and all(is_num(v) for v in phases.values()),
               f"whole run {run.get('case')}: phases is not an object of numbers")
    for s in r.get("steps", []) if p.need(isinstance(r.get("steps"), list), "steps is not a list") else []:
        p.need(isinstance(s.get("name"), str) and s.get("status") in STEP_STATUSES, f"step {s} has no name or status")


def check_device_run(r, p, steps):
    p.need(r.get("complete") is True, "the run did not complete")
    dev = r["device"]
    p.need(dev.get("found") is True, f"no device: {dev.get('reason')}")
    p.need((dev.get("check") or "").startswith("ok"), f"the device check says {dev.get('check')!r}")
    for s in r["steps"]:
        p.need(s["status"] == "ok", f"step {s['name']}: {s['status']}")
    if "bench" in steps:
        p.need(len(r["bench"]) > 0, "no bench rows")
        for row in r["bench"]:
            p.need(is_num(row.get("ms_per_iteration")), f"bench {row['case']} {row['backend']}: no ms/iteration")
            if not row["backend"].startswith("host"):
                p.need(is_num(row.get("device_floor_ms")), f"bench {row['case']} {row['backend']}: no device floor")
        cases = {row["case"] for row in r["bench"] if not row["backend"].startswith("host")}
        p.need(len(cases) == 3, f"device bench rows for {sorted(cases)}, not 3 cases")
    if "tests" in steps:
        t = r["tests"]
        p.need(t["passed"] > 0 and t["failed"] == 0 and not t["unfinished"],
               f"tests: {t['passed']} passed, {t['failed']} failed, unfinished {t['unfinished']}")
    if "whole" in steps:
        p.need(len(r["whole_runs"]) == 2, f"{len(r['whole_runs'])} whole runs, not 2")
        for run in r["whole_runs"]:
            p.need(is_num(run.get("wall_s")) and run.get("phases"), f"whole run {run['case']}: no wall time or phases")


def check_no_device(r, p):
    p.need(r.get("complete") is True, "the run did not complete")
    dev = r["device"]
    p.need(dev.get("found") is False, "a device was found")
    p.need(isinstance(dev.get("reason"), str) and dev["reason"], "no reason is given")
    search = r.get("driver_search") or {}
    p.need(bool(search.get("looked_for")) and bool(search.get("library_folders")), "the search does not say what it looked for")
    p.need(search.get("chosen") is None, "the search chose a library")
    p.need(not r["bench"] and not r["whole_runs"], "figures without a device")
    for s in r["steps"]:
        if s["name"] in ("bench", "tests", "whole"):
            p.need(s["status"] == "skipped", f"step {s['name']} was not skipped")


def summary(r):
    dev = r.get("device") or {}
    smi = r.get("nvidia_smi") or {}
    print(f"mode {r.get('mode')}, complete {r.get('complete')}, {r.get('wall_s')} s of {r.get('budget_s')}")
    # The tree the kit's binaries were built from: a run's figures and test counts belong to that commit only.
    kit = r.get("kit") or {}
    print(f"kit: commit {kit.get('commit')}, uncommitted changes {kit.get('uncommitted_changes')}, built {kit.get('built')}")
    print(f"device: {dev.get('spec')} {dev.get('description') or ''} check: {dev.get('check')}; "
          f"bit-identical in double: {dev.get('bit_identical_double')}" + (f"; nvidia-smi: {smi.get('query')}" if smi else ""))
    if not dev.get("found"):
        print(f"no device: {dev.get('reason')}")
    t = r.get("tests") or {}
    print(f"tests: {t.get('passed')} passed, {t.get('failed')} failed, unfinished {t.get('unfinished')}")
    for row in r.get("bench", []):
        floor = f"device floor {row['device_floor_ms']} ms" if row.get("device_floor_ms") is not None else \
            f"CPU floor {row.get('floor_ms_scalar_vector')} ms"
        print(f"bench {row['case']:>14} {row['backend'][:48]:<48} {row['nodes']:>9} nodes {row['ms_per_iteration']} ms/iteration"
              f" ({floor}, x floor {row.get('over_floor')})")
    for run in r.get("whole_runs", []):
        top = sorted(run.get("phases", {}).items(), key=lambda kv: -kv[1])[:4]
        print(f"whole {run['case']}: {run.get('wall_s')} s ({run.get('nodes')} nodes, {run.get('iterations')} iterations); "
              + ", ".join(f"{k} {v:.2f}" for k, v in top))
    for s in r.get("steps", []):
        print(f"step {s['name']}: {s['status']} {s.get('seconds', '-')} s of {s.get('budget_s', '-')}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--expect-device", action="store_true")
    g.add_argument("--expect-no-device", action="store_true")
    ap.add_argument("--steps", default="driver,bench,tests,whole")
    ap.add_argument("results")
    a = ap.parse_args()
    try:
        with open(a.results, encoding="utf-8") as f:
            r = json.load(f)
    except (OSError, ValueError) as e:
        print(f"check_results: {a.results}: {e}", file=sys.stderr)
        return 1
    p = Problems()
    check_schema(r, p)
    if not p and a.expect_device:
        check_device_run(r, p, a.steps.split(","))
    if not p and a.expect_no_device:
        check_no_device(r, p)
    try:
        summary(r)
    except (KeyError, TypeError, AttributeError) as e:
        p.append(f"cannot summarise: {e!r}")
    for what in p:
        print(f"check_results: {a.results}: {what}", file=sys.stderr)
    return 1 if p else 0


if __name__ == "__main__":
    sys.exit(main())
