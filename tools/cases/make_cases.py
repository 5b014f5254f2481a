#!/usr/bin/env python3
"""Generates every case directory under cases/ (geometry .crv files and case.toml) from the thesis'
descriptions (Fackler, chapters 6 and 7); `--estimate` prints each case's hexagonal-packing node estimate.

Standard library only. The output is deterministic: running it twice writes byte-identical files.
"""
import argparse
import math
import os
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
THIRTY_P_THIRTY_N_SOURCE = "/work/shared/data/30p30n/2010_30p30n_thik_te_18inches.crv.dat"

# Parameters chosen with --estimate so that the hexagonal-packing estimates land near the thesis'
# final node counts (Table 6.1); see docs/cases.md.
NACA_SEGMENTS_PER_SURFACE = 108     # upper and lower surface each
NACA_COSINE_WEIGHT = 0.85           # 1 = pure cosine spacing in x, 0 = uniform in x
NACA_FARFIELD_SEGMENTS = 26         # per side of the 30 x 30 square
P30N_FARFIELD_SEGMENTS = 10         # per side of the 20 x 20 square (90 would give ~320k nodes)
# 30P30N blunt trailing edges: points kept of the file's (5, 5, 9): one main TE segment (3.7e-4),
# two flap TE segments (2.9e-3, beside 3.1e-3), one slat TE segment (1.7e-3, beside 1.4e-3 and 2.2e-3).
P30N_TE_POINTS = {"main_te": 2, "flap_te": 3, "slat_te": 2}
P30N_TE_GROWTH = 1.2                # segment growth away from the main element's TE

ROD_PITCH = 1.26                    # PWR-like 17x17 assembly pitch (cm)
ROD_DIAMETER = 0.95                 # PWR fuel rod outer diameter (cm)

# Names of the 11 blocks of the HLPW-4 30P30N file, in file order (see its README table).
P30N_CURVE_NAMES = ["main_cove", "main_cove_wall", "main_lower", "main_upper", "main_te",
                    "flap_lower", "flap_upper", "flap_te",
                    "slat_te", "slat_cove", "slat_upper"]


# ----------------------------------------------------------------------------------------------
# Curve construction. Joints are made exact by passing the very same end-point tuples on.

def clean(v):
    """Returns v without a negative zero, so that '%.17g' never writes '-0'."""
    return v + 0.0


def line(p0, p1, segments):
    """Uniformly spaced points from p0 to p1, with both end points exactly p0 and p1."""
    pts = [p0]
    for k in range(1, segments):
        t = k / segments
        pts.append((clean(p0[0] + (p1[0] - p0[0]) * t), clean(p0[1] + (p1[1] - p0[1]) * t)))
    pts.append(p1)
    return pts


def square_sides(cx, cy, side, segments):
    """Four side curves (bottom, right, top, left) of an axis-aligned square, sharing exact corners."""
    h = side / 2
    c00, c10 = (clean(cx - h), clean(cy - h)), (clean(cx + h), clean(cy - h))
    c11, c01 = (clean(cx + h), clean(cy + h)), (clean(cx - h), clean(cy + h))
    return [("bottom", line(c00, c10, segments)), ("right", line(c10, c11, segments)),
            ("top", line(c11, c01, segments)), ("left", line(c01, c00, segments))]


def semicircles(radius, points, prefix):
    """Upper (angle 0 to pi) and lower (pi to 2 pi) semicircles of `points` equally spaced points each.

    The lower one mirrors the upper one, so the joints at angles 0 and pi are exactly shared."""
    n = points - 1
    upper = [(radius, 0.0)]
    for k in range(1, n):
        a = math.pi * k / n
        upper.append((clean(radius * math.cos(a)), clean(radius * math.sin(a))))
    upper.append((-radius, 0.0))
    lower = [(x, clean(-y)) for (x, y) in reversed(upper)]
    lower[0], lower[-1] = upper[-1], upper[0]
    return [(prefix + "_upper", upper), (prefix + "_lower", lower)]


