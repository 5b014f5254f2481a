"""Input geometry as the evaluation tools need it: the boundary loops of .crv/.dat and .poly files
(docs/geometry-input.md) and the angle of the domain at every input vertex, which bounds the minimum
angle any mesh that keeps that vertex can reach.

The readers are lenient on purpose: pdmesh validates geometry (and is the judge of what is valid);
these only need the points and how they chain into loops."""

import math
import os


def read_crv(path):
    """Point-count blocks: returns a list of curves, each a list of (x, y)."""
    tokens = []
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].split()
            if line:
                tokens.append(line)
    curves, i = [], 0
    while i < len(tokens):
        n = int(tokens[i][0])
        curves.append([(float(t[0]), float(t[1])) for t in tokens[i + 1:i + 1 + n]])
        i += 1 + n
    return curves


def read_poly_segments(path):
    """Triangle .poly: returns (segments as ((x, y), (x, y)) pairs, hole points)."""
    with open(path) as f:
        rows = [ln.split("#", 1)[0].split() for ln in f]
    rows = [r for r in rows if r]
    nv = int(rows[0][0])
    vertices = {int(r[0]): (float(r[1]), float(r[2])) for r in rows[1:1 + nv]}
    ns = int(rows[1 + nv][0])
    seg_rows = rows[2 + nv:2 + nv + ns]
    segments = [(vertices[int(r[1])], vertices[int(r[2])]) for r in seg_rows]
    nh = int(rows[2 + nv + ns][0]) if len(rows) > 2 + nv + ns else 0
    holes = [(float(r[1]), float(r[2])) for r in rows[3 + nv + ns:3 + nv + ns + nh]]
    return segments, holes


def read_segments(files, join_tolerance=1e-9):
    """All boundary segments of the geometry files, as pairs of point ids, and the points.

    Curve end points closer than join_tolerance x (extents' diagonal) are one point, as in pdmesh."""
    curves, poly_segments = [], []
    for path in files:
        if os.path.splitext(path)[1].lower() == ".poly":
            poly_segments += read_poly_segments(path)[0]
        else:
            curves += read_crv(path)
    every = [p for c in curves for p in c] + [p for s in poly_segments for p in s]
    xs, ys = [p[0] for p in every], [p[1] for p in every]
    tol = join_tolerance * math.hypot(max(xs) - min(xs), max(ys) - min(ys))
    points, ids, ends = [], {}, []

    def point_id(p, is_end):
        if p in ids:
            return ids[p]
        if is_end:
            for k in ends:
                if math.hypot(points[k][0] - p[0], points[k][1] - p[1]) <= tol:
                    ids[p] = k
                    return k
        ids[p] = len(points)
        points.append(p)
        if is_end:
            ends.append(ids[p])
        return ids[p]

    segments = []
    for c in curves:
        chain = [point_id(p, k in (0, len(c) - 1)) for k, p in enumerate(c)]
        segments += list(zip(chain, chain[1:]))
    for a, b in poly_segments:
        segments.append((point_id(a, False), point_id(b, False)))
    return points, segments


def loops_of(points, segments):
    """Chains the segments into closed loops of point ids (first not repeated). Every point of a
    valid geometry has exactly two segments."""
    adjacent = {}
    for a, b in segments:
        adjacent.setdefault(a, []).append(b)
        adjacent.setdefault(b, []).append(a)
    seen, loops = set(), []
    for start in sorted(adjacent):
        if start in seen:
            continue
        loop, prev, cur = [start], None, start
        seen.add(start)
        while True:
            nxt = [v for v in adjacent[cur] if v != prev]
            if not nxt:
                break
            prev, cur = cur, nxt[0]
            if cur == start:
                break
            seen.add(cur)
            loop.append(cur)
        loops.append(loop)
    return loops


def signed_area(poly):
    return 0.5 * sum(x1 * y2 - x2 * y1 for (x1, y1), (x2, y2) in zip(poly, poly[1:] + poly[:1]))


def point_in_polygon(x, y, poly):
    inside = False
    for (x1, y1), (x2, y2) in zip(poly, poly[1:] + poly[:1]):
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            inside = not inside
    return inside


def domain_corners(files):
    """Every input vertex with the angle of the domain there (degrees, in (0, 360)): the even-odd
    domain lies to the left of a counter-clockwise loop at even depth and to the right of it at odd
    depth. Returns [(x, y, angle)] in loop order."""
    points, segments = read_segments(files)
    loops = loops_of(points, segments)
    polys = [[points[i] for i in loop] for loop in loops]
    corners = []
    for a, poly in enumerate(polys):
        depth = sum(point_in_polygon(*poly[0], polys[b]) for b in range(len(polys)) if b != a)
        left = (signed_area(poly) > 0) == (depth % 2 == 0)
        if not left:
            poly = poly[::-1]
        n = len(poly)
        for k in range(n):
            (ax, ay), (bx, by), (cx, cy) = poly[k - 1], poly[k], poly[(k + 1) % n]
            ux, uy, vx, vy = cx - bx, cy - by, ax - bx, ay - by
            # Counter-clockwise angle from the outgoing to the incoming segment: the domain side.
            angle = math.degrees(math.atan2(ux * vy - uy * vx, ux * vx + uy * vy))
            corners.append((bx, by, angle + 360.0 if angle <= 0.0 else angle))
    return corners


def sharpest_corner(corners):
    """The (x, y, angle) of the smallest domain angle."""
    return min(corners, key=lambda c: (c[2], c[0], c[1]))
