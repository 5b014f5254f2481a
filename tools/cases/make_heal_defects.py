#!/usr/bin/env python3
"""Writes tests/data/heal/*.crv: synthetic defects for geometry healing (docs/geometry-input.md,
"Healing") and the short-arc spacing rule (docs/spacing.md). Coordinates in metres where the case is
a coastline (km scale, coast sampled at 1 km). Run from anywhere; edit this script, not the files.

  merged.crv     two polygons merged: 0.3-2.6 m segments at the two junctions
  inlet.crv      a coast with an inlet 100 m wide and 3 km deep (rectangular end)
  spike.crv      a coast with a one-vertex spike 700 m long on a 10 m base
  island.crv     a coast box with a 30 m island
  touch.crv      a 10 km square sea sampled at 500 m with a diamond hole whose tip touches its bottom
                 side at a vertex, as OGC polygons allow
  overlap.crv    the same sea with a diamond hole whose tip crosses its bottom side by 100 m
  blunt_te.crv   an airfoil-like loop (NACA 0012 thickness, chord 1) sampled at 0.05 chord whose
                 blunt trailing edge is closed by a 0.001-chord segment, in a box far field
  tiny_edge.crv  a 1 x 0.5 rectangle sampled at 0.05 with one 0.002 edge cut off a corner
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "..", "tests", "data", "heal")


def write(name, curves):
    with open(os.path.join(OUT, name), "w") as f:
        for pts in curves:
            f.write(f"{len(pts)}\n")
            for x, y in pts:
                f.write(f"{x:.17g} {y:.17g}\n")


def line(a, b, step):
    """Points from a to b (b excluded) at about `step`."""
    n = max(1, round(math.dist(a, b) / step))
    return [(a[0] + (b[0] - a[0]) * k / n, a[1] + (b[1] - a[1]) * k / n) for k in range(n)]


def closed(corners, step):
    pts = []
    for k in range(len(corners)):
        pts += line(corners[k], corners[(k + 1) % len(corners)], step)
    return pts + [pts[0]]


def coast(bottom, step=1000.0, width=20000.0, height=10000.0):
    """A counter-clockwise water box whose bottom (y = 0 side) is the given polyline from (0, 0) to
    (width, 0); the other sides sampled at `step`."""
    pts = list(bottom)
    for a, b in [((width, 0.0), (width, height)), ((width, height), (0.0, height)), ((0.0, height), (0.0, 0.0))]:
        pts += line(a, b, step)
    return pts + [pts[0]]


def main():
    os.makedirs(OUT, exist_ok=True)
    # Two polygons merged: A = [0, 10000] x [0, 10000], B = [10000, 20000] x [-1.2, 10002.6], their
    # union drawn with the small steps such unions leave behind.
    pts = line((0.0, 0.0), (10000.0, 0.0), 1000.0)
    pts += [(10000.0, 0.0), (10000.3, -1.1), (10001.5, -1.2)]
    pts += line((11000.0, -1.2), (20000.0, -1.2), 1000.0)
    pts += line((20000.0, -1.2), (20000.0, 10002.6), 1000.0)
    pts += line((20000.0, 10002.6), (11000.0, 10002.6), 1000.0)
    pts += [(11000.0, 10002.6), (10001.0, 10002.6), (10000.0, 10000.2), (9999.7, 10000.0)]
    pts += line((9000.0, 10000.0), (0.0, 10000.0), 1000.0)
    pts += line((0.0, 10000.0), (0.0, 0.0), 1000.0)
    write("merged.crv", [pts + [pts[0]]])

    bottom = line((0.0, 0.0), (10000.0, 0.0), 1000.0)
    bottom += line((10000.0, 0.0), (10000.0, -3000.0), 1000.0) + line((10000.0, -3000.0), (10100.0, -3000.0), 1000.0)
    bottom += line((10100.0, -3000.0), (10100.0, 0.0), 1000.0) + line((10100.0, 0.0), (20000.0, 0.0), 1000.0)
    write("inlet.crv", [coast(bottom)])

    bottom = line((0.0, 0.0), (10000.0, 0.0), 1000.0) + [(10000.0, 0.0), (10005.0, 700.0)]
    bottom += [(10010.0, 0.0)] + line((11000.0, 0.0), (20000.0, 0.0), 1000.0)
    write("spike.crv", [coast(bottom)])

    island = [(8000.0, 5000.0), (8000.0, 5030.0), (8030.0, 5030.0), (8030.0, 5000.0), (8000.0, 5000.0)]
    write("island.crv", [coast(line((0.0, 0.0), (20000.0, 0.0), 1000.0)), island])

    sea = closed([(0.0, 0.0), (10000.0, 0.0), (10000.0, 10000.0), (0.0, 10000.0)], 500.0)
    diamond = lambda x, y: closed([(x, y), (x - 1000.0, y + 1000.0), (x, y + 2000.0), (x + 1000.0, y + 1000.0)], 500.0)
    write("touch.crv", [sea, diamond(4000.0, 0.0)])
    write("overlap.crv", [sea, diamond(7000.0, -100.0)])

    # NACA 0012 thickness with the open trailing edge scaled to 0.001 chord.
    def half(x):
        t = 0.6 * (0.2969 * math.sqrt(x) - 0.1260 * x - 0.3516 * x**2 + 0.2843 * x**3 - 0.1015 * x**4)
        return t - (0.6 * (0.2969 - 0.1260 - 0.3516 + 0.2843 - 0.1015) - 0.0005) * x

    xs = [1.0 - 0.05 * k for k in range(21)]
    upper = [(x, half(x)) for x in xs]            # trailing edge to nose
    lower = [(x, -half(x)) for x in reversed(xs)][1:]  # nose to trailing edge
    body = upper + lower + [upper[0]]           # closing segment: the blunt trailing edge
    farfield = closed([(-2.0, -2.0), (3.0, -2.0), (3.0, 2.0), (-2.0, 2.0)], 0.25)
    write("blunt_te.crv", [farfield, body])

    corners = [(0.0, 0.0), (1.0, 0.0), (1.0, 0.498), (0.998, 0.5), (0.0, 0.5)]
    write("tiny_edge.crv", [closed(corners, 0.05)])


if __name__ == "__main__":
    main()
