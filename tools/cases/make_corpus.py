#!/usr/bin/env python3
"""Generates the evaluation corpus under cases/corpus/: user-like geometries (a gear with a bore, a
perforated plate, a slotted-flap airfoil, a coastline with inlets, an L-bracket, a finned channel)
with sharp corners, narrow gaps and curves segmented far more coarsely or finely than their
neighbours. Each case.toml names only the geometry, curve names and zoom views, so it runs with the
best defaults. See docs/cases.md, "Corpus".

Standard library only. Deterministic: running it twice writes byte-identical files.
"""
import argparse
import math
import os
import sys

from make_cases import circle_loop, clean, crv_text, line, write_or_check

# The evaluation tools' shared code (tools/eval/pdmesh_eval/) finds the corners the views zoom on.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "eval"))
from pdmesh_eval.geometry import domain_corners  # noqa: E402 (after the path is set)

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CORPUS = os.path.join("cases", "corpus")


# ----------------------------------------------------------------------------------------------
# Curve pieces. A closed outline is a chain of pieces; chain() makes the joints exact.

def arc(cx, cy, r, a0, a1, h):
    """Points on the circle (cx, cy, r) from angle a0 to a1 (radians), segments about h long."""
    n = max(1, round(abs(a1 - a0) * r / h))
    return [(clean(cx + r * math.cos(a0 + (a1 - a0) * k / n)), clean(cy + r * math.sin(a0 + (a1 - a0) * k / n)))
            for k in range(n + 1)]


def resample(dense, h, min_segments=1):
    """Equal arc-length points along a densely sampled polyline, segments about h long, with the
    end points kept exactly."""
    s = [0.0]
    for a, b in zip(dense, dense[1:]):
        s.append(s[-1] + math.hypot(b[0] - a[0], b[1] - a[1]))
    n = max(min_segments, round(s[-1] / h))
    out, k = [dense[0]], 0
    for i in range(1, n):
        target = s[-1] * i / n
        while s[k + 1] < target:
            k += 1
        t = (target - s[k]) / (s[k + 1] - s[k])
        a, b = dense[k], dense[k + 1]
        out.append((clean(a[0] + t * (b[0] - a[0])), clean(a[1] + t * (b[1] - a[1]))))
    return out + [dense[-1]]


def sampled(f, t0, t1, count=4000):
    """A dense polyline of the parametric curve f(t), t from t0 to t1."""
    return [f(t0 + (t1 - t0) * k / count) for k in range(count + 1)]


def chain(pieces, closed=False):
    """Concatenates pieces, each starting where the previous ends (the very same tuple is reused so
    the joint is exact); closed: the last point becomes the first one."""
    out = list(pieces[0])
    for p in pieces[1:]:
        gap = math.hypot(p[0][0] - out[-1][0], p[0][1] - out[-1][1])
        assert gap < 1e-9, f"pieces do not join: gap {gap}"
        out += p[1:]
    if closed:
        assert math.hypot(out[-1][0] - out[0][0], out[-1][1] - out[0][1]) < 1e-9
        out[-1] = out[0]
    return out


def rotate(p, centre, angle):
    c, s = math.cos(angle), math.sin(angle)
    dx, dy = p[0] - centre[0], p[1] - centre[1]
    return (clean(centre[0] + c * dx - s * dy), clean(centre[1] + s * dx + c * dy))


def rect_sides(x0, y0, x1, y1, h, names=("bottom", "right", "top", "left")):
    """Four side curves of an axis-aligned rectangle (counter-clockwise), sharing exact corners."""
    c = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    out = []
    for k, name in enumerate(names):
        a, b = c[k], c[(k + 1) % 4]
        h_k = h[k] if isinstance(h, tuple) else h
        out.append((name, line(a, b, max(1, round(math.hypot(b[0] - a[0], b[1] - a[1]) / h_k)))))
    return out


def min_distance(a, b):
    """Smallest distance between the vertices of polyline a and the segments of polyline b."""
    best = math.inf
    for px, py in a:
        for (x0, y0), (x1, y1) in zip(b, b[1:]):
            dx, dy = x1 - x0, y1 - y0
            t = max(0.0, min(1.0, ((px - x0) * dx + (py - y0) * dy) / (dx * dx + dy * dy)))
            best = min(best, math.hypot(x0 + t * dx - px, y0 + t * dy - py))
    return best


