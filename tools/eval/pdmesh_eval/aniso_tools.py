"""The anisotropic anchors run on issue 37's cases: mmg2d (PyPI mmgpy's mmg2d_O3 binary), BAMG inside
FreeFem++ (Debian freefem++) and Gmsh 4.15.2's BAMG (algorithm 7) with a MathEvalAniso field; Medit
.mesh/.sol files; initial meshes. Each runner returns (points, triangles, wall seconds) as numpy
arrays. Used by tools/eval/aniso_anchors.py; needs numpy (and gmsh for run_gmsh)."""

import os
import re
import subprocess
import tempfile
import time

import numpy as np

from . import metric as mt

CASES = ("linear", "polar-1", "polar-2")
METRICS = {"linear": mt.linear_metric, "polar-1": mt.polar1_metric, "polar-2": mt.polar2_metric}
DOMAIN = {"linear": "square", "polar-1": "square-minus-disc", "polar-2": "square-minus-disc"}


def complexity(case):
    """C of a case: tensor Gauss-Legendre on the square, or in polar coordinates on the square minus
    the disc (metric.complexity_square, metric.complexity_square_minus_disc)."""
    if DOMAIN[case] == "square":
        return float(mt.complexity_square(METRICS[case]))
    return float(mt.complexity_square_minus_disc(METRICS[case]))


# ---- Medit files ----------------------------------------------------------------------------------

def read_medit(path):
    """Vertices (N, 2) and triangles (T, 3, 0-based) of an ASCII Medit .mesh file (as mmg2d and
    FreeFem++'s savemesh write it)."""
    with open(path) as f:
        tokens = f.read().split()
    try:
        dim = int(tokens[tokens.index("Dimension") + 1])
        i = tokens.index("Vertices")
        n = int(tokens[i + 1])
        v = np.array(tokens[i + 2:i + 2 + n * (dim + 1)], float).reshape(n, dim + 1)[:, :2]
        i = tokens.index("Triangles")
        n = int(tokens[i + 1])
        t = np.array(tokens[i + 2:i + 2 + 4 * n], int).reshape(n, 4)[:, :3] - 1
    except (ValueError, IndexError) as e:
        raise ValueError(f"{path}: not an ASCII 2-D Medit mesh with Vertices and Triangles ({e})") from e
    return v, t


def write_medit(path, points, triangles, boundary_edges=(), corners=()):
    with open(path, "w") as f:
        f.write(f"MeshVersionFormatted 2\nDimension 2\nVertices\n{len(points)}\n")
        f.write("".join(f"{x:.17g} {y:.17g} 0\n" for x, y in np.asarray(points, float).tolist()))
        f.write(f"Triangles\n{len(triangles)}\n")
        f.write("".join(f"{a + 1} {b + 1} {c + 1} 0\n" for a, b, c in np.asarray(triangles, int).tolist()))
        if len(boundary_edges):
            f.write(f"Edges\n{len(boundary_edges)}\n")
            f.write("".join(f"{a + 1} {b + 1} {ref}\n" for a, b, ref in boundary_edges))
        if len(corners):
            f.write(f"Corners\n{len(corners)}\n" + "".join(f"{int(c) + 1}\n" for c in corners))
        f.write("End\n")


def write_sol(path, metric_values):
    """mmg's .sol of a tensor metric at the vertices (type 3: m11 m12 m22)."""
    with open(path, "w") as f:
        f.write(f"MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n{len(metric_values)}\n1 3\n")
        f.write("".join(f"{a:.17g} {b:.17g} {c:.17g}\n" for a, b, c in np.asarray(metric_values, float).tolist()))
        f.write("End\n")


def read_mesh_file(path):
    """A triangle mesh from .mesh (Medit), .msh (Gmsh ASCII 2.2/4.1) or ASCII .vtu."""
    if path.endswith(".mesh"):
        return read_medit(path)
    if path.endswith(".msh"):
        from .meshfiles import read_msh
        p, t = read_msh(path)
        return np.array(p, float), np.array(t, int)
    if path.endswith(".vtu"):
        with open(path) as f:
            text = f.read()
        pts = re.search(r"<Points>\s*<DataArray([^>]*)>(.*?)</DataArray>", text, re.S)
        con = re.search(r'<DataArray([^>]*Name="connectivity"[^>]*)>(.*?)</DataArray>', text, re.S)
        if not pts or not con:
            raise ValueError(f"{path}: no Points or connectivity array")
        p = _vtu_values(path, text, *pts.groups()).reshape(-1, 3)[:, :2]
        return p, _vtu_values(path, text, *con.groups()).astype(np.int64).reshape(-1, 3)
    raise ValueError(f"{path}: unknown mesh format (use .mesh, .msh or .vtu)")


