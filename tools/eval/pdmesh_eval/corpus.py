"""The user corpus (cases/user_corpus/) as the evaluation tools see it: each input read into a domain
(shapely polygons), embedded constraints (polylines) and embedded points, independently of pdmesh's
readers; a Gmsh .geo of that input with a free boundary (one compound curve per run of input points
between sharp corners, so Gmsh places its own boundary nodes) and the constraints embedded; and the
measures of a triangle mesh (min angle, share below 30 deg, mean aspect ratio, constraint edges
present). Needs numpy and shapely (tools/eval/setup_anchors.sh)."""

import json
import math
import os
import struct

import numpy as np

EARTH_RADIUS = 6371008.8  # metres; pdmesh's geometry.projection uses the same radius and centre
FARFIELD_SIDES = 128      # a polygon within 0.03 % of the far-field circle's radius


class Input:
    """One corpus input: kind ('airfoil', 'pslg', 'gis'), domain (shapely (Multi)Polygon),
    constraints [[(x, y)]], points [(x, y)], projection (lon0, lat0) or None, farfield
    (cx, cy, radius) or None, body (the airfoil's loop) or None."""

    def __init__(self, kind):
        self.kind, self.domain, self.constraints, self.points = kind, None, [], []
        self.projection, self.farfield, self.body = None, None, None


def read_text(path, errors="strict"):
    with open(path, errors=errors) as f:
        return f.read()


class Unsupported(Exception):
    """An input this module cannot read (a format or option the evaluation side lacks)."""


# ---------------------------------------------------------------------------------------------
# Readers


def read_selig(path):
    """The closed loop of a Selig-format airfoil file: a name line, then x y pairs (the first and
    last point at the trailing edge; a repeated closing point dropped)."""
    lines = [ln.split() for ln in read_text(path, errors="replace").splitlines()]
    pts = []
    for k, t in enumerate(lines[1:], 2):
        if not t:
            continue
        if len(t) != 2:
            raise Unsupported(f"{path}:{k}: not an x y pair (Lednicer files are not read here)")
        pts.append((float(t[0]), float(t[1])))
    if len(pts) > 2 and (pts[0][0] > 1.5 or pts[0][1] > 1.5):
        raise Unsupported(f"{path}: Lednicer format is not read here")
    if pts[0] == pts[-1]:
        pts.pop()
    return pts


def read_crv_loops(path):
    """pdmesh's point-count curve format (docs/geometry-input.md), each block a closed loop (its
    last point repeating its first); other .crv files are not read here."""
    rows = [ln.split() for ln in read_text(path).splitlines()]
    rows = [r for r in rows if r and not r[0].startswith("#")]
    loops, i = [], 0
    while i < len(rows):
        n = int(rows[i][0])
        pts = [(float(r[0]), float(r[1])) for r in rows[i + 1:i + 1 + n]]
        if pts[0] != pts[-1]:
            raise Unsupported(f"{path}: a curve that is not a closed loop is not read here")
        loops.append(pts[:-1])
        i += 1 + n
    return loops


def read_poly(path):
    """Triangle's .poly file: (vertices {index: (x, y)}, segments [(a, b)], hole points)."""
    rows = [ln.split("#")[0].split() for ln in read_text(path).splitlines()]
    rows = [r for r in rows if r]
    nv, _, nattr, nmark = (int(v) for v in rows[0][:4])
    vertices = {int(r[0]): (float(r[1]), float(r[2])) for r in rows[1:1 + nv]}
    i = 1 + nv
    ns = int(rows[i][0])
    segments = [(int(r[1]), int(r[2])) for r in rows[i + 1:i + 1 + ns]]
    i += 1 + ns
    holes = []
    if i < len(rows):
        nh = int(rows[i][0])
        holes = [(float(r[1]), float(r[2])) for r in rows[i + 1:i + 1 + nh]]
    return vertices, segments, holes