# ----------------------------------------------------------------------------------------------
# Geometries.

def gear():
    """An 18-tooth involute spur gear (module 0.1, 20 deg pressure angle) with a bore and keyway.
    The bore is segmented 10x finer than the tooth outline, 0.325 from its root circle."""
    z, m, alpha = 18, 0.1, math.radians(20.0)
    rp, h_outline, h_bore = m * z / 2, 0.03, 0.003
    rb, ra, rf = rp * math.cos(alpha), rp + m, rp - 1.25 * m

    def inv(phi):
        return math.tan(phi) - phi

    def half_thickness(r):  # angular half thickness of a tooth at radius r >= rb
        return math.pi / (2 * z) + inv(alpha) - inv(math.acos(rb / r))

    def polar(r, a):
        return (clean(r * math.cos(a)), clean(r * math.sin(a)))

    pieces = []
    pitch = 2 * math.pi / z
    for k in range(z):
        g = k * pitch
        # Root arc from the previous tooth's left flank to this tooth's right flank.
        pieces.append(arc(0.0, 0.0, rf, g - pitch + half_thickness(rb), g - half_thickness(rb), h_outline))
        pieces.append(resample([polar(rf, g - half_thickness(rb)), polar(rb, g - half_thickness(rb))], h_outline))
        pieces.append(resample(sampled(lambda r: polar(r, g - half_thickness(r)), rb, ra, 400), h_outline))
        pieces.append(arc(0.0, 0.0, ra, g - half_thickness(ra), g + half_thickness(ra), h_outline))
        pieces.append(resample(sampled(lambda r: polar(r, g + half_thickness(r)), ra, rb, 400), h_outline))
        pieces.append(resample([polar(rb, g + half_thickness(rb)), polar(rf, g + half_thickness(rb))], h_outline))
    outline = chain(pieces, closed=True)
    # Bore of radius 0.45 with a keyway 0.1 wide reaching radius 0.52 at the top.
    rbore, half_key, rkey = 0.45, 0.05, 0.52
    y_key = math.sqrt(rbore ** 2 - half_key ** 2)
    right, left = (half_key, clean(y_key)), (-half_key, clean(y_key))
    a_right, a_left = math.atan2(y_key, half_key), math.atan2(y_key, -half_key)
    bore = arc(0.0, 0.0, rbore, a_left, a_right + 2 * math.pi, h_bore)
    bore[0], bore[-1] = left, right
    keyway = chain([line(right, (half_key, rkey), 8), line((half_key, rkey), (-half_key, rkey), 10),
                    line((-half_key, rkey), left, 8)])
    files = {"gear.crv": [("outline", outline), ("bore", bore), ("keyway", keyway)]}
    views = [("tooth", [0.7, -0.15, 1.05, 0.2]), ("keyway", [-0.15, 0.35, 0.15, 0.6]),
             ("bore_to_root", [0.3, -0.25, 0.9, 0.25])]
    return files, views


def plate():
    """An 8 x 4 perforated plate (Triangle .poly) with walls segmented 0.1: a hole 0.05 from the
    bottom wall (quality-methods.md section 1), a 10x finer hole 0.1 from the right wall, two slots
    with a 0.06 web between them, a coarse octagonal cut-out and bolt holes."""
    walls = rect_sides(0.0, 0.0, 8.0, 4.0, 0.1, ("wall_bottom", "wall_right", "wall_top", "wall_left"))
    holes = [("hole_gap", 1.0, 0.2, 0.15, 0.03), ("hole_fine", 7.6, 2.0, 0.3, 0.01),
             ("bolt_1", 0.5, 3.5, 0.2, 0.04), ("bolt_2", 7.5, 0.5, 0.2, 0.04),
             ("bolt_3", 2.6, 1.0, 0.12, 0.02)]
    curves = list(walls)
    centres = []
    for name, cx, cy, r, h in holes:
        curves.append((name, circle_loop(cx, cy, r, max(8, round(2 * math.pi * r / h)))))
        centres.append((cx, cy))
    # Two stadium slots at y = 1.8 and 2.2, 0.34 wide: the web between them is 0.06 wide.
    for name, cy in (("slot_lower", 1.8), ("slot_upper", 2.2)):
        x0, x1, r = 3.4, 4.8, 0.17
        curves.append((name, chain([line((x0, clean(cy - r)), (x1, clean(cy - r)), 70),
                                    arc(x1, cy, r, -math.pi / 2, math.pi / 2, 0.02),
                                    line((x1, clean(cy + r)), (x0, clean(cy + r)), 70),
                                    arc(x0, cy, r, math.pi / 2, 1.5 * math.pi, 0.02)], closed=True)))
        centres.append(((x0 + x1) / 2, cy))
    # Octagonal cut-out with 0.31 segments: 3x the wall's, 15x the slots' beside it.
    curves.append(("octagon", circle_loop(5.8, 1.2, 0.4, 8)))
    centres.append((5.8, 1.2))
    return {"plate.poly": (curves, centres)}, [
        ("hole_gap", [0.6, -0.05, 1.4, 0.45]), ("slot_web", [3.1, 1.5, 3.9, 2.5]),
        ("fine_hole", [7.1, 1.5, 8.05, 2.5]), ("octagon", [5.2, 0.6, 6.4, 1.8])]