_VTU_TYPES = {"Float64": "<f8", "Float32": "<f4", "Int64": "<i8", "Int32": "<i4", "UInt64": "<u8",
              "UInt32": "<u4"}


def _vtu_values(path, text, attributes, body):
    """One inline DataArray of a .vtu as a flat numpy array: ASCII, or binary (base64 of a UInt64
    byte count and the little-endian data, uncompressed, as pdmesh writes it)."""
    import base64
    kind = re.search(r'type="(\w+)"', attributes)
    if 'format="ascii"' in attributes:
        return np.array(body.split(), float)
    if ('format="binary"' not in attributes or "compressor=" in text or 'header_type="UInt64"' not in text
            or 'byte_order="BigEndian"' in text or not kind or kind.group(1) not in _VTU_TYPES):
        raise ValueError(f"{path}: only ASCII or uncompressed little-endian binary .vtu arrays "
                         "(header_type UInt64) are read; write .msh instead")
    raw = base64.b64decode("".join(body.split()))
    count = int(np.frombuffer(raw[:8], "<u8")[0])
    return np.frombuffer(raw[8:8 + count], _VTU_TYPES[kind.group(1)]).astype(float)


# ---- initial meshes ------------------------------------------------------------------------------

def grid_mesh(n):
    """The unit square as an n x n grid of squares cut into two triangles each, with its boundary
    edges (ref 1..4 per side) and corners."""
    s = np.linspace(0.0, 1.0, n + 1)
    x, y = np.meshgrid(s, s)
    pts = np.column_stack([x.ravel(), y.ravel()])
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    tri = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    sides = [idx[0, :], idx[:, -1], idx[-1, ::-1], idx[::-1, 0]]
    edges = [(int(s_[k]), int(s_[k + 1]), ref + 1) for ref, s_ in enumerate(sides) for k in range(n)]
    return pts, tri, edges, [idx[0, 0], idx[0, -1], idx[-1, -1], idx[-1, 0]]