def circle_loop(cx, cy, radius, segments):
    """Closed polygon of `segments` equal segments; the last point repeats the first exactly."""
    pts = []
    for k in range(segments):
        a = 2 * math.pi * k / segments
        pts.append((clean(cx + radius * math.cos(a)), clean(cy + radius * math.sin(a))))
    pts.append(pts[0])
    return pts


def naca0012_half_thickness(x):
    """NACA 4-digit thickness with the closed trailing edge coefficient -0.1036 (t = 0.12)."""
    return 5 * 0.12 * (0.2969 * math.sqrt(x) - 0.1260 * x - 0.3516 * x ** 2
                       + 0.2843 * x ** 3 - 0.1036 * x ** 4)


def naca0012_surfaces(segments, cosine_weight):
    """Upper surface LE -> TE and lower surface TE -> LE, clustered at both edges by cosine spacing."""
    xs = [0.0]
    for k in range(1, segments):
        t = k / segments
        xs.append((1 - cosine_weight) * t + cosine_weight * 0.5 * (1 - math.cos(math.pi * t)))
    xs.append(1.0)
    le, te = (0.0, 0.0), (1.0, 0.0)
    upper = [le] + [(x, naca0012_half_thickness(x)) for x in xs[1:-1]] + [te]
    lower = [te] + [(x, clean(-naca0012_half_thickness(x))) for x in reversed(xs[1:-1])] + [le]
    return [("upper", upper), ("lower", lower)]


def read_point_blocks(path):
    """Reads a point-count block file (`N` then N lines `x y [z]`) into a list of point lists."""
    with open(path) as f:
        tokens = [line.split() for line in f if line.strip()]
    blocks, i = [], 0
    while i < len(tokens):
        n = int(tokens[i][0])
        blocks.append([(float(t[0]), float(t[1])) for t in tokens[i + 1:i + 1 + n]])
        i += 1 + n
    return blocks


def arc_lengths(pts):
    s = [0.0]
    for a, b in zip(pts, pts[1:]):
        s.append(s[-1] + math.hypot(b[0] - a[0], b[1] - a[1]))
    return s


def point_at(pts, s_of, s):
    """The point at arc length s on the polyline pts (linear interpolation on its segments)."""
    k = max(0, min(len(pts) - 2, next((i for i in range(1, len(pts)) if s_of[i] >= s), len(pts) - 1) - 1))
    t = (s - s_of[k]) / (s_of[k + 1] - s_of[k])
    a, b = pts[k], pts[k + 1]
    return (clean(a[0] + t * (b[0] - a[0])), clean(a[1] + t * (b[1] - a[1])))


def grade_end(pts, first_step, growth):
    """Re-spaces the end of a uniformly spaced polyline so that its segments grow geometrically
    (factor `growth`) from `first_step` at the last point up to the polyline's own spacing.

    The last k original segments (k = the graded run's length in original segments, rounded) are
    replaced by the graded run scaled to fit them exactly; the new points lie on the original
    polyline, every other original vertex and both end points are kept bit for bit."""
    s_of = arc_lengths(pts)
    h = s_of[-1] / (len(pts) - 1)
    steps = []
    while first_step * growth ** len(steps) < h:
        steps.append(first_step * growth ** len(steps))
    k = max(1, round(sum(steps) / h))
    zone_start = s_of[-1 - k]
    scale = (s_of[-1] - zone_start) / sum(steps)
    graded, s = [], s_of[-1]
    for step in steps[:-1]:
        s -= step * scale
        graded.append(point_at(pts, s_of, s))
    return pts[:len(pts) - k] + list(reversed(graded)) + [pts[-1]]


