#!/usr/bin/env python3
"""The periodic cell's effective conductivity with scikit-fem, on pdmesh's periodic mesh and on Gmsh's:

    tools/.venv-anchors/bin/python tools/eval/periodic_homogenization.py --python-path build/python --work W

The cell (examples/periodic_cell) is the unit square with three fibres as holes: a perforated medium,
conductivity 1 in the matrix and 0 in the fibres (insulating holes, natural boundary condition on the
fibres' curves). For each direction j the cell problem is: find chi_j periodic on the square's sides,
with zero value at one node, such that  int_Omega grad v . (grad chi_j + e_j) = 0  for every periodic
v; the effective tensor is  K_ij = (1/|Y|) int_Omega (e_i + grad chi_i) . (e_j + grad chi_j)  with
|Y| = 1 the cell's area (holes included). Periodicity is imposed by tying each image DOF to its source
DOF (a prolongation matrix over the pairs, chains such as the corners resolved by union-find).

Meshes:
  pdmesh:            `pdmesh.Case.from_toml(examples/periodic_cell/case.toml).run()` through the Python
                     API; P1, tied by `Mesh.periodic` (the pairs of mesh.msh's $Periodic, checked equal
                     to meshio's reading of the mesh.msh the same run writes);
  gmsh polygons:     Gmsh 4.15.2 on the same polygonal cell as pdmesh (cell.crv's polylines as lines),
                     the sizes of tools/eval/periodic_vs_gmsh.py (MeshSizeMax 0.025, fibre points
                     min(0.025, R x 10 deg), Frontal-Delaunay), setPeriodic right <- left and
                     top <- bottom; P1, tied by gmsh.model.mesh.getPeriodicNodes;
  gmsh circles:      tools/eval/periodic_vs_gmsh.py's own cell (true circles, four arcs per fibre): a
                     slightly different domain (the polygons are inscribed, within 6e-5 of the circles),
                     at its size 0.025 and at 1.09 x that (about pdmesh's node count);
  reference:         P2 on Gmsh periodic meshes of the polygonal cell and of the circles' cell at
                     uniform sizes --ref-sizes (default 0.01 0.005), DOFs tied by location; the finest
                     of each domain is its reference.
Each P1 mesh's own domain (its straight edges: the boundary nodes' chords) is also solved to
discretization accuracy (P2 on the mesh split twice into four), so that K - reference splits into the
P1 error on that mesh (d_fe) and the domain's difference (the chords at the mesh's boundary spacing).

Checks that stop the script (exit 1) rather than print a wrong table: every pair's image point is
A (source point) within 1e-9 (A the pair's affine matrix); the image DOFs of each link are exactly the
mesh's DOFs on the image side (x = 1 or y = 1) and the sources exactly those on the source side; the
solution's values agree on every paired node; pdmesh's pairs equal the mesh.msh file's; each P1
tensor is within 2 % of the reference. --break-pairs shifts pdmesh's pairs by one node along each
side, to see those checks fail. Exit 77 (ctest's skip) when gmsh, meshio, scikit-fem or the build's
pdmesh module cannot be imported."""

import argparse
import os
import sys
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.spatial import cKDTree

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CASE = os.path.join(REPO, "examples", "periodic_cell", "case.toml")
SIZE = 0.025
CURVATURE_DEG = 10.0
RELAX_SCALE = 1.09  # the best preset's spacing.relax_scale
FIBRES = [(0.28, 0.3, 0.17), (0.72, 0.6, 0.21), (0.25, 0.76, 0.1)]
SIDE_TOL = 1e-9  # a point within this of x = 1 (or y = 1) lies on the side
PAIR_TOL = 1e-9  # |A p_source - p_image| above this is a wrong pair
AGREE_REL = 0.02  # a P1 tensor entry farther than this from the reference (relative to K_xx) fails


class CheckFailed(Exception):
    pass


def require(ok, message):
    if not ok:
        raise CheckFailed(message)


