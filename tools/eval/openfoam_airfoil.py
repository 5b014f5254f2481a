#!/usr/bin/env python3
"""A solver check of pdmesh's OpenFOAM output: NASA's turbulence-modeling-resource NACA 0012 (sharp
trailing edge, far field 500 chords, Re 6 million, Spalart-Allmaras) with OpenFOAM's simpleFoam, on
pdmesh's boundary-layer mesh and on Gmsh 4.15.2's BoundaryLayer mesh of the same wall and far-field
nodes (gmshToFoam), with the same solver settings; lift, drag and the wall's y+ per mesh and angle.

Setup (once): tools/eval/setup_anchors.sh (Gmsh 4.15.2 and Debian's openfoam). From the repository root:
    tools/.venv-anchors/bin/python tools/eval/openfoam_airfoil.py --pdmesh build/pdmesh --work W
        [--alpha 0 10] [--iterations 4000] [--points 161] [--first-height 2e-6] [--growth 1.15]
        [--thickness 0.03] [--gmsh-sizes field|boundary] [--meshes pdmesh,gmsh] [--set KEY=VALUE]
        [--correctors N]
        [--json FILE]

The airfoil is the resource's revised NACA 0012 formula (closed at chord 1), --points per surface on a
cosine distribution, written as a Selig .dat file; pdmesh meshes it with its defaults, a circle far
field of radius 500 and one [[boundary_layer]] table on both surfaces (quads). Gmsh gets pdmesh's
wall and far-field nodes as its boundary (point sizes from the neighbouring segments), the same
BoundaryLayer parameters with a fan at the trailing edge and Frontal-Delaunay in the core, extruded one
cell thick. Both meshes run the same case: freestream far field, no-slip walls with nuTilda 0,
nuTilda 3 nu in the free stream, SIMPLEC, bounded linearUpwind. The coefficients are the means over
the last 10 % of the iterations; their spread over that window is reported with them."""

import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from pdmesh_eval import common  # noqa: E402
from pdmesh_eval.gmsh import write_pos  # noqa: E402

RE = 6.0e6
NU = 1.0 / RE
NU_TILDA = 3.0 * NU


def tmr_naca0012(points):
    """Selig-ordered (x, y) of the revised NACA 0012: upper surface from the trailing edge to the
    leading edge, then the lower surface back; cosine spacing, `points` per surface."""
    xs = [0.5 * (1.0 - math.cos(math.pi * k / (points - 1))) for k in range(points)]

    def y(x):
        return 0.594689181 * (0.298222773 * math.sqrt(x) - 0.127125232 * x - 0.357907906 * x ** 2
                              + 0.291984971 * x ** 3 - 0.105174606 * x ** 4)

    upper = [(x, y(x)) for x in reversed(xs)]
    lower = [(x, -y(x)) for x in xs[1:]]
    upper[0] = (1.0, 0.0)
    lower[-1] = (1.0, 0.0)
    return upper + lower


def write_pdmesh_case(work, args):
    with open(os.path.join(work, "tmr0012.dat"), "w") as f:
        f.write("NACA 0012, NASA TMR revised formula (sharp trailing edge)\n")
        for x, y in tmr_naca0012(args.points):
            f.write(f"{x:.12f} {y:.12f}\n")
    case = f"""name = "tmr0012"
[geometry]
files = ["tmr0012.dat"]
[farfield]
shape = "circle"
size = 500
[[boundary_layer]]
curves = ["upper", "lower"]
first_height = {args.first_height}
growth = {args.growth}
thickness = {args.thickness}
elements = "quads"
[output]
formats = ["msh", "openfoam", "png"]
views = [{{ name = "le", window = [-0.02, -0.05, 0.08, 0.05] }}, {{ name = "te", window = [0.95, -0.03, 1.03, 0.03] }}]
"""
    path = os.path.join(work, "case.toml")
    with open(path, "w") as f:
        f.write(case)
    return path


def boundary_chains(msh):
    """{physical name: [(x, y), ...]} of the curves of a pdmesh mesh.msh, each an ordered chain."""
    import gmsh

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(msh)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        xyz = {int(t): (coords[3 * k], coords[3 * k + 1]) for k, t in enumerate(tags)}
        chains = {}
        for dim, tag in gmsh.model.getPhysicalGroups(1):
            name = gmsh.model.getPhysicalName(dim, tag)
            edges = []
            for entity in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
                _, _, nodes = gmsh.model.mesh.getElements(1, entity)
                for block in nodes:
                    edges += [(int(block[k]), int(block[k + 1])) for k in range(0, len(block), 2)]
            nxt = dict(edges)
            heads = set(nxt) - set(nxt.values())
            v = heads.pop() if heads else edges[0][0]
            chain = [v]
            while v in nxt and len(chain) <= len(edges):
                v = nxt[v]
                chain.append(v)
            chains[name] = [xyz[v] for v in chain]
        return chains
    finally:
        gmsh.finalize()