def naca4(m, p, t, segments, weight=0.85):
    """A NACA 4-digit section (chord 1, closed trailing edge): upper surface LE -> TE and lower
    surface TE -> LE, clustered at both edges by partial cosine spacing."""
    def camber(x):
        if x < p:
            return m / p ** 2 * (2 * p * x - x * x), 2 * m / p ** 2 * (p - x)
        return m / (1 - p) ** 2 * (1 - 2 * p + 2 * p * x - x * x), 2 * m / (1 - p) ** 2 * (p - x)

    def thickness(x):
        return 5 * t * (0.2969 * math.sqrt(x) - 0.1260 * x - 0.3516 * x ** 2 + 0.2843 * x ** 3 - 0.1036 * x ** 4)

    xs = [(1 - weight) * k / segments + weight * 0.5 * (1 - math.cos(math.pi * k / segments))
          for k in range(segments + 1)]
    upper, lower = [], []
    for x in xs:
        yc, slope = camber(x)
        th = math.atan(slope)
        yt = thickness(x)
        upper.append((clean(x - yt * math.sin(th)), clean(yc + yt * math.cos(th))))
        lower.append((clean(x + yt * math.sin(th)), clean(yc - yt * math.cos(th))))
    upper[0] = lower[0] = (0.0, 0.0)
    upper[-1] = lower[-1] = (1.0, clean(camber(1.0)[0]))
    return upper, lower[::-1]


def flap_airfoil():
    """A NACA 4412 main element with a slotted NACA 2412 flap (0.3 chord, 25 deg down) whose slot
    is 0.012 wide, in a 6 x 3 box segmented 0.25 (about 20x the airfoils' mid-chord segments)."""
    main_upper, main_lower = naca4(0.04, 0.4, 0.12, 90)
    f_upper, f_lower = naca4(0.02, 0.4, 0.12, 40)
    chord, deflection, gap = 0.3, math.radians(-25.0), 0.012

    def place(pts, y):
        return [rotate((clean(0.88 + chord * px), clean(y + chord * py)), (0.88, y), deflection) for px, py in pts]

    # The flap's leading edge sits under the main trailing edge; bisect its height so that the
    # slot (nearest approach of the two elements) is `gap` wide.
    lo, hi = -0.2, 0.0
    for _ in range(40):
        y = 0.5 * (lo + hi)
        d = min(min_distance(place(f_upper, y), main_lower), min_distance(main_lower, place(f_upper, y)))
        lo, hi = (lo, y) if d < gap else (y, hi)
    y = lo
    flap_upper, flap_lower = place(f_upper, y), place(f_lower, y)
    flap_lower[-1] = flap_upper[0]
    flap_lower[0] = flap_upper[-1]
    box = rect_sides(-1.5, -1.5, 4.5, 1.5, 0.25, ("far_bottom", "far_right", "far_top", "far_left"))
    files = {"elements.crv": [("main_upper", main_upper), ("main_lower", main_lower),
                              ("flap_upper", flap_upper), ("flap_lower", flap_lower)],
             "farfield.crv": box}
    views = [("airfoil", [-0.1, -0.35, 1.3, 0.25]), ("slot", [0.82, -0.1, 1.04, 0.04]),
             ("leading_edge", [-0.03, -0.04, 0.05, 0.04]), ("flap_trailing_edge", [1.06, -0.2, 1.2, -0.06])]
    return files, views


