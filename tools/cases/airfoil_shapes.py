#!/usr/bin/env python3
"""Airfoils of different trailing edges as .crv files (one closed curve each), for the far-field
measurements of docs/journal/2026-12-02-geo-farfield.md: NACA 4-digit sections with a sharp trailing
edge (the closed-TE coefficient -0.1036) or a blunt one (the standard -0.1015, closed by its base
segment), and a Joukowski airfoil, whose trailing edge is a cusp.

    python3 tools/cases/airfoil_shapes.py OUTDIR
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

N = 100  # points per surface, cosine-spaced


def naca4(code: str, sharp: bool) -> list[tuple[float, float]]:
    m, p, t = int(code[0]) / 100.0, int(code[1]) / 10.0, int(code[2:]) / 100.0
    a4 = -0.1036 if sharp else -0.1015
    upper, lower = [], []
    for i in range(N + 1):
        x = 0.5 * (1.0 - math.cos(math.pi * i / N))
        yt = 5 * t * (0.2969 * math.sqrt(x) - 0.1260 * x - 0.3516 * x**2 + 0.2843 * x**3 + a4 * x**4)
        if m > 0 and x < p:
            yc, dy = m / p**2 * (2 * p * x - x * x), 2 * m / p**2 * (p - x)
        elif m > 0:
            yc, dy = m / (1 - p) ** 2 * (1 - 2 * p + 2 * p * x - x * x), 2 * m / (1 - p) ** 2 * (p - x)
        else:
            yc, dy = 0.0, 0.0
        th = math.atan(dy)
        upper.append((x - yt * math.sin(th), yc + yt * math.cos(th)))
        lower.append((x + yt * math.sin(th), yc - yt * math.cos(th)))
    # From the upper trailing edge over the leading edge to the lower trailing edge.
    points = upper[::-1] + lower[1:]
    if sharp:
        points[-1] = points[0]  # one trailing-edge point
    else:
        points.append(points[0])  # the blunt base closes the loop
    return points


def joukowski(centre: complex = complex(-0.08, 0.08)) -> list[tuple[float, float]]:
    """The image of the circle through z = 1 about `centre` under z + 1/z, scaled to chord 1."""
    radius = abs(1 - centre)
    beta = math.atan2(-centre.imag, 1 - centre.real)  # the angle of z = 1 on the circle
    zs = []
    for i in range(2 * N):
        th = beta + 2 * math.pi * i / (2 * N)
        z = centre + radius * complex(math.cos(th), math.sin(th))
        zs.append(z + 1 / z)
    xs = [z.real for z in zs]
    lo, hi = min(xs), max(xs)
    points = [((z.real - lo) / (hi - lo), z.imag / (hi - lo)) for z in zs]
    points.append(points[0])
    return points


def write(path: Path, points: list[tuple[float, float]]) -> None:
    path.write_text(f"{len(points)}\n" + "".join(f"{x:.17g} {y:.17g}\n" for x, y in points))


def main() -> None:
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    for code, sharp in [("0012", True), ("2412", True), ("6409", True), ("4412", False), ("0021", False)]:
        write(out / f"naca{code}_{'sharp' if sharp else 'blunt'}.crv", naca4(code, sharp))
    write(out / "joukowski_cusped.crv", joukowski())


if __name__ == "__main__":
    main()