def field_view(nodes_path):
    """pdmesh's spacing field q at the core's nodes (a node file, docs/node-file.md) as the text of a
    Gmsh view, linear on the Delaunay triangles of the nodes."""
    from scipy.spatial import Delaunay

    with open(nodes_path) as f:
        lines = f.read().split("\n")
    count = int(lines[1])
    rows = [line.split() for line in lines[2:2 + count]]
    points = [(float(r[0]), float(r[1])) for r in rows]
    q = [float(r[4]) for r in rows]
    return write_pos(points, Delaunay(points).simplices.tolist(), q)


def gmsh_mesh(chains, pos, args, msh_out):
    """Gmsh's BoundaryLayer mesh on pdmesh's boundary nodes, extruded one cell thick (z 0 to 1), as
    MSH 2.2 with physical surfaces airfoil, farfield, frontAndBack and the volume fluid (and the 2-D
    mesh as MSH_OUT's stem + _2d.msh, for pictures: pdmesh quality ... --picture). With --gmsh-sizes
    field the core's sizes are pdmesh's field q at its core's final nodes (`pos`, a background view; sizes from the boundary
    points off), with `boundary` Gmsh's default: the boundary points' sizes extended inwards. Gmsh's own
    extrusion of a surface meshed with a BoundaryLayer field writes collapsed hexahedra (4.15.2), so
    the 2-D mesh is extruded here."""
    import gmsh

    airfoil = chains["upper"] + chains["lower"][1:]
    if airfoil[0] != airfoil[-1]:
        common.fail("openfoam_airfoil: the airfoil's upper and lower chains do not close")
    airfoil = airfoil[:-1]
    farfield = chains["farfield"]
    farfield = farfield[:-1] if farfield[0] == farfield[-1] else farfield

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("tmr0012")
        geo = gmsh.model.geo

        def loop(points):
            n = len(points)
            sizes = [min(math.dist(points[k], points[k - 1]), math.dist(points[k], points[(k + 1) % n]))
                     for k in range(n)]
            tags = [geo.addPoint(x, y, 0.0, h) for (x, y), h in zip(points, sizes)]
            lines = [geo.addLine(tags[k], tags[(k + 1) % n]) for k in range(n)]
            return tags, lines

        _, far_lines = loop(farfield)
        wall_points, wall_lines = loop(airfoil)
        surface = geo.addPlaneSurface([geo.addCurveLoop(far_lines), geo.addCurveLoop(wall_lines)])
        geo.synchronize()
        field = gmsh.model.mesh.field.add("BoundaryLayer")
        gmsh.model.mesh.field.setNumbers(field, "CurvesList", wall_lines)
        gmsh.model.mesh.field.setNumber(field, "Size", args.first_height)
        gmsh.model.mesh.field.setNumber(field, "Ratio", args.growth)
        gmsh.model.mesh.field.setNumber(field, "Thickness", args.thickness)
        gmsh.model.mesh.field.setNumber(field, "Quads", 1)
        trailing = min(range(len(airfoil)), key=lambda k: math.dist(airfoil[k], (1.0, 0.0)))
        gmsh.model.mesh.field.setNumbers(field, "FanPointsList", [wall_points[trailing]])
        gmsh.model.mesh.field.setAsBoundaryLayer(field)
        if args.gmsh_sizes == "field":
            pos_path = os.path.splitext(msh_out)[0] + "_q.pos"
            with open(pos_path, "w") as f:
                f.write(pos)
            gmsh.merge(pos_path)
            background = gmsh.model.mesh.field.add("PostView")
            gmsh.model.mesh.field.setNumber(background, "ViewTag", gmsh.view.getTags()[0])
            gmsh.model.mesh.field.setAsBackgroundMesh(background)
            gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
            gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
            gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        start = time.perf_counter()
        gmsh.model.mesh.generate(2)
        seconds = time.perf_counter() - start
        tags, coords, _ = gmsh.model.mesh.getNodes()
        index = {int(t): k for k, t in enumerate(tags)}
        points = [(coords[3 * k], coords[3 * k + 1]) for k in range(len(tags))]
        cells = []
        for etype, enodes in zip(*gmsh.model.mesh.getElements(2)[::2]):
            width = {2: 3, 3: 4}[int(etype)]
            cells += [[index[int(v)] for v in enodes[k:k + width]] for k in range(0, len(enodes), width)]
        edges = {}
        for name, lines in (("airfoil", wall_lines), ("farfield", far_lines)):
            for line in lines:
                _, _, enodes = gmsh.model.mesh.getElements(1, line)
                for block in enodes:
                    for k in range(0, len(block), 2):
                        edges[frozenset((index[int(block[k])], index[int(block[k + 1])]))] = name
        gmsh.model.addPhysicalGroup(1, wall_lines, name="airfoil")
        gmsh.model.addPhysicalGroup(1, far_lines, name="farfield")
        gmsh.model.addPhysicalGroup(2, [surface], name="fluid")
        gmsh.write(os.path.splitext(msh_out)[0] + "_2d.msh")
        write_extruded_msh22(points, cells, edges, msh_out)
        return {"version": gmsh.__version__, "seconds": round(seconds, 3)}
    finally:
        gmsh.finalize()