def coastline():
    """A bay: open sea boundaries (segments 0.15) and a wiggly coastline (segments 0.01, 15x finer)
    with a 0.06 and a 0.025 wide inlet, a V-shaped inlet whose tip is about 15 deg, an island 0.03 off
    the coast and one in open water."""
    h_coast, h_sea = 0.01, 0.15

    def xc(y):
        return 2.8 + 0.15 * math.sin(2.1 * y) + 0.07 * math.sin(5.3 * y + 1.0) + 0.03 * math.sin(13.0 * y + 2.0)

    def coast_piece(y0, y1):
        return resample(sampled(lambda y: (clean(xc(y)), clean(y)), y0, y1, 2000), h_coast)

    # Inlets: (centre y, mouth width, length, tip width); tip width 0 makes a V.
    inlets = [(0.7, 0.06, 0.7, 0.06), (1.35, 0.025, 0.5, 0.025), (2.45, 0.16, 0.6, 0.0)]
    pieces, y = [], 0.0
    for yi, w, length, tip in inlets:
        a, b = yi - w / 2, yi + w / 2
        pieces.append(coast_piece(y, a))
        x_tip = clean(xc(yi) + length)
        if tip > 0:
            p0, p1 = (clean(x_tip), clean(a)), (clean(x_tip), clean(b))
            pieces += [resample([pieces[-1][-1], p0], h_coast), resample([p0, p1], h_coast),
                       resample([p1, (clean(xc(b)), clean(b))], h_coast)]
        else:
            apex = (x_tip, clean(yi))
            pieces += [resample([pieces[-1][-1], apex], h_coast), resample([apex, (clean(xc(b)), clean(b))], h_coast)]
        y = b
    pieces.append(coast_piece(y, 3.0))
    coast = chain(pieces)
    south, north = coast[0], coast[-1]
    sea = [("sea_south", line((0.0, 0.0), south, max(1, round(south[0] / h_sea)))),
           ("coast", coast),
           ("sea_north", line(north, (0.0, 3.0), max(1, round(north[0] / h_sea)))),
           ("sea_west", line((0.0, 3.0), (0.0, 0.0), round(3.0 / h_sea)))]

    def blob(cx, cy, r, h):
        def f(t):
            rr = r * (1 + 0.15 * math.sin(3 * t) + 0.08 * math.cos(5 * t))
            return (clean(cx + rr * math.cos(t)), clean(cy + rr * math.sin(t)))
        pts = resample(sampled(f, 0.0, 2 * math.pi, 3000), h)
        pts[-1] = pts[0]
        return pts

    # The near island is pushed towards the coast until the strait is 0.03 wide (measured against
    # the stretch of coast beside it, between the inlets, to keep the search quick).
    beside = [p for p in coast if 1.5 < p[1] < 2.35]
    lo, hi = 2.0, 2.6
    for _ in range(40):
        cx = 0.5 * (lo + hi)
        d = min_distance(blob(cx, 1.95, 0.2, 0.02), beside)
        lo, hi = (cx, hi) if d > 0.03 else (lo, cx)
    islands = [("island_near", blob(lo, 1.95, 0.2, 0.02)), ("island_far", blob(1.2, 1.2, 0.3, 0.04))]
    files = {"coast.crv": sea + islands}
    views = [("inlets", [2.6, 0.4, 3.7, 1.6]), ("v_inlet", [2.7, 2.2, 3.6, 2.7]),
             ("strait", [2.3, 1.6, 3.0, 2.3]), ("sea_corner", [2.3, -0.1, 3.1, 0.5])]
    return files, views