# ---------------------------------------------------------------------------------------- solving


def tie_matrix(ndof, ties, pin):
    """P (ndof x nfree): column k is the free DOF k and every DOF tied to it; the DOF `pin`'s class is
    dropped (chi = 0 there, fixing the constant)."""
    parent = np.arange(ndof)

    def find(a):
        root = a
        while parent[root] != root:
            root = parent[root]
        while parent[a] != root:
            parent[a], a = root, parent[a]
        return root

    for image, source in ties:
        ri, rs = find(int(image)), find(int(source))
        if ri != rs:
            parent[max(ri, rs)] = min(ri, rs)
    roots = np.array([find(a) for a in range(ndof)])
    keep = np.unique(roots)
    keep = keep[keep != roots[pin]]
    column = -np.ones(ndof, dtype=np.int64)
    column[keep] = np.arange(len(keep))
    rows = np.nonzero(column[roots] >= 0)[0]
    return sp.csr_matrix((np.ones(len(rows)), (rows, column[roots[rows]])), shape=(ndof, len(keep))), roots


def effective_tensor(points, triangles, ties, order=1, refine=0):
    """K_eff of the perforated cell on this mesh (P1 or P2 Lagrange), and chi per direction. `ties`:
    (image DOF, source DOF) pairs; with ties=None they are found here by location. `refine`: the mesh
    split that many times into four first (the same straight-sided domain)."""
    import skfem
    from skfem.helpers import dot, grad

    mesh = skfem.MeshTri(np.ascontiguousarray(points.T, dtype=float), np.ascontiguousarray(triangles.T))
    if refine:
        mesh = mesh.refined(refine)
    element = skfem.ElementTriP1() if order == 1 else skfem.ElementTriP2()
    basis = skfem.Basis(mesh, element)
    if ties is None:
        ties = location_ties(basis.doflocs.T)

    @skfem.BilinearForm
    def laplace(u, v, _):
        return dot(grad(u), grad(v))

    @skfem.Functional
    def area(w):
        return 1.0 + 0.0 * w.x[0]

    K = laplace.assemble(basis)
    rhs = []
    for j in range(2):
        form = skfem.LinearForm(lambda v, _, j=j: -grad(v)[j])
        rhs.append(form.assemble(basis))
    P, roots = tie_matrix(basis.N, ties, pin=0)
    A = (P.T @ K @ P).tocsc()
    solve = spla.factorized(A)
    chi = [P @ solve(P.T @ f) for f in rhs]
    omega = area.assemble(basis)
    # K_ij = |Omega| delta_ij + int d_i chi_j + int d_j chi_i + chi_i^T K chi_j, and the cell problem
    # tested with chi_i gives chi_i^T K chi_j = -int d_j chi_i: K_ij = |Omega| delta_ij + int d_i chi_j,
    # where int d_i chi_j = -rhs_i . chi_j.
    keff = np.array([[omega * (i == j) - rhs[i] @ chi[j] for j in range(2)] for i in range(2)])
    for c in chi:
        require(np.array_equal(c[np.asarray([t[0] for t in ties])], c[np.asarray([t[1] for t in ties])]),
                "the solution differs on paired DOFs")
    return {"K": keff, "omega": omega, "dofs": basis.N, "free": A.shape[0], "nodes": len(points),
            "triangles": len(triangles), "chi": chi, "roots": roots}


def location_ties(doflocs):
    """(image, source) DOF pairs by location: a DOF on x = 1 with the DOF at (x - 1, y), on y = 1
    with the one at (x, y - 1); every image-side DOF must find its source."""
    tree = cKDTree(doflocs)
    ties = []
    for axis in range(2):
        shift = np.zeros(2)
        shift[axis] = 1.0
        image = np.nonzero(np.abs(doflocs[:, axis] - 1.0) < SIDE_TOL)[0]
        dist, source = tree.query(doflocs[image] - shift)
        require(np.all(dist < PAIR_TOL), f"a DOF on side {axis} has no source DOF (max distance {dist.max():.3g})")
        ties += list(zip(image, source))
    return ties