def write_extruded_msh22(points, cells, edges, path):
    """MSH 2.2 of the 2-D cells (counter-clockwise made) extruded from z = 0 to z = 1: prisms and
    hexahedra, the boundary edges `edges` ({frozenset((a, b)): group}) as quads, both faces as
    frontAndBack."""
    n = len(points)
    groups = {"airfoil": 1, "farfield": 2, "frontAndBack": 3, "fluid": 4}
    elements = []
    for c in cells:
        area = sum(points[c[k]][0] * points[c[(k + 1) % len(c)]][1] - points[c[(k + 1) % len(c)]][0] * points[c[k]][1]
                   for k in range(len(c)))
        if area < 0:
            c = c[::-1]
        elements.append((6 if len(c) == 3 else 5, groups["fluid"], c + [v + n for v in c]))
        elements.append((2 if len(c) == 3 else 3, groups["frontAndBack"], c[::-1]))
        elements.append((2 if len(c) == 3 else 3, groups["frontAndBack"], [v + n for v in c]))
    for edge, name in edges.items():
        a, b = sorted(edge)
        elements.append((3, groups[name], [a, b, b + n, a + n]))
    with open(path, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n4\n")
        f.write('2 1 "airfoil"\n2 2 "farfield"\n2 3 "frontAndBack"\n3 4 "fluid"\n$EndPhysicalNames\n')
        f.write(f"$Nodes\n{2 * n}\n")
        for z in (0, 1):
            for k, (x, y) in enumerate(points):
                f.write(f"{k + 1 + z * n} {float(x)!r} {float(y)!r} {z}\n")
        f.write(f"$EndNodes\n$Elements\n{len(elements)}\n")
        for k, (etype, group, nodes) in enumerate(elements):
            f.write(f"{k + 1} {etype} 2 {group} {group} " + " ".join(str(v + 1) for v in nodes) + "\n")
        f.write("$EndElements\n")


def foam_dict(path, cls, obj, body):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(f"FoamFile\n{{\n    version 2.0;\n    format ascii;\n    class {cls};\n    object {obj};\n}}\n{body}\n")


def patches(poly):
    """[(name, type)] of a polyMesh boundary file."""
    text = open(os.path.join(poly, "boundary")).read()
    return re.findall(r"\n\s*([A-Za-z_][\w.]*)\s*\{\s*type\s+(\w+);", text)


def set_patch_types(poly, types):
    """Rewrite the boundary file's types: {patch: type} (gmshToFoam makes every patch a `patch`)."""
    path = os.path.join(poly, "boundary")
    text = open(path).read()
    for name, kind in types.items():
        text = re.sub(rf"(\n\s*{name}\s*\{{\s*type\s+)\w+;", rf"\g<1>{kind};", text)
    with open(path, "w") as f:
        f.write(text)


def write_case(case, poly_src, alpha, iterations, correctors=0):
    """An OpenFOAM case at `case` around the polyMesh `poly_src`, the flow at `alpha` degrees."""
    if os.path.exists(case):
        shutil.rmtree(case)
    shutil.copytree(poly_src, os.path.join(case, "constant", "polyMesh"))
    kinds = patches(os.path.join(case, "constant", "polyMesh"))
    walls = [n for n, t in kinds if t == "wall"]
    far = [n for n, t in kinds if t == "patch"]
    empty = [n for n, t in kinds if t == "empty"]
    if not walls or not far or not empty:
        common.fail(f"openfoam_airfoil: {poly_src}: expected wall, patch and empty patches, found {kinds}")
    a = math.radians(alpha)
    ux, uy = math.cos(a), math.sin(a)

    def bc(wall, farfield):
        lines = [f"    {n} {{ {wall} }}" for n in walls] + [f"    {n} {{ {farfield} }}" for n in far]
        lines += [f"    {n} {{ type empty; }}" for n in empty]
        return "boundaryField\n{\n" + "\n".join(lines) + "\n}\n"

    u = f"({ux:.15g} {uy:.15g} 0)"
    foam_dict(f"{case}/0/U", "volVectorField", "U", f"dimensions [0 1 -1 0 0 0 0];\ninternalField uniform {u};\n"
              + bc("type noSlip;", f"type freestreamVelocity; freestreamValue uniform {u};"))
    foam_dict(f"{case}/0/p", "volScalarField", "p", "dimensions [0 2 -2 0 0 0 0];\ninternalField uniform 0;\n"
              + bc("type zeroGradient;", "type freestreamPressure; freestreamValue uniform 0;"))
    foam_dict(f"{case}/0/nuTilda", "volScalarField", "nuTilda",
              f"dimensions [0 2 -1 0 0 0 0];\ninternalField uniform {NU_TILDA:.9g};\n"
              + bc("type fixedValue; value uniform 0;", f"type freestream; freestreamValue uniform {NU_TILDA:.9g};"))
    foam_dict(f"{case}/0/nut", "volScalarField", "nut", "dimensions [0 2 -1 0 0 0 0];\ninternalField uniform 0;\n"
              + bc("type nutLowReWallFunction; value uniform 0;", "type calculated; value uniform 0;"))
    foam_dict(f"{case}/constant/transportProperties", "dictionary", "transportProperties",
              f"transportModel Newtonian;\nnu {NU:.9g};")
    foam_dict(f"{case}/constant/turbulenceProperties", "dictionary", "turbulenceProperties",
              "simulationType RAS;\nRAS { RASModel SpalartAllmaras; turbulence on; printCoeffs on; }")
    wall_list = " ".join(walls)
    foam_dict(f"{case}/system/controlDict", "dictionary", "controlDict", f"""application simpleFoam;
startFrom startTime; startTime 0; stopAt endTime; endTime {iterations}; deltaT 1;
writeControl timeStep; writeInterval {iterations}; purgeWrite 0; writeFormat ascii; writePrecision 10;
runTimeModifiable false;
functions
{{
    coefficients
    {{
        type forceCoeffs; libs ("libforces.so"); writeControl timeStep; writeInterval 1;
        patches ({wall_list}); rho rhoInf; rhoInf 1; CofR (0.25 0 0);
        liftDir ({-uy:.15g} {ux:.15g} 0); dragDir ({ux:.15g} {uy:.15g} 0); pitchAxis (0 0 1);
        magUInf 1; lRef 1; Aref 1;
    }}
    wallYPlus {{ type yPlus; libs ("libfieldFunctionObjects.so"); writeControl writeTime; }}
}}""")
    foam_dict(f"{case}/system/fvSchemes", "dictionary", "fvSchemes", """ddtSchemes { default steadyState; }
gradSchemes { default Gauss linear; grad(U) cellLimited Gauss linear 1; grad(nuTilda) cellLimited Gauss linear 1; }
divSchemes { default none; div(phi,U) bounded Gauss linearUpwind grad(U);
  div(phi,nuTilda) bounded Gauss linearUpwind grad(nuTilda); div((nuEff*dev2(T(grad(U))))) Gauss linear; }
laplacianSchemes { default Gauss linear corrected; }
interpolationSchemes { default linear; }
snGradSchemes { default corrected; }
wallDist { method meshWave; }""")
    foam_dict(f"{case}/system/fvSolution", "dictionary", "fvSolution", """solvers
{
    p { solver GAMG; smoother GaussSeidel; tolerance 1e-10; relTol 0.05; }
    "(U|nuTilda)" { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-12; relTol 0.1; }
}
SIMPLE { nNonOrthogonalCorrectors %d; consistent yes; }
relaxationFactors { equations { U 0.9; nuTilda 0.9; } }""" % correctors)
    return walls


def coefficients(case):
    """(rows of the forceCoeffs file as dicts) of a finished run."""
    base = os.path.join(case, "postProcessing", "coefficients", "0")
    path = next((os.path.join(base, f) for f in ("coefficient.dat", "forceCoeffs.dat")
                 if os.path.exists(os.path.join(base, f))), None)
    if path is None:
        common.fail(f"openfoam_airfoil: {case}: no forceCoeffs output in {base}")
    header, rows = None, []
    for line in open(path):
        if line.startswith("#"):
            words = line[1:].split()
            if words and words[0] == "Time":
                header = words
            continue
        values = line.split()
        if header and len(values) == len(header):
            rows.append(dict(zip(header, (float(v) for v in values))))
    return rows


def y_plus(case, log):
    """(max, mean) of the wall y+ over the wall patches, from the yPlus function object's log lines."""
    found = re.findall(r"patch (\S+) y\+ : min = (\S+), max = (\S+), average = (\S+)", log)
    if not found:
        return None
    last = {}
    for name, lo, hi, mean in found:
        last[name] = (float(hi), float(mean))
    return max(v[0] for v in last.values()), sum(v[1] for v in last.values()) / len(last)


def run_case(case, label):
    start = time.perf_counter()
    proc = subprocess.run(["simpleFoam", "-case", case], capture_output=True, text=True)
    seconds = time.perf_counter() - start
    with open(os.path.join(case, "simpleFoam.log"), "w") as f:
        f.write(proc.stdout + proc.stderr)
    if proc.returncode != 0:
        common.fail(f"openfoam_airfoil: {label}: simpleFoam failed (see {case}/simpleFoam.log)")
    rows = coefficients(case)
    window = rows[-max(1, len(rows) // 10):]
    out = {"iterations": len(rows), "seconds": round(seconds, 1)}
    for key in ("Cl", "Cd", "CmPitch"):
        values = [r[key] for r in window]
        out[key] = sum(values) / len(values)
        out[key + "_spread"] = max(values) - min(values)
    res = re.findall(r"Solving for Ux, Initial residual = (\S+),", proc.stdout)
    out["final_Ux_residual"] = float(res[-1].rstrip(",")) if res else None
    if not all(math.isfinite(out[k]) for k in ("Cl", "Cd", "CmPitch")):
        common.fail(f"openfoam_airfoil: {label}: the coefficients are not finite: {out}")
    yp = y_plus(case, proc.stdout)
    if yp:
        out["yplus_max"], out["yplus_mean"] = yp
    return out


def check_mesh(case):
    """checkMesh's verdict: ok when it prints "Mesh OK." or when its only failed check is the aspect
    ratio (above 1000 in wall cells a y+ of 1 asks for: a warning for a RANS mesh, not an error)."""
    proc = subprocess.run(["checkMesh", "-case", case], capture_output=True, text=True)
    text = proc.stdout
    cells = re.search(r"^\s+cells:\s+(\d+)", text, re.M)
    ortho = re.search(r"Mesh non-orthogonality Max: (\S+) average: (\S+)", text)
    skew = re.search(r"Max skewness = (\S+)", text)
    aspect = re.search(r"Max aspect ratio = (\S+)|Max aspect ratio: (\S+)", text)
    failed = [line.strip() for line in text.splitlines() if line.strip().startswith("***")]
    return {"ok": "Mesh OK." in text or (bool(failed) and all("High aspect ratio" in f for f in failed)),
            "mesh_ok_printed": "Mesh OK." in text, "failed_checks": failed,
            "cells": int(cells.group(1)) if cells else None,
            "non_orthogonality_max": float(ortho.group(1)) if ortho else None,
            "skewness_max": float(skew.group(1)) if skew else None,
            "aspect_ratio_max": float(next(g for g in aspect.groups() if g).rstrip(".,")) if aspect else None}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--pdmesh", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--alpha", type=float, nargs="+", default=[0.0, 10.0])
    ap.add_argument("--iterations", type=int, default=4000)
    ap.add_argument("--points", type=int, default=161, help="airfoil points per surface")
    ap.add_argument("--first-height", type=float, default=2e-6)
    ap.add_argument("--growth", type=float, default=1.15)
    ap.add_argument("--thickness", type=float, default=0.03)
    ap.add_argument("--meshes", default="pdmesh,gmsh", help="which meshes to run: pdmesh, gmsh or both")
    ap.add_argument("--gmsh-sizes", choices=["field", "boundary"], default="field",
                    help="Gmsh's core sizes: pdmesh's field q (default) or Gmsh's from the boundary points")
    ap.add_argument("--correctors", type=int, default=0,
                    help="SIMPLE's nNonOrthogonalCorrectors (0; OpenFOAM's guides ask for some above 70 degrees)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="passed to pdmesh mesh as --set (e.g. spacing.scale=0.7 for a refinement study)")
    ap.add_argument("--json")
    args = ap.parse_args()
    for tool in ("simpleFoam", "checkMesh", "gmshToFoam"):
        if shutil.which(tool) is None:
            print(f"openfoam_airfoil: no {tool} (Debian openfoam; tools/eval/setup_anchors.sh); skipped")
            sys.exit(77)
    try:
        import gmsh  # noqa: F401
        import scipy  # noqa: F401
    except ImportError as e:
        print(f"openfoam_airfoil: {e} (tools/eval/setup_anchors.sh); skipped")
        sys.exit(77)
    if not os.environ.get("WM_PROJECT_DIR") and os.path.isdir("/usr/share/openfoam/etc"):
        os.environ["WM_PROJECT_DIR"] = "/usr/share/openfoam"
    work = os.path.abspath(args.work)
    os.makedirs(work, exist_ok=True)

    case_toml = write_pdmesh_case(work, args)
    start = time.perf_counter()
    subprocess.run([os.path.abspath(args.pdmesh), "mesh", case_toml, "--out", os.path.join(work, "pdmesh"), "-q"]
                   + [a for kv in args.set for a in ("--set", kv)], check=True)
    meshes = {"pdmesh": {"poly": os.path.join(work, "pdmesh", "mesh_openfoam", "constant", "polyMesh"),
                         "seconds": round(time.perf_counter() - start, 2)}}
    if "gmsh" in args.meshes:
        chains = boundary_chains(os.path.join(work, "pdmesh", "mesh.msh"))
        pos = field_view(os.path.join(work, "pdmesh", "final.nodes"))
        gcase = os.path.join(work, "gmsh_case")
        shutil.rmtree(gcase, ignore_errors=True)
        os.makedirs(os.path.join(gcase, "system"))
        info = gmsh_mesh(chains, pos, args, os.path.join(work, "gmsh.msh"))
        foam_dict(f"{gcase}/system/controlDict", "dictionary", "controlDict",
                  "application simpleFoam; startFrom startTime; startTime 0; stopAt endTime; endTime 1; deltaT 1;"
                  " writeControl timeStep; writeInterval 1;")
        subprocess.run(["gmshToFoam", "-case", gcase, os.path.join(work, "gmsh.msh")], check=True,
                       capture_output=True)
        poly = os.path.join(gcase, "constant", "polyMesh")
        set_patch_types(poly, {"airfoil": "wall", "frontAndBack": "empty", "farfield": "patch"})
        meshes["gmsh"] = {"poly": poly, **info}

    results = {"re": RE, "gmsh_sizes": args.gmsh_sizes, "set": args.set, "correctors": args.correctors,
               "first_height": args.first_height, "growth": args.growth, "thickness": args.thickness,
               "points": args.points, "iterations": args.iterations, "meshes": {}}
    for name, mesh in meshes.items():
        if name not in args.meshes:
            continue
        entry = {k: v for k, v in mesh.items() if k != "poly"}
        for alpha in args.alpha:
            case = os.path.join(work, f"{name}_a{alpha:g}")
            write_case(case, mesh["poly"], alpha, args.iterations, args.correctors)
            if "check" not in entry:
                entry["check"] = check_mesh(case)
                if name == "pdmesh" and not entry["check"]["ok"]:
                    common.fail(f"openfoam_airfoil: checkMesh failed on pdmesh's mesh ({case}): "
                                f"{entry['check']['failed_checks']}")
            entry[f"alpha {alpha:g}"] = run_case(case, f"{name} alpha {alpha:g}")
            r = entry[f"alpha {alpha:g}"]
            print(f"{name:7s} cells {entry['check']['cells']} alpha {alpha:4g}: Cl {r['Cl']:.4f} (+-{r['Cl_spread']:.1e})"
                  f" Cd {r['Cd']:.5f} (+-{r['Cd_spread']:.1e}) y+ max {r.get('yplus_max', float('nan')):.2f}"
                  f" mean {r.get('yplus_mean', float('nan')):.2f}, {r['iterations']} iterations {r['seconds']} s",
                  flush=True)
        results["meshes"][name] = entry
    if args.json:
        common.write_atomically(args.json, json.dumps(results, indent=1).encode())


if __name__ == "__main__":
    main()
