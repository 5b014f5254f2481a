#!/usr/bin/env python3
"""Writes NACA 0012 (cases/naca0012/*.crv) as a Gmsh 4.1 mesh with physical lines wall (5, the airfoil) and
farfield (7, the box) and surface fluid (11), for a layered run of a Gmsh-made input
(docs/journal/2026-12-08a-layer-tags.md):

    tools/.venv-anchors/bin/python tools/eval/make_naca0012_msh.py . OUT.msh
"""
import gmsh, sys
def blocks(path):
    lines = [l.split('#')[0].split() for l in open(path)]
    lines = [l for l in lines if l]
    out, i = [], 0
    while i < len(lines):
        n = int(lines[i][0]); out.append([(float(a[0]), float(a[1])) for a in lines[i + 1:i + 1 + n]]); i += n + 1
    return out
root = sys.argv[1]
air = blocks(root + "/cases/naca0012/airfoil.crv")
far = blocks(root + "/cases/naca0012/farfield.crv")
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
geo = gmsh.model.geo
tag_of = {}
def point(p, lc):
    key = (round(p[0], 12), round(p[1], 12))
    if key not in tag_of: tag_of[key] = geo.addPoint(p[0], p[1], 0, lc)
    return tag_of[key]
def polyline(curves, lc):
    out = []
    for c in curves:
        pts = [point(p, lc) for p in c]
        out += [geo.addLine(a, b) for a, b in zip(pts, pts[1:]) if a != b]
    return out
wall = polyline(air, 0.01)
box = polyline(far, 2.0)
outer = geo.addCurveLoop(box)
inner = geo.addCurveLoop(wall)
surface = geo.addPlaneSurface([outer, inner])
geo.synchronize()
gmsh.model.addPhysicalGroup(1, wall, 5, "wall")
gmsh.model.addPhysicalGroup(1, box, 7, "farfield")
gmsh.model.addPhysicalGroup(2, [surface], 11, "fluid")
gmsh.model.mesh.generate(2)
gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
gmsh.write(sys.argv[2])
print(len(wall), len(box), gmsh.__version__)
gmsh.finalize()
