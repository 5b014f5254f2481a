#!/usr/bin/env python3
"""Boundary layers on every corpus geometry: a sweep of [[boundary_layer]] settings.

For each case of cases/corpus, cases/user_corpus and the layered examples, writes a case file into
WORK (never into cases/) with one [[boundary_layer]] table on the case's walls and runs
`PDMESH mesh` on it, then tabulates exit status, error, time and the layer measures of quality.json
(docs/boundary-layers.md, "Measures"):

    python3 tools/eval/layer_sweep.py --pdmesh build/pdmesh --work /tmp/sweep [--cases gear,box]

Walls: every curve but the far field and the open boundaries (inlet, outlet, the coastline's sea
curves); closed domains (a box, a channel, a plate) put layers on all their walls. L is the body's
size (the chord for airfoils, else the domain's largest extent, in metres for lon/lat inputs).
Variants: thin (h1 1e-4 L, growth 1.2, thickness 0.02 L, triangles), thick (thickness 0.1 L),
quads (thin in quads), and on a few airfoils a metric field (metric_*: thin under the metric).
Writes WORK/sweep.csv and WORK/sweep.md.
"""
import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# Curves that are no walls: far fields and open boundaries.
OPEN = {"farfield", "far_bottom", "far_right", "far_top", "far_left", "inlet", "outlet", "sea_south", "sea_north",
        "sea_west"}
# The examples' far-field box (cases/naca0012, cases/30p30n).
OPEN_BY_CASE = {"naca0012_layers": {"bottom", "right", "top", "left"}, "30p30n_layers": {"bottom", "right", "top", "left"}}
# Body size where it is not the domain's extent (far fields given as curves).
BODY_SIZE = {"flap_airfoil": 1.0, "naca0012_layers": 1.0, "30p30n_layers": 1.0}
# Metric fields (docs/metric-fields.md, "UIUC airfoils in a far field"; the flap's slot under the
# expression metric, where its layers collide).
HESSIAN = ('field = "hessian"\nfunction = "tanh(20*(y - 0.1*x))"\ncomplexity = 4000\nhmax = 2\n')
EXPRESSION = ('field = "metric"\nh1 = "0.02 + 0.1*sqrt(x*x+y*y)"\nh2 = "0.005 + 0.05*sqrt(x*x+y*y)"\n')
METRIC = {"s1223": {"hessian": HESSIAN, "expr": EXPRESSION}, "naca0012": {"expr": EXPRESSION},
          "flap_airfoil": {"expr": EXPRESSION}}


def case_dirs():
    out = []
    for group in ("cases/corpus", "cases/user_corpus"):
        for name in sorted(os.listdir(os.path.join(ROOT, group))):
            if os.path.isfile(os.path.join(ROOT, group, name, "case.toml")):
                out.append((name, os.path.join(ROOT, group, name, "case.toml")))
    for name in ("naca0012_layers", "30p30n_layers"):
        out.append((name, os.path.join(ROOT, "examples", name, "case.toml")))
    return out


def absolute_case_text(path):
    """The case file without its [[boundary_layer]] tables and [spacing], files made absolute."""
    text = open(path).read()
    base = os.path.dirname(path)
    text = re.sub(r'files = \[(.*?)\]',
                  lambda m: 'files = [' + ', '.join(
                      '"%s"' % os.path.normpath(os.path.join(base, f.strip().strip('"')))
                      for f in m.group(1).split(',') if f.strip()) + ']',
                  text, count=1, flags=re.S)
    # Drop its own layer tables (the examples'): the sweep adds one.
    text = re.sub(r'\[\[boundary_layer\]\].*?(?=\n\[|\Z)', '', text, flags=re.S)
    return text