def thirty_p_thirty_n_curves():
    """The 11 HLPW-4 blocks scaled from inches to unit stowed chord (1/18), joints made identical,
    with the blunt trailing edges re-spaced (P30N_TE_POINTS, grade_end; docs/cases.md)."""
    blocks = read_point_blocks(THIRTY_P_THIRTY_N_SOURCE)
    if len(blocks) != 11:
        sys.exit(f"{THIRTY_P_THIRTY_N_SOURCE}: expected 11 blocks, found {len(blocks)}")
    scaled = [[(clean(x / 18.0), clean(y / 18.0)) for (x, y) in b] for b in blocks]
    # Loops main 1-5, flap 6-8, slat 9-11 (0-based below); each block's last point starts the next.
    for loop in ([0, 1, 2, 3, 4], [5, 6, 7], [8, 9, 10]):
        for a, b in zip(loop, loop[1:] + loop[:1]):
            if blocks[a][-1] != blocks[b][0]:
                sys.exit(f"30P30N blocks {a + 1} and {b + 1} do not join: "
                         f"{blocks[a][-1]} vs {blocks[b][0]}")
            scaled[b][0] = scaled[a][-1]
    curves = dict(zip(P30N_CURVE_NAMES, scaled))
    # Trailing edges: keep only every k-th of the file's points (original vertices, ends kept), so
    # each TE segment is about as long as its neighbours' (the file's 9e-5 main TE segments beside
    # 2e-3 surface segments made 1-degree slivers).
    for name, keep in P30N_TE_POINTS.items():
        pts = curves[name]
        step = (len(pts) - 1) // (keep - 1)
        curves[name] = pts[::step]
        assert len(curves[name]) == keep and curves[name][-1] == pts[-1]
    # The main element's TE (one segment of 3.7e-4) is still 6x and 15x shorter than the upper
    # surface and cove segments beside it: grade those from the TE.
    te = curves["main_te"]
    te_length = math.hypot(te[1][0] - te[0][0], te[1][1] - te[0][1])
    curves["main_upper"] = grade_end(curves["main_upper"], te_length * P30N_TE_GROWTH, P30N_TE_GROWTH)
    curves["main_cove"] = list(reversed(grade_end(list(reversed(curves["main_cove"])),
                                                  te_length * P30N_TE_GROWTH, P30N_TE_GROWTH)))
    return [(name, curves[name]) for name in P30N_CURVE_NAMES]


# ----------------------------------------------------------------------------------------------
# Cases.

def views(*items):
    return list(items)


