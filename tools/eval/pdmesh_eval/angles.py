"""Where a mesh's smallest angles are, and which of them an input corner forces: a mesh that keeps
an input vertex whose domain angle is below the target cannot beat that angle there, so the angles
at such vertices are judged apart from the rest."""

import math

from .meshfiles import corner_angles


class PointLookup:
    """Values at points, found again within a tolerance: Gmsh writes coordinates with 16
    significant digits, so its copy of a boundary node is not always bit-identical."""

    def __init__(self, items, tolerance):
        self.tolerance = tolerance
        self.cells = {}
        for (x, y), value in items:
            self.cells.setdefault(self.key(x, y), []).append((x, y, value))

    def key(self, x, y):
        return (math.floor(x / self.tolerance), math.floor(y / self.tolerance))

    def get(self, x, y):
        kx, ky = self.key(x, y)
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for px, py, value in self.cells.get((kx + dx, ky + dy), ()):
                    if abs(px - x) <= self.tolerance and abs(py - y) <= self.tolerance:
                        return value
        return None


def angle_report(points, triangles, corners, target=30.0, boundary=()):
    """The worst angle of the mesh and where it is, the worst angle away from sharp input corners
    (corners below `target`), and the triangles below `target` (all, and those that are below it
    away from sharp input corners). `boundary`: the boundary node coordinates, so that the worst
    triangles say how many of their vertices lie on the boundary."""
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    tolerance = 1e-9 * math.hypot(max(xs) - min(xs), max(ys) - min(ys))
    corner_lookup = PointLookup([((x, y), a) for x, y, a in corners if a < target], tolerance)
    sharp = {}
    for i, (x, y) in enumerate(points):
        angle = corner_lookup.get(x, y)
        if angle is not None:
            sharp[i] = angle
    on_boundary = PointLookup([(p, True) for p in boundary], tolerance)
    boundary_points = {i for i, (x, y) in enumerate(points) if on_boundary.get(x, y)}
    worst = (math.inf, -1, -1)   # angle, triangle, vertex
    worst_away = (math.inf, -1, -1)
    worst_interior = math.inf     # over triangles with a vertex off the boundary
    below, below_away = 0, 0
    for t, tri in enumerate(triangles):
        angles = corner_angles(points, tri)
        k = min(range(3), key=lambda j: angles[j])
        if angles[k] < worst[0]:
            worst = (angles[k], t, tri[k])
        if angles[k] < worst_interior and any(i not in boundary_points for i in tri):
            worst_interior = angles[k]
        away = [(angles[j], tri[j]) for j in range(3) if tri[j] not in sharp]
        if away:
            a, v = min(away)
            if a < worst_away[0]:
                worst_away = (a, t, v)
            below_away += a < target
        below += angles[k] < target
    return {"min_angle": worst[0], "worst": describe(points, triangles, worst, sharp, boundary_points),
            "min_angle_away_from_sharp_corners": worst_away[0] if worst_away[1] >= 0 else None,
            "worst_away_from_sharp_corners": describe(points, triangles, worst_away, sharp, boundary_points),
            "min_angle_with_interior_vertex": worst_interior if worst_interior < math.inf else None,
            "triangles_below_target": below, "triangles_below_target_away_from_sharp_corners": below_away,
            "sharp_corner_vertices": len(sharp)}


def describe(points, triangles, worst, sharp, boundary_points):
    """A triangle as the report shows it: its angle, centroid, longest edge, how many of its
    vertices are boundary nodes, the vertex of the angle, and the input corner angle there (None
    when the vertex is no sharp input corner)."""
    angle, t, v = worst
    if t < 0:
        return None
    tri = triangles[t]
    cx = sum(points[i][0] for i in tri) / 3
    cy = sum(points[i][1] for i in tri) / 3
    longest = max(math.dist(points[tri[k]], points[tri[(k + 1) % 3]]) for k in range(3))
    return {"angle": angle, "triangle": t, "centroid": [cx, cy], "longest_edge": longest,
            "boundary_vertices": sum(1 for i in tri if i in boundary_points),
            "vertices": [list(points[i]) for i in tri],
            "vertex": list(points[v]), "input_corner_angle": sharp.get(v)}


def has_triangle(points, triangles, vertices):
    """Whether the mesh has a triangle with these three vertices (found within a tolerance)."""
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    tolerance = 1e-9 * math.hypot(max(xs) - min(xs), max(ys) - min(ys))
    wanted = PointLookup([(tuple(v), k) for k, v in enumerate(vertices)], tolerance)
    for tri in triangles:
        found = {wanted.get(*points[i]) for i in tri}
        if found == {0, 1, 2}:
            return True
    return False