def bracket():
    """An L-shaped bracket (Triangle .poly), arms 1 wide and 3 long: straight edges segmented 0.05,
    the inner fillet (radius 0.25) 0.004 (12x finer), one arm end in two segments of 0.5 (10x
    coarser), a rounded outer corner, a chamfer, three bolt holes and a small hole 0.07 from an edge."""
    h = 0.05
    r_in, r_out = 0.25, 0.3
    fillet = arc(1.0 + r_in, 1.0 + r_in, r_in, math.pi, 1.5 * math.pi, 0.004)
    fillet = [(clean(x), clean(y)) for x, y in fillet]
    fillet[0], fillet[-1] = (1.0, clean(1.0 + r_in)), (clean(1.0 + r_in), 1.0)
    corner = arc(r_out, r_out, r_out, math.pi, 1.5 * math.pi, 0.03)
    corner[0], corner[-1] = (0.0, r_out), (r_out, 0.0)

    def seg(a, b, step=h):
        return line(a, b, max(1, round(math.hypot(b[0] - a[0], b[1] - a[1]) / step)))

    outer = [("outer_corner", corner[::-1]),
             ("bottom", seg((r_out, 0.0), (3.0, 0.0))),
             ("arm_end", line((3.0, 0.0), (3.0, 1.0), 2)),
             ("arm_top", seg((3.0, 1.0), (fillet[-1][0], 1.0))),
             ("fillet", fillet[::-1]),
             ("arm_inner", seg((1.0, fillet[0][1]), (1.0, 2.9))),
             ("chamfer", seg((1.0, 2.9), (0.9, 3.0))),
             ("top", seg((0.9, 3.0), (0.0, 3.0))),
             ("left", seg((0.0, 3.0), (0.0, r_out)))]
    holes = [("bolt_a", 0.5, 2.4, 0.18, 0.02), ("bolt_b", 2.4, 0.5, 0.18, 0.02),
             ("bolt_corner", 0.5, 0.5, 0.15, 0.01), ("hole_edge", 2.0, 0.85, 0.08, 0.01)]
    curves = list(outer)
    centres = []
    for name, cx, cy, r, step in holes:
        curves.append((name, circle_loop(cx, cy, r, max(8, round(2 * math.pi * r / step)))))
        centres.append((cx, cy))
    return {"bracket.poly": (curves, centres)}, [
        ("fillet", [0.9, 0.9, 1.5, 1.5]), ("arm_end", [2.4, -0.1, 3.1, 1.1]),
        ("hole_edge", [1.8, 0.65, 2.2, 1.05]), ("chamfer", [0.6, 2.7, 1.1, 3.05])]


def heatsink_channel():
    """A channel (5 x 1.2, walls segmented 0.05, inlet/outlet 0.1) over a heat sink of seven fins
    0.04 thick (outline segmented 0.01, 5x finer), with a thin slot 0.03 wide in the top wall whose
    V-shaped end has a 17 deg tip."""
    h_sink, h_wall = 0.01, 0.05
    base, fin_t, fin_h, pitch, first = 0.08, 0.04, 0.5, 0.28, 1.12
    pts = [(1.0, 0.0), (1.0, base)]
    for k in range(7):
        x0 = clean(first + k * pitch)
        x1 = clean(x0 + fin_t)
        pts += [(x0, base), (x0, clean(base + fin_h)), (x1, clean(base + fin_h)), (x1, base)]
    pts += [(3.0, base), (3.0, 0.0)]
    sink = chain([resample([a, b], h_sink) for a, b in zip(pts, pts[1:])])
    # Slot in the top wall at x = 3.5: 0.03 wide, straight walls 0.25 deep, then a V 0.1 long.
    xs, w, depth, v = 3.5, 0.03, 0.25, 0.1
    a, b = (clean(xs + w / 2), 1.2), (clean(xs - w / 2), 1.2)
    slot_pts = [a, (a[0], clean(1.2 + depth)), (xs, clean(1.2 + depth + v)), (b[0], clean(1.2 + depth)), b]
    slot = chain([resample([p, q], h_sink) for p, q in zip(slot_pts, slot_pts[1:])])

    def seg(p, q, step):
        return line(p, q, max(1, round(math.hypot(q[0] - p[0], q[1] - p[1]) / step)))

    curves = [("wall_in", seg((0.0, 0.0), (1.0, 0.0), h_wall)), ("sink", sink),
              ("wall_out", seg((3.0, 0.0), (5.0, 0.0), h_wall)), ("outlet", seg((5.0, 0.0), (5.0, 1.2), 0.1)),
              ("top_right", seg((5.0, 1.2), a, h_wall)), ("slot", slot), ("top_left", seg(b, (0.0, 1.2), h_wall)),
              ("inlet", seg((0.0, 1.2), (0.0, 0.0), 0.1))]
    return {"channel.crv": curves}, [
        ("fins", [1.0, -0.05, 1.8, 0.7]), ("fin_tip", [1.35, 0.5, 1.55, 0.65]),
        ("slot", [3.35, 1.0, 3.65, 1.6]), ("sink_end", [2.7, -0.05, 3.3, 0.4])]