def curve_names(pdmesh, text, work):
    probe = os.path.join(work, "probe.toml")
    with open(probe, "w") as f:
        f.write(text + '\n[[boundary_layer]]\ncurves = ["?none"]\nfirst_height = 1e-3\nthickness = 0.01\n')
    r = subprocess.run([pdmesh, "mesh", probe, "--out", os.path.join(work, "probe_out"), "-q"],
                       capture_output=True, text=True)
    m = re.search(r"unknown curve '\?none' \((?:the geometry's curves|geometry\.curve_names): (.*)\)", r.stderr)
    if not m:
        raise RuntimeError("no curve list: " + r.stderr)
    return [n.strip() for n in m.group(1).split(",")]


def domain_extent(pdmesh, text, work):
    """Largest extent of the mesh of the case without layers (0 iterations), in metres for lon/lat."""
    probe = os.path.join(work, "extent.toml")
    with open(probe, "w") as f:
        f.write(text)
    out = os.path.join(work, "extent_out")
    subprocess.run([pdmesh, "mesh", probe, "--out", out, "-q", "--iterations", "0", "--formats", "msh"],
                   capture_output=True, text=True, check=True)
    xs, ys = [], []
    inside = False
    for line in open(os.path.join(out, "mesh.msh")):
        if line.startswith("$Nodes"):
            inside = True
            continue
        if line.startswith("$EndNodes"):
            break
        parts = line.split()
        if inside and len(parts) == 3 and any(c in line for c in ".eE"):
            xs.append(float(parts[0]))
            ys.append(float(parts[1]))
    dx, dy = max(xs) - min(xs), max(ys) - min(ys)
    if 'equirectangular' in text:
        lat = math.radians(0.5 * (max(ys) + min(ys)))
        k = 6371000.0 * math.pi / 180.0
        dx, dy = dx * k * math.cos(lat), dy * k
    return max(dx, dy)


def body_size(name, text, extent):
    if name in BODY_SIZE:
        return BODY_SIZE[name]
    m = re.search(r'\[farfield\][^\[]*size\s*=\s*([0-9.eE+-]+)', text, flags=re.S)
    if m:  # a circle of radius size x the body's extent: the domain is 2 size x that
        return extent / (2.0 * float(m.group(1)))
    return extent


def variants(name, size):
    thin = {"first_height": 1e-4 * size, "growth": 1.2, "thickness": 0.02 * size, "elements": "triangles"}
    out = [("thin", thin, None), ("thick", dict(thin, thickness=0.1 * size), None),
           ("quads", dict(thin, elements="quads"), None)]
    for key, spacing in METRIC.get(name, {}).items():
        out.append(("metric_" + key, thin, spacing))
    return out


def layer_table(walls, s):
    return ('\n[[boundary_layer]]\ncurves = [%s]\nfirst_height = %.6g\ngrowth = %g\nthickness = %.6g\n'
            'elements = "%s"\n' % (", ".join('"%s"' % w for w in walls), s["first_height"], s["growth"],
                                   s["thickness"], s["elements"]))


def with_spacing(text, spacing):
    text = re.sub(r'\n\[spacing\].*?(?=\n\[|\Z)', '', text, flags=re.S)
    return text + "\n[spacing]\n" + spacing