def build_cases():
    """Returns [(case name, {file name: [(curve name, points)]}, toml fields)] in a fixed order."""
    cases = []
    circles = semicircles(10.0, 31, "outer") + semicircles(0.5, 31, "inner")
    cases.append(("circle_circle", {"circles.crv": circles}, dict(
        dt={"structured": 0.01, "random": 0.025}, method="structured",
        views=views(("inner_circle", [-1.0, -1.0, 1.0, 1.0]),
                    ("upper_right_quadrant", [0.0, 0.0, 5.0, 5.0])))))

    cases.append(("naca0012", {
        "airfoil.crv": naca0012_surfaces(NACA_SEGMENTS_PER_SURFACE, NACA_COSINE_WEIGHT),
        "farfield.crv": square_sides(0.5, 0.0, 30.0, NACA_FARFIELD_SEGMENTS)}, dict(
        dt=0.009, method="structured",
        views=views(("airfoil", [-0.1, -0.35, 1.1, 0.35]),
                    ("leading_edge", [-0.02, -0.05, 0.08, 0.05]),
                    ("trailing_edge", [0.92, -0.05, 1.02, 0.05]),
                    ("midway", [-1.0, -1.0, 2.0, 1.0])))))

    p30n = thirty_p_thirty_n_curves()
    xs = [p[0] for _, pts in p30n for p in pts]
    ys = [p[1] for _, pts in p30n for p in pts]
    cx = round((min(xs) + max(xs)) / 2 * 20) / 20
    cy = round((min(ys) + max(ys)) / 2 * 20) / 20
    cases.append(("30p30n", {
        "airfoil.crv": p30n,
        "farfield.crv": square_sides(cx, cy, 20.0, P30N_FARFIELD_SEGMENTS)}, dict(
        dt=0.009, method="structured",
        views=views(("airfoil", [-0.15, -0.45, 1.2, 0.25]),
                    ("slat_main_gap", [-0.02, -0.06, 0.08, 0.04]),
                    ("main_flap_gap", [0.82, -0.04, 0.92, 0.06]),
                    ("leading_edge", [-0.12, -0.15, 0.08, 0.05]),
                    ("trailing_edge", [1.06, -0.2, 1.16, -0.1])))))

    for name, rod_segments, side_segments, dt in (
            ("rods_coarse", 20, 40, {"structured": 0.0025, "random": 0.005}),
            ("rods_fine", 60, 130, 0.02)):
        rods = []
        for i in range(5):          # row, from the bottom
            for j in range(5):      # column, from the left
                rods.append((f"rod_{i + 1}_{j + 1}", circle_loop(
                    clean((j - 2) * ROD_PITCH), clean((i - 2) * ROD_PITCH), ROD_DIAMETER / 2,
                    rod_segments)))
        cases.append((name, {"rods.crv": rods,
                             "box.crv": square_sides(0.0, 0.0, 5 * ROD_PITCH, side_segments)}, dict(
            dt=dt, method="structured",
            views=views(("one_rod", [-0.8, -0.8, 0.8, 0.8]),
                        ("upper_left_corner", [-3.25, 1.75, -1.75, 3.25])))))

    square = square_sides(0.0, 0.0, 200.0, 10)
    cases.append(("square200", {"square.crv": square}, dict(dt=None, method="structured", views=[])))
    cases.append(("shock", {"square.crv": square}, dict(
        dt=None, method="random", expression="0.5 + 19.5*tanh(x/16)^2",
        views=views(("bottom_boundary", [-40.0, -105.0, 40.0, -65.0]),
                    ("top_boundary", [-40.0, 65.0, 40.0, 105.0])))))
    return cases


# ----------------------------------------------------------------------------------------------
# Writing.

def crv_text(curves):
    out = []
    for _, pts in curves:
        out.append(f"{len(pts)}\n")
        out.extend("%.17g %.17g\n" % p for p in pts)
    return "".join(out)


def toml_number(v):
    return repr(float(v))


def toml_text(name, files, fields):
    curve_names = [c for f in files for c, _ in files[f]]
    lines = [f"# Generated by tools/cases/make_cases.py; edit the script, not this file.",
             f'name = "{name}"',
             "# The thesis' settings (docs/cli.md, \"Presets\"), so that tools/eval/report reproduces chapter 6.",
             'preset = "thesis"', "", "[geometry]",
             "files = [" + ", ".join(f'"{f}"' for f in files) + "]",
             "curve_names = [" + ", ".join(f'"{c}"' for c in curve_names) + "]", ""]
    if "expression" in fields:
        lines += ["[spacing]", 'field = "expression"', f'expression = "{fields["expression"]}"', ""]
    lines += ["[init]", f'method = "{fields["method"]}"', "seed = 1", "",
              "[simulation]", "iterations = 2000", "cutoff = 1.5"]
    dt = fields["dt"]
    if isinstance(dt, dict):
        lines.append("dt_initial = { " + ", ".join(f"{k} = {toml_number(v)}" for k, v in dt.items())
                     + " }")
    elif dt is not None:
        lines.append(f"dt_initial = {toml_number(dt)}")
    if fields["views"]:
        lines += ["", "[output]", "views = ["]
        for view_name, w in fields["views"]:
            lines.append(f'  {{ name = "{view_name}", window = ['
                         + ", ".join(toml_number(v) for v in w) + "] },")
        lines.append("]")
    return "\n".join(lines) + "\n"