def poly_input(path, hull):
    """Triangle's semantics: the domain is what the segments enclose (with hull, the convex hull of
    all vertices), minus the faces that hold a hole point; segments inside the domain are embedded
    constraints, vertices on no segment embedded points."""
    from shapely.geometry import LineString, MultiPoint, Point
    from shapely.ops import polygonize, unary_union
    vertices, segments, holes = read_poly(path)
    lines = [LineString([vertices[a], vertices[b]]) for a, b in segments]
    if hull:
        lines.append(MultiPoint(list(vertices.values())).convex_hull.exterior)
    faces = [f for f in polygonize(unary_union(lines))
             if not any(f.contains(Point(h)) for h in holes)]
    if not faces:
        raise Unsupported(f"{path}: no closed region (a convex hull input needs geometry.hull)")
    domain = unary_union(faces)
    out = Input("pslg")
    out.domain = domain
    boundary = domain.boundary
    for a, b in segments:
        seg = LineString([vertices[a], vertices[b]])
        if seg.length > 0 and not boundary.buffer(1e-9 * seg.length).contains(seg) and domain.covers(seg):
            out.constraints.append([vertices[a], vertices[b]])
    used = {v for s in segments for v in s}
    out.points = [p for k, p in sorted(vertices.items())
                  if k not in used and domain.covers(Point(p)) and not boundary.intersects(Point(p))]
    out.constraints = merge_chains(out.constraints)
    return out


def merge_chains(segments):
    """Joins two-point segments into polylines at vertices where exactly two of them meet."""
    from collections import defaultdict
    ends = defaultdict(list)
    for k, (a, b) in enumerate(segments):
        ends[a].append(k)
        ends[b].append(k)
    used, chains = set(), []
    for k, (a, b) in enumerate(segments):
        if k in used:
            continue
        used.add(k)
        chain = [a, b]
        for forward in (True, False):
            while True:
                tip = chain[-1] if forward else chain[0]
                nxt = [j for j in ends[tip] if j not in used] if len(ends[tip]) == 2 else []
                if not nxt:
                    break
                used.add(nxt[0])
                s = segments[nxt[0]]
                other = s[1] if s[0] == tip else s[0]
                if forward:
                    chain.append(other)
                else:
                    chain.insert(0, other)
        chains.append(chain)
    return chains


def shapefile_rings(path):
    """Every ring of every Polygon record of a .shp file (shapefile whitepaper: clockwise outer
    rings, counter-clockwise holes)."""
    with open(path, "rb") as f:
        data = f.read()
    rings, pos = [], 100
    while pos < len(data):
        _, words = struct.unpack(">ii", data[pos:pos + 8])
        content = data[pos + 8:pos + 8 + 2 * words]
        pos += 8 + 2 * words
        if struct.unpack("<i", content[:4])[0] != 5:
            raise Unsupported(f"{path}: only Polygon records are read here")
        nparts, npoints = struct.unpack("<ii", content[36:44])
        parts = list(struct.unpack(f"<{nparts}i", content[44:44 + 4 * nparts])) + [npoints]
        xy = struct.unpack(f"<{2 * npoints}d", content[44 + 4 * nparts:44 + 4 * nparts + 16 * npoints])
        rings += [[(xy[2 * k], xy[2 * k + 1]) for k in range(parts[i], parts[i + 1])] for i in range(nparts)]
    return rings


def gis_input(paths):
    """GeoJSON and shapefile inputs: polygons make the domain (rings in the files' lon/lat),
    LineStrings embedded constraints, Points embedded points."""
    from shapely.geometry import MultiPolygon, Polygon, shape
    from shapely.ops import unary_union
    polys, lines, points = [], [], []
    for path in paths:
        if path.endswith(".shp"):
            rings = shapefile_rings(path)
            area = [0.5 * sum(a[0] * b[1] - b[0] * a[1] for a, b in zip(r, r[1:] + r[:1])) for r in rings]
            shells = [Polygon(r) for r, a in zip(rings, area) if a < 0]
            holes = [Polygon(r) for r, a in zip(rings, area) if a > 0]
            polys += [s.difference(unary_union([h for h in holes if s.contains(h)])) for s in shells]
            continue
        with open(path) as f:
            doc = json.load(f)
        features = doc["features"] if doc.get("type") == "FeatureCollection" else [doc]
        for feat in features:
            g = shape(feat["geometry"] if feat.get("type") == "Feature" else feat)
            for part in getattr(g, "geoms", [g]):
                if isinstance(part, (Polygon, MultiPolygon)):
                    polys.append(part)
                elif part.geom_type == "LineString":
                    lines.append(list(part.coords))
                elif part.geom_type == "Point":
                    points.append(part.coords[0])
    out = Input("gis")
    out.domain, out.constraints, out.points = unary_union(polys), lines, points
    return out