# ------------------------------------------------------------------------------------ pair checks


def check_links(points, links):
    """Each link: (image, source) point pairs and the affine matrix. The pairs map by the affine, and
    cover exactly the mesh points on the image side (and on the source side)."""
    for name, pairs, affine in links:
        image, source = points[pairs[:, 0]], points[pairs[:, 1]]
        mapped = source @ affine[:2, :2].T + affine[:2, 3]
        miss = np.max(np.linalg.norm(mapped - image, axis=1))
        require(miss <= PAIR_TOL, f"{name}: a pair's image point is {miss:.3g} from A (source point)")
        shift = affine[:2, 3]
        axis = int(np.argmax(np.abs(shift)))
        on_image = np.nonzero(np.abs(points[:, axis] - 1.0) < SIDE_TOL)[0]
        on_source = np.nonzero(np.abs(points[:, axis]) < SIDE_TOL)[0]
        require(np.array_equal(np.sort(pairs[:, 0]), on_image), f"{name}: the image nodes are not the side's nodes")
        require(np.array_equal(np.sort(pairs[:, 1]), on_source), f"{name}: the source nodes are not the side's nodes")


# ----------------------------------------------------------------------------------------- meshes


def pdmesh_cell(work, break_pairs):
    import meshio
    import pdmesh

    out = os.path.join(work, "pdmesh")
    start = time.perf_counter()
    mesh = pdmesh.Case.from_toml(CASE).run(device="host", out=out, formats=["msh"])
    seconds = time.perf_counter() - start
    points, triangles = np.array(mesh.points), np.array(mesh.triangles)
    links = [(f"{p.source} -> {p.image}", np.array(p.nodes), np.array(p.affine)) for p in mesh.periodic]
    require(len(links) == 2, f"expected 2 periodic links, got {len(links)}")
    # The same pairs as the run's mesh.msh, read by meshio (gmsh_periodic: node tags less one).
    written = meshio.read(os.path.join(out, "mesh.msh"))
    require(np.array_equal(written.points[:, :2], points), "mesh.msh's points differ from Mesh.points")
    from_file = [np.asarray(pairs) for _dim, _tags, _affine, pairs in written.gmsh_periodic]
    require(len(from_file) == len(links) and all(np.array_equal(a, b) for (_, a, _), b in zip(links, from_file)),
            "Mesh.periodic differs from mesh.msh's $Periodic")
    if break_pairs:
        # Each side's source nodes shifted by one position along the side: every pair off by a node.
        broken = []
        for name, pairs, affine in links:
            axis = int(np.argmax(np.abs(affine[:2, 3])))
            order = np.argsort(points[pairs[:, 1], 1 - axis])
            shifted = pairs.copy()
            shifted[order, 1] = pairs[np.roll(order, 1), 1]
            broken.append((name, shifted, affine))
        links = broken
    return points, triangles, links, seconds