def write_atomically(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w", newline="\n") as f:
        f.write(text)
    os.replace(tmp, path)


def generated_files(cases):
    """Maps each relative output path to its text."""
    out = {}
    for name, files, fields in cases:
        for fname, curves in files.items():
            out[f"cases/{name}/{fname}"] = crv_text(curves)
        out[f"cases/{name}/case.toml"] = toml_text(name, files, fields)
    return out


# ----------------------------------------------------------------------------------------------
# Node-count estimate: integral over the domain of 2 / (sqrt(3) q^2), the node density of a
# hexagonal packing with spacing q, where q is thesis eq. 3.6.

class CurveIndex:
    """Segments of one curve in a bounding-box tree over contiguous index ranges (a polyline's
    consecutive segments are spatially close, so ranges make tight boxes)."""

    LEAF = 4

    def __init__(self, pts):
        self.segs = [(pts[i][0], pts[i][1], pts[i + 1][0], pts[i + 1][1],
                      math.hypot(pts[i + 1][0] - pts[i][0], pts[i + 1][1] - pts[i][1]))
                     for i in range(len(pts) - 1)]
        self.nodes = []   # (xmin, ymin, xmax, ymax, lo, hi, left child, right child)
        self.root = self._build(0, len(self.segs))

    def _build(self, lo, hi):
        s = self.segs[lo:hi]
        box = (min(min(a[0], a[2]) for a in s), min(min(a[1], a[3]) for a in s),
               max(max(a[0], a[2]) for a in s), max(max(a[1], a[3]) for a in s))
        index = len(self.nodes)
        self.nodes.append(None)
        left = right = -1
        if hi - lo > self.LEAF:
            mid = (lo + hi) // 2
            left, right = self._build(lo, mid), self._build(mid, hi)
        self.nodes[index] = box + (lo, hi, left, right)
        return index

    def _seg_d2(self, i, px, py):
        x0, y0, x1, y1, _ = self.segs[i]
        dx, dy = x1 - x0, y1 - y0
        den = dx * dx + dy * dy
        t = 0.0 if den == 0.0 else max(0.0, min(1.0, ((px - x0) * dx + (py - y0) * dy) / den))
        ex, ey = x0 + t * dx - px, y0 + t * dy - py
        return ex * ex + ey * ey

    def closest(self, px, py, hint):
        """(squared distance, segment index) of the closest segment; `hint` seeds the bound."""
        best, best_i = self._seg_d2(hint, px, py), hint
        stack = [self.root]
        nodes = self.nodes
        while stack:
            xmin, ymin, xmax, ymax, lo, hi, left, right = nodes[stack.pop()]
            dx = xmin - px if px < xmin else (px - xmax if px > xmax else 0.0)
            dy = ymin - py if py < ymin else (py - ymax if py > ymax else 0.0)
            if dx * dx + dy * dy >= best:
                continue
            if left < 0:
                for i in range(lo, hi):
                    d2 = self._seg_d2(i, px, py)
                    if d2 < best:
                        best, best_i = d2, i
            else:
                stack.append(left)
                stack.append(right)
        return best, best_i

    def crossings(self, px, py):
        """Number of segments crossed by the ray from (px, py) towards +x (half-open in y)."""
        count = 0
        stack = [self.root]
        while stack:
            xmin, ymin, xmax, ymax, lo, hi, left, right = self.nodes[stack.pop()]
            if py < ymin or py > ymax or px > xmax:
                continue
            if left >= 0:
                stack.append(left)
                stack.append(right)
                continue
            for x0, y0, x1, y1, _ in self.segs[lo:hi]:
                if (y0 > py) != (y1 > py):
                    if x0 + (py - y0) * (x1 - x0) / (y1 - y0) > px:
                        count += 1
        return count


def estimate_nodes(curves, ratio, q_expression=None):
    """Integrates 2/(sqrt(3) q^2) over the even-odd interior of `curves` on an adaptive grid:
    cells are split until their side is at most `ratio` times the local q (and the smallest nearby
    segment), and cells straddling the boundary are classified by their centre."""
    index = [CurveIndex(pts) for _, pts in curves]
    xs = [p[0] for _, pts in curves for p in pts]
    ys = [p[1] for _, pts in curves for p in pts]
    side = max(max(xs) - min(xs), max(ys) - min(ys)) * 1.0001
    x0, y0 = min(xs), min(ys)
    density = 2 / math.sqrt(3)
    total = 0.0
    cells = 0
    # Stack entries: (centre x, centre y, side, inside flag or None, closest-segment hints).
    stack = [(x0 + side / 2, y0 + side / 2, side, None, [0] * len(index))]
    while stack:
        cx, cy, h, inside, hints = stack.pop()
        cells += 1
        num = den = 0.0
        zero_lengths = []
        dmin = math.inf
        lmin_near = math.inf
        half_diag = h * 0.7071067811865476
        new_hints = []
        for ci, hint in zip(index, hints):
            d2, i = ci.closest(cx, cy, hint)
            new_hints.append(i)
            d = math.sqrt(d2)
            length = ci.segs[i][4]
            dmin = min(dmin, d)
            if d <= half_diag:
                lmin_near = min(lmin_near, length)
            if d == 0.0:
                zero_lengths.append(length)
            else:
                num += length / d
                den += 1 / d
        q = sum(zero_lengths) / len(zero_lengths) if zero_lengths else num / den
        if q_expression is not None:
            q = q_expression(cx, cy)
        uniform = dmin > half_diag
        if uniform and inside is None:
            inside = sum(ci.crossings(cx, cy) for ci in index) % 2 == 1
        if uniform and not inside:
            continue
        if h <= ratio * min(q, lmin_near) or h < side * 1e-12:
            if not uniform:
                inside = sum(ci.crossings(cx, cy) for ci in index) % 2 == 1
            if inside:
                total += density * h * h / (q * q)
            continue
        child_inside = inside if uniform else None
        for sx in (-0.25, 0.25):
            for sy in (-0.25, 0.25):
                stack.append((cx + sx * h, cy + sy * h, h / 2, child_inside, new_hints))
    return total, cells


def shock_q(x, _y):
    return 0.5 + 19.5 * math.tanh(x / 16) ** 2


def run_estimates(cases, ratio, only):
    rows = []
    for name, files, fields in cases:
        if only and name not in only:
            continue
        curves = [c for f in files.values() for c in f]
        boundary_points = len({p for _, pts in curves for p in pts})
        expr = shock_q if "expression" in fields else None
        estimate, cells = estimate_nodes(curves, ratio, expr)
        rows.append((name, boundary_points, estimate, cells))
        print(f"{name:14s} boundary points {boundary_points:6d}  estimate {estimate:10.0f}"
              f"  ({cells} cells, ratio {ratio})", flush=True)
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=REPO, help="repository root to write cases/ under")
    parser.add_argument("--check", action="store_true",
                        help="write nothing; fail if the committed files differ from the output")
    parser.add_argument("--estimate", action="store_true",
                        help="print each case's hexagonal-packing node estimate instead of writing")
    parser.add_argument("--ratio", type=float, default=0.5,
                        help="estimate grid cell side as a fraction of the local spacing q")
    parser.add_argument("cases", nargs="*", help="restrict --estimate to these cases")
    args = parser.parse_args()

    cases = build_cases()
    if args.estimate:
        run_estimates(cases, args.ratio, args.cases)
        return 0
    return write_or_check(generated_files(cases), args.out, args.check, "cases")


def write_or_check(files, root, check, under):
    """Writes {relative path: text} under root (atomically, file by file), or with check lists the
    files that differ from the text and returns 1 if any does. Returns the exit status."""
    if check:
        stale = []
        for rel, text in files.items():
            path = os.path.join(root, rel)
            if not os.path.exists(path):
                stale.append(rel)
                continue
            with open(path, newline="") as f:
                if f.read() != text:
                    stale.append(rel)
        for rel in stale:
            print(f"differs from the script's output: {rel}")
        return 1 if stale else 0
    for rel, text in files.items():
        path = os.path.join(root, rel)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        write_atomically(path, text)
    print(f"wrote {len(files)} files under {os.path.join(root, under)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