def project(inp):
    """geometry.projection = "equirectangular" as pdmesh does it: metres about the centre of the
    input's bounding box (lon0, lat0), x = R cos(lat0) (lon - lon0), y = R (lat - lat0)."""
    import shapely
    x0, y0, x1, y1 = inp.domain.bounds
    for c in inp.constraints:
        for x, y in c:
            x0, y0, x1, y1 = min(x0, x), min(y0, y), max(x1, x), max(y1, y)
    for x, y in inp.points:
        x0, y0, x1, y1 = min(x0, x), min(y0, y), max(x1, x), max(y1, y)
    inp.projection = (0.5 * (x0 + x1), 0.5 * (y0 + y1))
    f = lonlat_to_xy(inp.projection)
    inp.domain = shapely.transform(inp.domain, lambda xy: np.column_stack(f(xy[:, 0], xy[:, 1])))
    inp.constraints = [[tuple(map(float, f(x, y))) for x, y in c] for c in inp.constraints]
    inp.points = [tuple(map(float, f(x, y))) for x, y in inp.points]


def lonlat_to_xy(centre):
    lon0, lat0 = centre
    k = math.pi / 180.0
    return lambda lon, lat: (EARTH_RADIUS * math.cos(lat0 * k) * (lon - lon0) * k, EARTH_RADIUS * (lat - lat0) * k)


def read_input(case):
    """The Input of a corpus case (a dict from common.read_case)."""
    from shapely.geometry import Polygon
    geometry = case.get("geometry", {})
    files = [os.path.join(case["dir"], f) for f in geometry.get("files", [])]
    if not files:
        raise Unsupported("the case names no geometry file")
    ext = os.path.splitext(files[0])[1].lower()
    if ext == ".dat" or (ext == ".crv" and "farfield" in case):
        body = read_selig(files[0]) if ext == ".dat" else read_crv_loops(files[0])[0]
        inp = Input("airfoil")
        inp.body = body
        ff = case.get("farfield")
        if ff is None:
            inp.domain = Polygon(body)
        else:
            xs, ys = [p[0] for p in body], [p[1] for p in body]
            cx, cy = 0.5 * (min(xs) + max(xs)), 0.5 * (min(ys) + max(ys))
            r = ff["size"] * max(max(xs) - min(xs), max(ys) - min(ys))
            if ff.get("shape", "circle") == "circle":
                ring = [(cx + r * math.cos(2 * math.pi * k / FARFIELD_SIDES), cy + r * math.sin(2 * math.pi * k / FARFIELD_SIDES))
                        for k in range(FARFIELD_SIDES)]
            else:
                ring = [(cx - r, cy - r), (cx + r, cy - r), (cx + r, cy + r), (cx - r, cy + r)]
            inp.farfield = (cx, cy, r)
            inp.domain = Polygon(ring, [body])
        return inp
    if ext == ".poly":
        return poly_input(files[0], bool(geometry.get("hull", False)))
    if ext in (".geojson", ".json", ".shp"):
        inp = gis_input(files)
        if geometry.get("projection", "none") == "equirectangular":
            project(inp)
        return inp
    raise Unsupported(f"{files[0]}: no reader for '{ext}' here")


# ---------------------------------------------------------------------------------------------
# Gmsh


def polygons(domain):
    return list(getattr(domain, "geoms", [domain]))


def turn_deg(a, b, c):
    """How far the polyline a-b-c turns at b (0 straight on, 180 back)."""
    u = (b[0] - a[0], b[1] - a[1])
    v = (c[0] - b[0], c[1] - b[1])
    return abs(math.degrees(math.atan2(u[0] * v[1] - u[1] * v[0], u[0] * v[0] + u[1] * v[1])))