def run_one(pdmesh, case_path, out):
    start = time.time()
    r = subprocess.run([pdmesh, "mesh", case_path, "--out", out, "--formats", "msh"], capture_output=True, text=True)
    elapsed = time.time() - start
    row = {"rc": r.returncode, "time_s": round(elapsed, 1), "error": "", "warnings": ""}
    errors = [line for line in r.stderr.splitlines() if "error" in line]
    row["error"] = errors[-1].replace("pdmesh: error: ", "")[:300] if errors else ""
    warn = [line for line in r.stderr.splitlines() if "warning" in line.lower()]
    row["warnings"] = " | ".join(w[:160] for w in warn[:3])
    q = os.path.join(out, "quality.json")
    if r.returncode == 0 and os.path.exists(q):
        text = open(q).read()
        # Older binaries write a non-finite thickness jump as `inf`.
        data = json.loads(re.sub(r'\binf\b', 'null', text))
        bl = data.get("boundary_layer", {})
        t = bl.get("tables", [{}])[0]
        row.update({
            "inverted": t.get("inverted_cells"),
            "h1_err_pct": t.get("first_height_max_error"),
            "max_layers": t.get("max_layers"),
            "thick_min": t.get("min_thickness"), "thick_max": t.get("max_thickness"),
            "rays": t.get("rays", ""), "stop_core": t.get("rays_stopped_by_core_spacing", ""),
            "cut": t.get("rays_cut_by_collision", ""), "le1_layer": t.get("rays_with_at_most_one_layer", ""),
            "layer_max_angle": t.get("max_angle"),
            "junction_median": bl.get("junction", {}).get("median"),
            "junction_p95": bl.get("junction", {}).get("p95"),
            "junction_max": bl.get("junction", {}).get("max"),
            "core_min_angle": bl.get("core_min_angle") if bl.get("core_min_angle") is not None
            else bl.get("core_min_angle_physical"),
            "points": bl.get("points"),
        })
    return row


FIELDS = ["case", "variant", "walls", "L", "rc", "time_s", "inverted", "h1_err_pct", "max_layers", "thick_min",
          "thick_max", "rays", "stop_core", "cut", "le1_layer", "layer_max_angle", "junction_median", "junction_p95",
          "junction_max", "core_min_angle", "points", "error", "warnings"]


def fmt(v):
    if isinstance(v, float):
        return "%.4g" % v
    return "" if v is None else str(v)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pdmesh", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--cases", default="", help="comma-separated case names (default: all)")
    ap.add_argument("--variants", default="", help="comma-separated variant names (default: all)")
    ap.add_argument("--keep", action="store_true", help="keep each run's output directory")
    a = ap.parse_args()
    pdmesh = os.path.abspath(a.pdmesh)
    os.makedirs(a.work, exist_ok=True)
    only = set(filter(None, a.cases.split(",")))
    only_v = set(filter(None, a.variants.split(",")))
    rows = []
    for name, path in case_dirs():
        if only and name not in only:
            continue
        text = absolute_case_text(path)
        names = curve_names(pdmesh, text, a.work)
        walls = [n for n in names if n not in OPEN and n not in OPEN_BY_CASE.get(name, set())]
        size = body_size(name, text, domain_extent(pdmesh, text, a.work))
        for vname, s, spacing in variants(name, size):
            if only_v and vname not in only_v:
                continue
            case_text = (with_spacing(text, spacing) if spacing else text) + layer_table(walls, s)
            case_path = os.path.join(a.work, "%s_%s.toml" % (name, vname))
            with open(case_path, "w") as f:
                f.write(case_text)
            out = os.path.join(a.work, "out_%s_%s" % (name, vname))
            row = {"case": name, "variant": vname, "walls": " ".join(walls), "L": size}
            row.update(run_one(pdmesh, case_path, out))
            rows.append(row)
            print(" ".join("%s=%s" % (k, fmt(row.get(k))) for k in FIELDS if k not in ("walls", "warnings")),
                  flush=True)
            if not a.keep:
                subprocess.run(["rm", "-rf", out])
    with open(os.path.join(a.work, "sweep.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        for r in rows:
            w.writerow({k: fmt(r.get(k)) for k in FIELDS})
    cols = ["case", "variant", "rc", "time_s", "inverted", "h1_err_pct", "max_layers", "rays", "stop_core", "cut",
            "le1_layer", "layer_max_angle", "junction_median", "junction_max", "core_min_angle", "error"]
    with open(os.path.join(a.work, "sweep.md"), "w") as f:
        f.write("| " + " | ".join(cols) + " |\n|" + "---|" * len(cols) + "\n")
        for r in rows:
            f.write("| " + " | ".join(fmt(r.get(k)).replace("|", "/") for k in cols) + " |\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
