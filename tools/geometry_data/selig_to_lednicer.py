#!/usr/bin/env python3
"""Rewrites a Selig airfoil file in Lednicer's layout: the name line, a line of the two surface point
counts ("N. M."), a blank line, the upper surface from the leading edge (the point of least x) to the
trailing edge, a blank line, the lower surface likewise. The numbers are copied as written."""
import sys


def main(path):
    lines = [l.rstrip("\n") for l in open(path)]
    name, rows = lines[0].strip(), [l.split() for l in lines[1:] if l.strip()]
    le = min(range(len(rows)), key=lambda k: float(rows[k][0]))
    upper, lower = rows[: le + 1][::-1], rows[le:]
    print(name)
    print(f"{len(upper)}. {len(lower)}.")
    for surface in (upper, lower):
        print()
        for x, y in surface:
            print(f" {x} {y}")


if __name__ == "__main__":
    main(sys.argv[1])