def write_free_geo(inp, corner_deg, background=None, size_max=None, algorithm=6):
    """A .geo of the input with a free boundary: one Gmsh point per input vertex, one line per input
    segment, and one Compound Curve per run of boundary vertices between breaks (corners turning by
    more than corner_deg, vertices where constraints meet the boundary), so Gmsh meshes each run as
    one curve and places its own nodes on it. Constraints are embedded lines (their input vertices
    kept), isolated points embedded points. background: a .pos view as the only size source."""
    from collections import Counter
    out = ["// Written by tools/eval/corpus_anchors.py: the input with a free boundary.",
           f"Mesh.Algorithm = {algorithm};", "General.NumThreads = 1;", "Geometry.Tolerance = 1e-12;",
           "Mesh.MeshSizeFromCurvature = 0;",
           # Gmsh meshes compound curves at half the size field by default (CompoundMeshSizeFactor
           # 0.5); 1 gives the boundary the size the field asks for, as on the other curves.
           "Mesh.CompoundMeshSizeFactor = 1;"]
    if background is not None:
        out += [f'Merge "{background}";', "Background Mesh View[0];",
                "Mesh.MeshSizeExtendFromBoundary = 0;", "Mesh.MeshSizeFromPoints = 0;"]
        if size_max is not None:
            out.append(f"Mesh.MeshSizeMax = {size_max!r};")
    else:
        out += ["Mesh.MeshSizeExtendFromBoundary = 1;", "Mesh.MeshSizeFromPoints = 1;"]
    ids = {}

    def point(p, size=0.0):
        if p not in ids:
            ids[p] = len(ids) + 1
            out.append(f"Point({ids[p]}) = {{{p[0]!r}, {p[1]!r}, 0, {size!r}}};")
        return ids[p]

    touch = Counter(p for c in inp.constraints for p in (c[0], c[-1]))
    line_id = [0]

    def line(a, b):
        line_id[0] += 1
        out.append(f"Line({line_id[0]}) = {{{point(a)}, {point(b)}}};")
        return line_id[0]

    surfaces, loop_id = [], 0
    for poly in polygons(inp.domain):
        loops = []
        for ring in [poly.exterior] + list(poly.interiors):
            pts = [tuple(map(float, p)) for p in ring.coords][:-1]
            n = len(pts)
            if background is None:  # Gmsh's own sizes: mean of the two segments at each vertex
                for k in range(n):
                    a, b, c = pts[k - 1], pts[k], pts[(k + 1) % n]
                    point(b, 0.5 * (math.dist(a, b) + math.dist(b, c)))
            breaks = [k for k in range(n) if touch[pts[k]] or turn_deg(pts[k - 1], pts[k], pts[(k + 1) % n]) > corner_deg]
            if not breaks:
                breaks = [0]
            lines = []
            for j, start in enumerate(breaks):
                end = breaks[(j + 1) % len(breaks)]
                run = []
                k = start
                while True:
                    run.append(line(pts[k], pts[(k + 1) % n]))
                    k = (k + 1) % n
                    if k == end:
                        break
                if len(run) > 1:
                    out.append(f"Compound Curve{{{', '.join(map(str, run))}}};")
                lines += run
            loop_id += 1
            out.append(f"Curve Loop({loop_id}) = {{{', '.join(map(str, lines))}}};")
            loops.append(loop_id)
        surfaces.append(len(surfaces) + 1)
        out.append(f"Plane Surface({surfaces[-1]}) = {{{', '.join(map(str, loops))}}};")
    for c in inp.constraints:
        s = which_surface(inp, c[len(c) // 2] if len(c) > 2 else ((c[0][0] + c[1][0]) / 2, (c[0][1] + c[1][1]) / 2))
        ls = [line(a, b) for a, b in zip(c, c[1:])]
        out.append(f"Curve{{{', '.join(map(str, ls))}}} In Surface{{{s}}};")
    for p in inp.points:
        s = which_surface(inp, p)
        out.append(f"Point{{{point(tuple(p))}}} In Surface{{{s}}};")
    return "\n".join(out) + "\n"


def which_surface(inp, p):
    from shapely.geometry import Point
    for k, poly in enumerate(polygons(inp.domain), 1):
        if poly.covers(Point(p)):
            return k
    return 1


def sharpest_corner(inp, mesh=None):
    """The smallest angle of the domain at an input vertex (degrees, measured on the domain side: a
    sharp trailing edge seen from the flow is about 345 deg), between boundary segments and, where
    embedded constraints meet a vertex, between any two segments there whose wedge lies in the
    domain: a mesh that keeps every input vertex and segment cannot have a larger minimum angle.
    mesh: (points, triangles) of a mesh of the input in the same plane: the boundary's corners are
    then the mesh's (sharpest_mesh_corner), those of the domain after pdmesh's healing, which may
    have removed the input's sharpest ones (a spike, an inlet)."""
    from shapely.geometry.polygon import orient
    best = 360.0
    rings = []
    for poly in polygons(inp.domain):
        poly = orient(poly, 1.0)  # the domain on the left of every ring
        for ring in [poly.exterior] + list(poly.interiors):
            pts = [tuple(p) for p in list(ring.coords)[:-1]]
            rings.append(pts)
            for k, b in enumerate(pts):
                a, c = pts[k - 1], pts[(k + 1) % len(pts)]
                u, v = (c[0] - b[0], c[1] - b[1]), (a[0] - b[0], a[1] - b[1])
                angle = math.degrees(math.atan2(u[0] * v[1] - u[1] * v[0], u[0] * v[0] + u[1] * v[1])) % 360.0
                best = min(best, angle)
    if mesh is not None:
        best = sharpest_mesh_corner(*mesh)
    return min(best, sharpest_constraint_wedge(inp, rings))


def sharpest_mesh_corner(points, triangles):
    """The smallest angle of a mesh's domain at a boundary vertex (degrees): the sum of the angles
    of its triangles at a vertex of an edge that only one triangle has (360 when there is none)."""
    p, t = used_mesh(points, triangles)
    if len(t) == 0:
        return 360.0
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    la, lb, lc = (np.linalg.norm(b - c, axis=1), np.linalg.norm(c - a, axis=1), np.linalg.norm(a - b, axis=1))

    def angle(u, v, w):  # at the vertex opposite w, between sides u and v
        return np.degrees(np.arccos(np.clip((u * u + v * v - w * w) / (2 * u * v), -1.0, 1.0)))

    total = np.zeros(len(p))
    with np.errstate(divide="ignore", invalid="ignore"):
        for k, at in enumerate((angle(lb, lc, la), angle(lc, la, lb), angle(la, lb, lc))):
            np.add.at(total, t[:, k], np.nan_to_num(at))
    edges = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    unique, count = np.unique(edges, axis=0, return_counts=True)
    boundary = np.unique(unique[count == 1])
    return float(total[boundary].min()) if len(boundary) else 360.0


def sharpest_constraint_wedge(inp, rings):
    """The smallest angle between consecutive segments around a vertex that a constraint touches,
    counting only wedges inside the domain (360 without constraints)."""
    from shapely.geometry import Point
    neighbours = {}

    def add(a, b):
        neighbours.setdefault(a, set()).add(b)
        neighbours.setdefault(b, set()).add(a)

    for c in inp.constraints:
        for a, b in zip(c, c[1:]):
            add(tuple(a), tuple(b))
    touched = set(neighbours)
    for pts in rings:
        for k, b in enumerate(pts):
            if b in touched:
                add(b, pts[k - 1])
                add(b, pts[(k + 1) % len(pts)])
    domain = polygons(inp.domain)
    best = 360.0
    for v in touched:
        angles = sorted(math.atan2(n[1] - v[1], n[0] - v[0]) for n in neighbours[v])
        reach = min(math.dist(v, n) for n in neighbours[v]) * 1e-3
        for k, lo in enumerate(angles):
            hi = angles[(k + 1) % len(angles)] + (2 * math.pi if k + 1 == len(angles) else 0.0)
            gap = math.degrees(hi - lo)
            mid = (lo + hi) / 2
            probe = Point(v[0] + reach * math.cos(mid), v[1] + reach * math.sin(mid))
            if gap < best and any(poly.covers(probe) for poly in domain):
                best = gap
    return best


# ---------------------------------------------------------------------------------------------
# Measures


def used_mesh(points, triangles):
    """(points as an array, triangles as an index array) keeping only the points triangles use."""
    tri = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    used = np.unique(tri)
    remap = np.full(len(points), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    return np.asarray(points, dtype=float)[used], remap[tri]


def measures(points, triangles):
    """{nodes, triangles, min_angle, share_below_30, mean_aspect_ratio}: angles in degrees, aspect
    ratio R/(2r) = l1 l2 l3 s / (8 A^2) as docs/quality.md defines it."""
    p, t = used_mesh(points, triangles)
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    la, lb, lc = (np.linalg.norm(b - c, axis=1), np.linalg.norm(c - a, axis=1), np.linalg.norm(a - b, axis=1))
    area = 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))

    def angle(u, v, w):  # at the vertex opposite w, between sides u and v
        return np.degrees(np.arccos(np.clip((u * u + v * v - w * w) / (2 * u * v), -1.0, 1.0)))

    with np.errstate(divide="ignore", invalid="ignore"):
        mins = np.minimum(np.minimum(angle(lb, lc, la), angle(lc, la, lb)), angle(la, lb, lc))
        s = 0.5 * (la + lb + lc)
        ar = np.where(area > 0, la * lb * lc * s / (8 * area * area), np.inf)
    return {"nodes": int(len(p)), "triangles": int(len(t)), "min_angle": float(np.nanmin(mins)) if len(t) else None,
            "share_below_30": float(np.mean(mins < 30.0)) if len(t) else None,
            "mean_aspect_ratio": float(np.mean(ar)) if len(t) else None}


def constraint_check(inp, points, triangles):
    """(present, missing): input constraint segments and embedded points present in the mesh. A
    segment is present when the mesh nodes on it (within 1e-9 of its length) include both ends and
    each consecutive pair along it is a mesh edge; a point when a mesh node is within 1e-9 of the
    domain's size of it."""
    p, t = used_mesh(points, triangles)
    edges = set()
    for a, b, c in t:
        for u, v in ((a, b), (b, c), (c, a)):
            edges.add((min(u, v), max(u, v)))
    x0, y0, x1, y1 = inp.domain.bounds
    scale = max(x1 - x0, y1 - y0)
    present = missing = 0
    for chain in inp.constraints:
        for a, b in zip(chain, chain[1:]):
            a, b = np.asarray(a, float), np.asarray(b, float)
            d = b - a
            L2 = float(d @ d)
            tol = 1e-9 * max(math.sqrt(L2), 1e-300) + 1e-12 * scale
            s = (p - a) @ d / L2
            dist = np.abs((p[:, 0] - a[0]) * d[1] - (p[:, 1] - a[1]) * d[0]) / math.sqrt(L2)
            on = np.where((dist <= tol) & (s >= -tol) & (s <= 1 + tol))[0]
            on = on[np.argsort(s[on])]
            ok = (len(on) >= 2 and np.linalg.norm(p[on[0]] - a) <= tol and np.linalg.norm(p[on[-1]] - b) <= tol
                  and all((min(u, v), max(u, v)) in edges for u, v in zip(on, on[1:])))
            present += ok
            missing += not ok
    for q in inp.points:
        ok = bool(len(p)) and float(np.min(np.linalg.norm(p - np.asarray(q, float), axis=1))) <= 1e-9 * scale
        present += ok
        missing += not ok
    return present, missing


# The Gmsh run, in a child Python (a crash or hang of Gmsh stays there): opens the .geo, meshes it in
# 2-D, writes .msh 4.1, and prints the wall time of the meshing alone.
GMSH_CHILD = """
import sys, time, gmsh
geo, msh = sys.argv[1], sys.argv[2]
gmsh.initialize(["gmsh", "-v", "2"])
gmsh.open(geo)
start = time.monotonic()
gmsh.model.mesh.generate(2)
seconds = time.monotonic() - start
gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
gmsh.write(msh)
print(f"mesh seconds: {seconds!r}")
gmsh.finalize()
"""


def run_gmsh_child(python, geo, msh, timeout):
    """Meshes geo into msh with Gmsh in a child process of python. Returns (seconds or None,
    message): the meshing's wall time, or None and the end of Gmsh's output on failure."""
    import re
    import subprocess
    try:
        proc = subprocess.run([python, "-c", GMSH_CHILD, geo, msh], stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, f"Gmsh ran past {timeout} s"
    m = re.search(r"^mesh seconds: (\S+)$", proc.stdout, re.M)
    if proc.returncode != 0 or m is None or not os.path.exists(msh):
        return None, proc.stdout[-1500:]
    return float(m.group(1)), proc.stdout