def quarter_annulus_mesh(n_theta=40, n_r=16, radius=0.5):
    """[0,1]² minus the disc r < radius: the polar grid θ ∈ [0, π/2] (n_theta even, so that the
    corner (1,1) is a vertex), r from the wall to the square's edge, cut into triangles; boundary
    edges with refs 1 (wall), 2 (y = 0), 3 (outer edges x = 1, y = 1), 4 (x = 0)."""
    th = np.linspace(0.0, np.pi / 2, n_theta + 1)
    rmax = 1.0 / np.maximum(np.cos(th), np.sin(th))
    u = np.linspace(0.0, 1.0, n_r + 1)
    r = radius + np.outer(rmax - radius, u)                      # (θ, r)
    pts = np.column_stack([(r * np.cos(th)[:, None]).ravel(), (r * np.sin(th)[:, None]).ravel()])
    pts[np.abs(pts) < 1e-15] = 0.0
    pts[np.abs(pts - 1.0) < 1e-12] = 1.0
    idx = np.arange((n_theta + 1) * (n_r + 1)).reshape(n_theta + 1, n_r + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    tri = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    loops = [(idx[::-1, 0], 1), (idx[0, :], 2), (idx[:, -1], 3), (idx[-1, ::-1], 4)]
    edges = [(int(v[k]), int(v[k + 1]), ref) for v, ref in loops for k in range(len(v) - 1)]
    corners = [idx[0, 0], idx[0, -1], idx[n_theta // 2, -1], idx[-1, -1], idx[-1, 0]]
    return pts, tri, edges, corners


def initial_mesh(domain, wall_segments=160):
    """mmg2d's first mesh: a 20 x 20 grid, or the quarter annulus with `wall_segments` wall segments
    (a coarser wall polyline changes mmg2d's polar Q_min several-fold: docs/anisotropy-anchors.md)."""
    return grid_mesh(20) if domain == "square" else quarter_annulus_mesh(n_theta=wall_segments)


# ---- mmg2d ---------------------------------------------------------------------------------------

def mmg2d_binary():
    import shutil
    import sys
    here = os.path.join(os.path.dirname(sys.executable), "mmg2d_O3")
    return here if os.path.exists(here) else shutil.which("mmg2d_O3")


MMG_OPTIONS = ["-hgrad", "-1", "-hausd", "0.001", "-v", "-1"]


def run_mmg2d(start, metric, passes=5, options=MMG_OPTIONS):
    """mmg2d adaptation as its users iterate it: pass k writes the mesh of pass k − 1 with the metric
    evaluated at its vertices (.sol), runs mmg2d_O3 and reads the result. The wall time covers every
    pass (process start and file I/O included)."""
    binary = mmg2d_binary()
    if not binary:
        raise RuntimeError("mmg2d_O3 not found (tools/eval/setup_anchors.sh installs it)")
    pts, tri, edges, corners = start
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        src, sol, out = (os.path.join(tmp, n) for n in ("in.mesh", "in.sol", "out.mesh"))
        write_medit(src, pts, tri, edges, corners)
        for k in range(passes):
            if k > 0:
                os.replace(out, src)
                pts, tri = read_medit(src)
            write_sol(sol, metric(pts))
            subprocess.run([binary, "-in", src, "-sol", sol, "-out", out, *options], check=True,
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        pts, tri = read_medit(out)
    return pts, tri, time.perf_counter() - t0


# ---- BAMG inside FreeFem++ -----------------------------------------------------------------------

# The cases' metrics in FreeFem++'s language (the same formulas as metric.py, which judges the result).
FREEFEM_METRIC = {
    "linear": "func h1 = 0.1; func h2 = 0.001 + 0.198*abs(y - 0.5);\n"
              "func m11 = 1/h1^2; func m12 = 0.; func m22 = 1/h2^2;\n",
    "polar-1": "func r = sqrt(x^2 + y^2); func hr = 0.001 + 0.198*abs(r - 0.5); func ht = 0.1;\n",
    "polar-2": "func r = sqrt(x^2 + y^2); func hr = 0.001 + 0.198*abs(r - 0.5);\n"
               "func d = 10*(0.6 - r); func ht = (d >= 0)*(d/40 + (1 - d)/10) + (d < 0)*0.1;\n",
}
FREEFEM_POLAR = ("func c = x/r; func s = y/r; func a = 1/hr^2; func b = 1/ht^2;\n"
                 "func m11 = a*c^2 + b*s^2; func m12 = (a - b)*c*s; func m22 = a*s^2 + b*c^2;\n")
FREEFEM_DOMAIN = {
    "square": "mesh Th = square(1, 1);\n",
    "square-minus-disc": (
        "border bot(t=0.5, 1){x=t; y=0; label=2;}\n"
        "border rig(t=0, 1){x=1; y=t; label=3;}\n"
        "border top(t=0, 1){x=1-t; y=1; label=3;}\n"
        "border lef(t=0, 0.5){x=0; y=1-t; label=4;}\n"
        "border wall(t=0, pi/2){x=0.5*cos(pi/2-t); y=0.5*sin(pi/2-t); label=1;}\n"
        "mesh Th = buildmesh(bot(10) + rig(20) + top(20) + lef(10) + wall(16));\n"),
}


def run_bamg(case, passes=5):
    """BAMG through FreeFem++'s adaptmesh, one FreeFem++ process: pass k interpolates the metric on
    the mesh of pass k − 1 (P1) and adapts to it (IsMetric=1, ratio=0: no gradation). The wall time
    is the whole process."""
    body = FREEFEM_DOMAIN[DOMAIN[case]] + FREEFEM_METRIC[case]
    if case != "linear":
        body += FREEFEM_POLAR
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.mesh")
        body += (f"for (int k = 0; k < {passes}; ++k) {{\n"
                 "  fespace Vh(Th, P1); Vh n11 = m11, n12 = m12, n22 = m22;\n"
                 "  Th = adaptmesh(Th, [n11, n12, n22], IsMetric=1, nbvx=2000000, hmin=1e-7, hmax=1,"
                 " ratio=0, anisomax=1e8, err=1);\n}\n"
                 f'savemesh(Th, "{out}");\n')
        script = os.path.join(tmp, "adapt.edp")
        with open(script, "w") as f:
            f.write(body)
        t0 = time.perf_counter()
        subprocess.run(["FreeFem++", "-nw", "-ne", "-v", "0", script], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        wall = time.perf_counter() - t0
        pts, tri = read_medit(out)
    return pts, tri, wall


# ---- Gmsh 4.15.2, algorithm 7 (BAMG) with MathEvalAniso ------------------------------------------

GMSH_METRIC = {
    "linear": ("100", "0", "1/((0.001+0.198*Fabs(y-0.5))*(0.001+0.198*Fabs(y-0.5)))"),
}
_R = "Sqrt(x*x+y*y)"
_HR = f"(0.001+0.198*Fabs({_R}-0.5))"
_HT = {"polar-1": "(0.1)",
       # h_t = 0.1 − 0.075·max(d, 0), d = 10(0.6 − r): polar-2's grading without a conditional
       "polar-2": f"(0.1-0.075*0.5*(10*(0.6-{_R})+Fabs(10*(0.6-{_R}))))"}
for _case, _ht in _HT.items():
    _a, _b = f"(1/({_HR}*{_HR}))", f"(1/({_ht}*{_ht}))"
    GMSH_METRIC[_case] = (f"({_a}*x*x+{_b}*y*y)/(x*x+y*y)", f"({_a}-{_b})*x*y/(x*x+y*y)",
                          f"({_a}*y*y+{_b}*x*x)/(x*x+y*y)")


def run_gmsh(case):
    """Gmsh 4.15.2 in this process: the domain (the wall a circle arc), a MathEvalAniso background
    field of the case's metric, Mesh.Algorithm = 7 (BAMG), sizes from the field only. The wall time
    covers the model, the meshing and reading the nodes back."""
    import gmsh
    t0 = time.perf_counter()
    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        g = gmsh.model.geo
        if DOMAIN[case] == "square":
            p = [g.addPoint(*c, 0) for c in ((0, 0), (1, 0), (1, 1), (0, 1))]
            loop = g.addCurveLoop([g.addLine(p[k], p[(k + 1) % 4]) for k in range(4)])
        else:
            o = g.addPoint(0, 0, 0)
            p = [g.addPoint(*c, 0) for c in ((0.5, 0), (1, 0), (1, 1), (0, 1), (0, 0.5))]
            lines = [g.addLine(p[k], p[k + 1]) for k in range(4)]
            loop = g.addCurveLoop(lines + [g.addCircleArc(p[4], o, p[0])])
        g.addPlaneSurface([loop])
        g.synchronize()
        f = gmsh.model.mesh.field.add("MathEvalAniso")
        for name, expr in zip(("M11", "M12", "M22"), GMSH_METRIC[case]):
            gmsh.model.mesh.field.setString(f, name, expr)
        for name, expr in (("M13", "0"), ("M23", "0"), ("M33", "1")):
            gmsh.model.mesh.field.setString(f, name, expr)
        gmsh.model.mesh.field.setAsBackgroundMesh(f)
        for name, value in (("Mesh.Algorithm", 7), ("Mesh.MeshSizeExtendFromBoundary", 0),
                            ("Mesh.MeshSizeFromPoints", 0), ("Mesh.MeshSizeFromCurvature", 0),
                            ("Mesh.AnisoMax", 1e10)):
            gmsh.option.setNumber(name, value)
        gmsh.model.mesh.generate(2)
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        types, _, conn = gmsh.model.mesh.getElements(2)
        tri_tags = np.concatenate([c for ty, c in zip(types, conn) if ty == 2]).astype(np.int64)
    finally:
        gmsh.finalize()
    index = np.zeros(int(tags.max()) + 1, np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    pts = xyz.reshape(-1, 3)[:, :2].copy()
    tri = index[tri_tags].reshape(-1, 3)
    used = np.unique(tri)                     # drop the arc's centre and other unmeshed points
    remap = np.full(len(pts), -1, np.int64)
    remap[used] = np.arange(len(used))
    return pts[used], remap[tri], time.perf_counter() - t0


def version(command):
    try:
        out = subprocess.run(command, capture_output=True, text=True, timeout=30)
        return (out.stdout + out.stderr).strip().splitlines()[0] if (out.stdout + out.stderr).strip() else "?"
    except (OSError, subprocess.TimeoutExpired):
        return "not found"


def tanh_error(points, triangles):
    """e_L2 and e_max of the tanh layer's P1 interpolant, and e_L2·N_v."""
    e2, emax = mt.interpolation_error(points, triangles, mt.tanh_u)
    return {"vertices": int(len(points)), "triangles": int(len(triangles)), "e_L2": e2, "e_max": emax,
            "e_L2_times_Nv": e2 * len(points)}


def uniform_reference(n):
    """The tanh layer's error on the n x n grid (the uniform reference)."""
    pts, tri, _, _ = grid_mesh(n)
    return tanh_error(pts, tri)

