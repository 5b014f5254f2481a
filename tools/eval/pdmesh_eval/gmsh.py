"""Gmsh meshes of pdmesh's boundary: a .geo with one point per boundary node of a pdmesh node file
and one transfinite 2-node line per boundary segment (so Gmsh keeps exactly those boundary nodes),
sized either from the boundary (tools/eval/report) or by a background view of pdmesh's own spacing
(tools/eval/compare); the view as a .pos file; and running Gmsh."""

import math
import subprocess

from .geometry import point_in_polygon
from .meshfiles import boundary_loops

GMSH_INSTALL = "apt-get install -y --no-install-recommends gmsh"


def write_geo(nodes, curves, algorithm, background=None, source="pdmesh's mesh.nodes"):
    """The .geo text for nodes and curves of a node file. One Plane Surface per even-odd region
    (outer loop minus the loops directly inside it).

    background None: mesh size at a point = mean of its two boundary segments, extended from the
    boundary into the domain (Gmsh's defaults). background "FILE.pos": that post-processing view
    (merged, relative to the .geo) is the background mesh and the only size source: sizes from
    points, from the boundary and from curvature are off."""
    loops = boundary_loops(curves)
    polys = [[(nodes[i][0], nodes[i][1]) for i in loop] for loop in loops]
    depth = [sum(point_in_polygon(*polys[a][0], polys[b]) for b in range(len(loops)) if b != a)
             for a in range(len(loops))]
    out = [f"// Written by the pdmesh evaluation tools from {source}.", f"Mesh.Algorithm = {algorithm};"]
    if background is None:
        out += ["Mesh.MeshSizeExtendFromBoundary = 1;", "Mesh.MeshSizeFromPoints = 1;"]
    else:
        out += [f'Merge "{background}";', "Background Mesh View[0];",
                "Mesh.MeshSizeExtendFromBoundary = 0;", "Mesh.MeshSizeFromPoints = 0;"]
    out += ["Mesh.MeshSizeFromCurvature = 0;", "General.NumThreads = 1;", "Geometry.Tolerance = 1e-12;"]
    size = {}
    for loop in loops:
        n = len(loop)
        for k, i in enumerate(loop):
            a, b, c = nodes[loop[k - 1]], nodes[i], nodes[loop[(k + 1) % n]]
            size[i] = 0.5 * (math.hypot(b[0] - a[0], b[1] - a[1]) + math.hypot(c[0] - b[0], c[1] - b[1]))
    for i in sorted(size):
        out.append(f"Point({i + 1}) = {{{nodes[i][0]!r}, {nodes[i][1]!r}, 0, {size[i]!r}}};")
    line_id = 0
    loop_lines = []
    for loop in loops:
        ids = []
        for k, i in enumerate(loop):
            line_id += 1
            out.append(f"Line({line_id}) = {{{i + 1}, {loop[(k + 1) % len(loop)] + 1}}};")
            ids.append(line_id)
        loop_lines.append(ids)
    out.append(f"Transfinite Curve {{1:{line_id}}} = 2;")
    for k, ids in enumerate(loop_lines):
        out.append(f"Curve Loop({k + 1}) = {{{', '.join(map(str, ids))}}};")
    surface = 0
    for a in range(len(loops)):
        if depth[a] % 2:
            continue
        holes = [b for b in range(len(loops)) if depth[b] == depth[a] + 1
                 and point_in_polygon(*polys[b][0], polys[a])]
        surface += 1
        out.append(f"Plane Surface({surface}) = {{{', '.join(str(k + 1) for k in [a] + holes)}}};")
    return "\n".join(out) + "\n"


def write_pos(points, triangles, values, name="q"):
    """A Gmsh post-processing view of scalar triangles (ST): the piecewise-linear field that takes
    values[i] at points[i] on the given triangles."""
    out = [f'View "{name}" {{']
    for a, b, c in triangles:
        (xa, ya), (xb, yb), (xc, yc) = points[a], points[b], points[c]
        out.append(f"ST({xa!r},{ya!r},0,{xb!r},{yb!r},0,{xc!r},{yc!r},0)"
                   f"{{{values[a]!r},{values[b]!r},{values[c]!r}}};")
    out.append("};")
    return "\n".join(out) + "\n"


def run_gmsh(gmsh, geo, msh):
    """Meshes geo in 2-D into msh (format 4.1). Returns (ok, Gmsh's output)."""
    proc = subprocess.run([gmsh, geo, "-2", "-format", "msh41", "-o", msh],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    return proc.returncode == 0, proc.stdout


def gmsh_version(gmsh):
    return subprocess.run([gmsh, "--version"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True).stdout.strip()
