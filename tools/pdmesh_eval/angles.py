"""Where a mesh's smallest angles are, and which of them an input corner forces: a mesh that keeps
an input vertex whose domain angle is below the target cannot beat that angle there, so the angles
at such vertices are judged apart from the rest."""

import math

from .meshfiles import corner_angles


def sharp_vertices(points, corners, target, tolerance):
    """{mesh point index: input corner angle} for every mesh point within `tolerance` of an input
    vertex whose domain angle is below `target` degrees."""
    sharp = [c for c in corners if c[2] < target]
    found = {}
    for i, (x, y) in enumerate(points):
        for cx, cy, angle in sharp:
            if abs(x - cx) <= tolerance and abs(y - cy) <= tolerance:
                found[i] = angle
    return found


def angle_report(points, triangles, corners, target=30.0):
    """The worst angle of the mesh and where it is, the worst angle away from sharp input corners
    (corners below `target`), and the triangles below `target` (all, and those that are below it
    away from sharp input corners)."""
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    tolerance = 1e-9 * math.hypot(max(xs) - min(xs), max(ys) - min(ys))
    sharp = sharp_vertices(points, corners, target, tolerance)
    worst = (math.inf, -1, -1)   # angle, triangle, vertex
    worst_away = (math.inf, -1, -1)
    below, below_away = 0, 0
    for t, tri in enumerate(triangles):
        angles = corner_angles(points, tri)
        k = min(range(3), key=lambda j: angles[j])
        if angles[k] < worst[0]:
            worst = (angles[k], t, tri[k])
        away = [(angles[j], tri[j]) for j in range(3) if tri[j] not in sharp]
        if away:
            a, v = min(away)
            if a < worst_away[0]:
                worst_away = (a, t, v)
            below_away += a < target
        below += angles[k] < target
    return {"min_angle": worst[0], "worst": describe(points, triangles, worst, sharp),
            "min_angle_away_from_sharp_corners": worst_away[0] if worst_away[1] >= 0 else None,
            "worst_away_from_sharp_corners": describe(points, triangles, worst_away, sharp),
            "triangles_below_target": below, "triangles_below_target_away_from_sharp_corners": below_away,
            "sharp_corner_vertices": len(sharp)}


def describe(points, triangles, worst, sharp):
    """A triangle as the report shows it: its angle, centroid, longest edge, the vertex of the
    angle, and the input corner angle there (None when the vertex is no sharp input corner)."""
    angle, t, v = worst
    if t < 0:
        return None
    tri = triangles[t]
    cx = sum(points[i][0] for i in tri) / 3
    cy = sum(points[i][1] for i in tri) / 3
    longest = max(math.dist(points[tri[k]], points[tri[(k + 1) % 3]]) for k in range(3))
    return {"angle": angle, "triangle": t, "centroid": [cx, cy], "longest_edge": longest,
            "vertex": list(points[v]), "input_corner_angle": sharp.get(v)}