CASES = [("gear", gear), ("plate", plate), ("flap_airfoil", flap_airfoil), ("coastline", coastline),
         ("bracket", bracket), ("heatsink_channel", heatsink_channel)]


# ----------------------------------------------------------------------------------------------
# Writing.

def poly_text(curves, hole_points):
    """Triangle .poly: vertices in order of first use, one boundary marker per curve (so each curve
    comes back as one curve, in this order), hole points at the given centres."""
    index, vertices, segments = {}, [], []
    for marker, (_, pts) in enumerate(curves, start=1):
        for a, b in zip(pts, pts[1:]):
            for p in (a, b):
                if p not in index:
                    index[p] = len(vertices) + 1
                    vertices.append(p)
            segments.append((index[a], index[b], marker))
    out = [f"{len(vertices)} 2 0 0"]
    out += ["%d %.17g %.17g" % (k + 1, x, y) for k, (x, y) in enumerate(vertices)]
    out.append(f"{len(segments)} 1")
    out += [f"{k + 1} {a} {b} {m}" for k, (a, b, m) in enumerate(segments)]
    out.append(str(len(hole_points)))
    out += ["%d %.17g %.17g" % (k + 1, x, y) for k, (x, y) in enumerate(hole_points)]
    return "\n".join(out) + "\n"


def toml_text(name, doc, files, views):
    curve_names = [c for f in files for c, _ in (files[f][0] if f.endswith(".poly") else files[f])]
    lines = ["# Generated by tools/cases/make_corpus.py; edit the script, not this file.",
             f"# {doc}",
             "# No preset and no settings: the case runs with pdmesh's best defaults.",
             f'name = "{name}"', "", "[geometry]",
             "files = [" + ", ".join(f'"{f}"' for f in files) + "]",
             "curve_names = [" + ", ".join(f'"{c}"' for c in curve_names) + "]", "", "[output]", "views = ["]
    for view_name, w in views:
        lines.append(f'  {{ name = "{view_name}", window = [' + ", ".join(repr(float(v)) for v in w) + "] },")
    lines.append("]")
    return "\n".join(lines) + "\n"


def generated_files():
    """Maps each relative output path to its text."""
    out = {}
    for name, build in CASES:
        files, views = build()
        doc = " ".join(build.__doc__.split())
        for fname, content in files.items():
            text = poly_text(*content) if fname.endswith(".poly") else crv_text(content)
            out[os.path.join(CORPUS, name, fname)] = text
        out[os.path.join(CORPUS, name, "case.toml")] = toml_text(name, doc, files, views)
    return out


def summary(root):
    """Per case: boundary points, the sharpest domain angle at an input vertex, segment lengths."""
    for name, build in CASES:
        files, _ = build()
        paths = [os.path.join(root, CORPUS, name, f) for f in files]
        corners = domain_corners(paths)
        x, y, angle = min(corners, key=lambda c: c[2])
        sharp = sum(1 for c in corners if c[2] < 30.0)
        lengths = []
        for content in files.values():
            curves = content[0] if isinstance(content, tuple) else content
            for _, pts in curves:
                lengths += [math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(pts, pts[1:])]
        print(f"{name:17s} {len(corners):6d} boundary points; sharpest input corner {angle:6.2f} deg at "
              f"({x:.4g}, {y:.4g}); {sharp} corner(s) < 30 deg; segments {min(lengths):.3g} to {max(lengths):.3g}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=REPO, help="repository root to write cases/corpus/ under")
    parser.add_argument("--check", action="store_true",
                        help="write nothing; fail if the committed files differ from the output")
    parser.add_argument("--summary", action="store_true",
                        help="print each case's boundary points, sharpest input corner and segment lengths "
                             "(reads the files under --out)")
    args = parser.parse_args()
    if args.summary:
        summary(args.out)
        return 0
    return write_or_check(generated_files(), args.out, args.check, CORPUS)


if __name__ == "__main__":
    sys.exit(main())
