"""Running pdmesh from the evaluation tools: `pdmesh mesh` with its progress messages parsed
(node count, device, timings), `pdmesh quality --json` to measure any mesh, and
`pdmesh quality --picture` to draw one."""

import json
import os
import re
import shutil
import subprocess
import tempfile
import time

from .common import log, write_atomically


class RunError(Exception):
    """pdmesh failed; the message holds the command's status and the end of its messages."""


def run_mesh(pdmesh, arguments, out, label, reuse=False):
    """Runs `pdmesh mesh ARGUMENTS --out OUT`; returns the run record {command, out, wall_seconds,
    stderr, nodes, device, ...timings}, saved as OUT/run.json. With reuse, a record made by the
    very same command is returned without running again. Raises RunError when pdmesh fails."""
    command = [pdmesh, "mesh", *arguments, "--out", out]
    record_path = os.path.join(out, "run.json")
    if reuse and os.path.exists(record_path):
        with open(record_path) as f:
            record = json.load(f)
        if record.get("command") == command:
            log(f"{label}: reusing {out}")
            record.update(parse_pdmesh_stderr(record["stderr"]))  # the parser may have learnt more
            return record
    log(f"{label}: {' '.join(command)}")
    start = time.monotonic()
    proc = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wall = time.monotonic() - start
    if proc.returncode != 0:
        raise RunError(f"{label}: pdmesh exited with status {proc.returncode}:\n{proc.stderr[-3000:]}")
    stderr = proc.stderr.replace("\r", "\n")
    record = {"command": command, "out": out, "wall_seconds": wall, "stderr": stderr}
    record.update(parse_pdmesh_stderr(stderr))
    write_atomically(record_path, json.dumps(record, indent=1))
    return record


def measure(pdmesh, mesh, geometry):
    """`pdmesh quality MESH --geometry GEOMETRY --json`: the quality summary (docs/quality.md) with
    spacing conformance against the geometry's (or case file's) spacing field."""
    json_path = mesh + ".quality.json"
    proc = subprocess.run([pdmesh, "quality", mesh, "--geometry", geometry, "--json", json_path],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if proc.returncode != 0:
        raise RunError(f"pdmesh quality {mesh} failed:\n{proc.stderr[-2000:]}")
    with open(json_path) as f:
        return json.load(f)


def draw(pdmesh, mesh, png, window=None, color_by="min_angle", color_range=None):
    """`pdmesh quality MESH --picture PNG`: the mesh (in window x0, y0, x1, y1) filled by a metric."""
    command = [pdmesh, "quality", mesh, "--picture", png, "--color-by", color_by]
    if window is not None:
        command += ["--view", ",".join(repr(float(v)) for v in window)]
    if color_range is not None:
        command += ["--color-range", ",".join(repr(float(v)) for v in color_range)]
    proc = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if proc.returncode != 0:
        raise RunError(f"{' '.join(command)} failed:\n{proc.stderr[-2000:]}")


def supports_method(pdmesh, method, geometry):
    """Whether this pdmesh binary accepts `--method METHOD` (an unknown value exits 2 before
    anything is written). Probed with a 0-iteration run of a small geometry into a scratch
    directory, removed afterwards."""
    scratch = tempfile.mkdtemp(prefix="pdmesh-probe-")
    try:
        proc = subprocess.run([pdmesh, "mesh", geometry, "--out", scratch, "--method", method, "--iterations", "0",
                               "--formats", "msh", "--device", "host", "--quiet"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        return proc.returncode == 0
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


NUMBER = r"([0-9]+(?:\.[0-9]*)?(?:[eE][-+]?[0-9]+)?)"


def parse_pdmesh_stderr(text):
    """Pulls node count, device, precision and timings from pdmesh's progress messages. Lines
    pdmesh does not print (initialization or triangulation time) give None."""
    found = {"nodes": None, "device": None, "precision": None, "simulation_seconds": None,
             "ms_per_iteration": None, "initialization_seconds": None,
             "triangulation_seconds": None}
    m = re.search(r"^initial distribution: (\d+) nodes", text, re.M)
    if m:
        found["nodes"] = int(m.group(1))
    # "... on the host reference (double), ..." or "... on opencl:0:0 (NAME, CPU, double, device-resident), ..."
    m = re.search(r"^simulation: (?:until converged, at most )?\d+ iterations on (?:the )?(host reference|opencl:\d+:\d+)(.*)$",
                  text, re.M)
    if m:
        found["device"] = m.group(1)
        if m.group(1).startswith("opencl"):
            name = re.match(r" \((.*?), (?:CPU|GPU|accelerator|other), ", m.group(2))
            if name:
                found["device"] += f" ({name.group(1)})"
        p = re.search(r"\b(double|float)\b", m.group(2))
        found["precision"] = p.group(1) if p else None
    m = re.search(rf"^simulation: {NUMBER} s \({NUMBER} ms/iteration\)", text, re.M)
    if m:
        found["simulation_seconds"] = float(m.group(1))
        found["ms_per_iteration"] = float(m.group(2))
    # The phase summary: "timing (wall s): read 0.002, spacing 0.1, estimate 0.2, fill 0.02, ...,
    # triangulation 0.008, ...". The initialization is the spacing field, the estimate and the fill.
    m = re.search(r"^timing \(wall s\): (.*)$", text, re.M)
    if m:
        phases = {}
        for item in m.group(1).split(";")[0].split(", "):
            name, _, value = item.rpartition(" ")
            try:
                phases[name] = float(value)
            except ValueError:
                pass
        init = [phases[k] for k in ("spacing", "estimate", "fill") if k in phases]
        if init:
            found["initialization_seconds"] = sum(init)
        if "triangulation" in phases:
            found["triangulation_seconds"] = phases["triangulation"]
        return found
    for key, pattern in (("initialization_seconds",
                          rf"^(?:initialization: |initial distribution: .*?\bin ){NUMBER} s\b"),
                         ("triangulation_seconds",
                          rf"^(?:triangulation: |mesh: .*?\bin ){NUMBER} s\b")):
        m = re.search(pattern, text, re.M)
        if m:
            found[key] = float(m.group(1))
    return found