def gmsh_mesh(gmsh):
    """Points, triangles (only the nodes the triangles use, renumbered) and the periodic curve links
    (image, source) of the current model's mesh."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    types, _, nodes = gmsh.model.mesh.getElements(2)
    tri_tags = np.array([n for t, n in zip(types, nodes) if int(t) == 2][0], dtype=np.int64).reshape(-1, 3)
    xyz = coords.reshape(-1, 3)[:, :2]
    used = np.unique(tri_tags)
    index = {int(t): k for k, t in enumerate(tags)}
    rows = np.array([index[int(t)] for t in used])
    renumber = {int(t): k for k, t in enumerate(used)}
    points = xyz[rows]
    triangles = np.vectorize(renumber.get)(tri_tags).astype(np.int32)
    links = []
    for dim, tag in gmsh.model.getEntities(1):
        master, slaves, masters, affine = gmsh.model.mesh.getPeriodicNodes(dim, tag)
        if master == tag or len(slaves) == 0:
            continue
        pairs = np.array([[renumber[int(s)], renumber[int(m)]] for s, m in zip(slaves, masters)], dtype=np.int64)
        links.append((f"gmsh curve {master} -> {tag}", pairs, np.asarray(affine).reshape(4, 4)))
    return points, triangles, links


def polygon_cell(gmsh, size, fibre_size):
    """The cell as pdmesh reads it (cell.crv's polylines) in Gmsh's built-in kernel, periodic."""
    import pdmesh

    geo_in = pdmesh.Geometry.from_file(os.path.join(os.path.dirname(CASE), "cell.crv"))
    curves = [np.asarray(c) for c in geo_in.curves.values()]  # bottom, right, top, left, the fibres
    gmsh.model.add("polygons")
    geo = gmsh.model.geo
    point_tags = {}

    def point(x, y, lc):
        key = (float(x), float(y))
        if key not in point_tags:
            point_tags[key] = geo.addPoint(key[0], key[1], 0, lc)
        return point_tags[key]

    # The sides as periodic_vs_gmsh.py gives them: each image side runs as its source does.
    corners = [point(x, y, size) for x, y in [(0, 0), (1, 0), (1, 1), (0, 1)]]
    bottom, right = geo.addLine(corners[0], corners[1]), geo.addLine(corners[1], corners[2])
    top, left = geo.addLine(corners[3], corners[2]), geo.addLine(corners[0], corners[3])
    loops = [geo.addCurveLoop([bottom, right, -top, -left])]
    for c in curves[4:]:
        centre = c[:-1].mean(axis=0)
        radius = min(FIBRES, key=lambda f: np.hypot(f[0] - centre[0], f[1] - centre[1]))[2]
        lc = fibre_size(radius)
        ring = c[:-1] if np.array_equal(c[0], c[-1]) else c
        tags = [point(x, y, lc) for x, y in ring]
        lines = [geo.addLine(tags[k], tags[(k + 1) % len(tags)]) for k in range(len(tags))]
        loops.append(geo.addCurveLoop(lines))
    geo.addPlaneSurface(loops)
    geo.synchronize()
    gmsh.model.mesh.setPeriodic(1, [right], [left], [1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1])
    gmsh.model.mesh.setPeriodic(1, [top], [bottom], [1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 0, 0, 0, 0, 1])
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.Algorithm", 6)
    start = time.perf_counter()
    gmsh.model.mesh.generate(2)
    seconds = time.perf_counter() - start
    mesh = gmsh_mesh(gmsh)
    gmsh.model.remove()
    return (*mesh, seconds)


def circle_cell(gmsh, work, size):
    """tools/eval/periodic_vs_gmsh.py's periodic cell (true circles) at this size."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import periodic_vs_gmsh

    out = os.path.join(work, f"gmsh_circles_{size:g}.msh")
    seconds = periodic_vs_gmsh.gmsh_cell(gmsh, True, out, size)
    gmsh.open(out)
    mesh = gmsh_mesh(gmsh)
    gmsh.model.remove()
    return (*mesh, seconds)


# ------------------------------------------------------------------------------------------- main


def domain_tensor(points, triangles):
    """K_eff of the mesh's own domain (its straight-sided boundary) to discretization accuracy: P2 on
    the mesh split twice into four, tied by location."""
    return effective_tensor(points, triangles, None, order=2, refine=2)["K"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--python-path", required=True, help="the build's python directory (build/python)")
    parser.add_argument("--work", required=True)
    parser.add_argument("--ref-sizes", type=float, nargs="+", default=[0.01, 0.005])
    parser.add_argument("--break-pairs", action="store_true", help="shift pdmesh's pairs by one node (must fail)")
    args = parser.parse_args()
    sys.path.insert(0, os.path.abspath(args.python_path))
    try:
        import gmsh
        import meshio  # noqa: F401
        import pdmesh  # noqa: F401
        import skfem  # noqa: F401
    except ImportError as e:
        # ctest's skip status: this interpreter lacks the anchors (tools/eval/setup_anchors.sh), or the
        # build's extension was made for another Python.
        print(f"periodic_homogenization: skipped: {e}", file=sys.stderr)
        return 77

    os.makedirs(args.work, exist_ok=True)
    gmsh.initialize(["gmsh", "-v", "2"])
    gmsh.option.setNumber("General.NumThreads", 1)
    rows = []  # (name, domain, result, the mesh's own domain's K or None, mesh seconds)

    def p1_row(name, domain, points, triangles, links, seconds):
        check_links(points, links)
        ties = [tuple(t) for _, pairs, _ in links for t in pairs]
        rows.append((name, domain, effective_tensor(points, triangles, ties), domain_tensor(points, triangles),
                     seconds))

    def curvature(r):
        return min(SIZE, r * np.radians(CURVATURE_DEG))

    try:
        p1_row("pdmesh", "polygons", *pdmesh_cell(args.work, args.break_pairs))
        p1_row("gmsh polygons", "polygons", *polygon_cell(gmsh, SIZE, curvature))
        p1_row("gmsh circles", "circles", *circle_cell(gmsh, args.work, SIZE))
        # At the size pdmesh relaxes its nodes at (about pdmesh's node count).
        p1_row(f"gmsh circles {RELAX_SCALE}x", "circles", *circle_cell(gmsh, args.work, SIZE * RELAX_SCALE))
        for h in args.ref_sizes:
            points, triangles, links, seconds = polygon_cell(gmsh, h, lambda r, h=h: h)
            check_links(points, links)
            rows.append((f"ref polygons h={h:g}", "polygons", effective_tensor(points, triangles, None, order=2),
                         None, seconds))
            points, triangles, links, seconds = circle_cell(gmsh, args.work, h)
            check_links(points, links)
            rows.append((f"ref circles h={h:g}", "circles", effective_tensor(points, triangles, None, order=2),
                         None, seconds))
    except CheckFailed as e:
        print(f"periodic_homogenization: check failed: {e}", file=sys.stderr)
        return 1
    finally:
        gmsh.finalize()
    # The finest reference of each domain.
    reference = {r[1]: r[2]["K"] for r in rows if r[0].startswith("ref")}
    print("effective conductivity of examples/periodic_cell (matrix 1, fibres 0), P1 on the meshes, P2 on the "
          f"references; d = K - the finest reference of the same domain ({', '.join(reference)}); "
          "d_fe = K - the same mesh's domain to discretization accuracy (P2, split twice)")
    print(f"{'mesh':<20} {'domain':<8} {'nodes':>6} {'tris':>6} {'dofs':>7} {'area':>9} {'K_xx':>9} {'K_yy':>9} "
          f"{'K_xy':>9} {'d_xx':>9} {'d_yy':>9} {'d_xy':>9} {'d_fe_xx':>9} {'d_fe_yy':>9} {'mesh s':>6}")
    failed = False
    for name, domain, r, own, secs in rows:
        K = r["K"]
        d = K - reference[domain]
        fe = (K - own) if own is not None else np.full((2, 2), np.nan)
        print(f"{name:<20} {domain:<8} {r['nodes']:>6} {r['triangles']:>6} {r['dofs']:>7} {r['omega']:>9.6f} "
              f"{K[0, 0]:>9.6f} {K[1, 1]:>9.6f} {K[0, 1]:>9.6f} {d[0, 0]:>9.2e} {d[1, 1]:>9.2e} {d[0, 1]:>9.2e} "
              f"{fe[0, 0]:>9.2e} {fe[1, 1]:>9.2e} {secs:>6.2f}")
        if np.max(np.abs(d)) > AGREE_REL * reference[domain][0, 0]:
            print(f"periodic_homogenization: {name}: the tensor is more than {AGREE_REL:.0%} off the reference",
                  file=sys.stderr)
            failed = True
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
