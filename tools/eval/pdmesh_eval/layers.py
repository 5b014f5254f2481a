"""Boundary-layer measures of a mesh, whatever made it (issue 38; ../shared/notes/anisotropy.md §1):
the same numbers for pdmesh's layers and for Gmsh's BoundaryLayer field.

The mesh is points, triangles and quads; the walls are polylines. Nothing about how the layers were
built is read from the mesh: wall nodes are the points on a wall, the first cells are the cells on a
wall edge, and the columns are walked from each wall node along the mesh edge best aligned with the
wall normal, as a user's evaluator would.

- first height: the heights of a wall cell's other corners over its wall edge; a cell is within
  ±2 % when every such height is;
- growth: (d_{k+1} - d_k) / (d_k - d_{k-1}) along each column, d the distance to the nearest wall,
  up to and including the first node beyond `thickness` (so the junction with the core counts);
- angles: the largest cell angle and the count above 150 degrees (quads by their four corners);
- core: the smallest angle of the triangles with no corner within `thickness` of a wall;
- fan: the cells around the wall node where the wall turns most sharply (a trailing edge);
- thickness jumps (given which cells are the layer's): at both ends of a wall edge, the layer
  thickness is the wall distance of the last node of the column (started along the edge's normal,
  so at a fan corner the fan's ray next to the edge) that is still a corner of a layer cell, and
  the edge's jump is the ratio of the two (largest over smallest); the largest jump
  and the share above 1.3 overall and per region (boxes; an edge is in a box when its midpoint is)."""

import math

import numpy as np


def wall_distance(points, segments, chunk=4096):
    """Distance from each point (N, 2) to the nearest of the segments (W, 2, 2)."""
    a, b = segments[:, 0, :], segments[:, 1, :]
    ab = b - a
    length2 = np.maximum((ab * ab).sum(axis=1), 1e-300)
    out = np.empty(len(points))
    for start in range(0, len(points), chunk):
        p = points[start:start + chunk, None, :]
        t = np.clip(((p - a) * ab).sum(axis=2) / length2, 0.0, 1.0)
        d = p - (a + t[..., None] * ab)
        out[start:start + chunk] = np.sqrt((d * d).sum(axis=2)).min(axis=1)
    return out


def cell_angles(points, cell):
    """The corner angles (degrees) of a triangle or quad given by point indices in order."""
    n = len(cell)
    out = []
    for k in range(n):
        p, prev, nxt = points[cell[k]], points[cell[k - 1]], points[cell[(k + 1) % n]]
        u, v = prev - p, nxt - p
        out.append(math.degrees(math.atan2(abs(u[0] * v[1] - u[1] * v[0]), u @ v)))
    return out


def _percentile(values, q):
    return float(np.percentile(values, q)) if len(values) else float("nan")


def layer_measures(points, triangles, quads, wall_segments, first_height, thickness, min_cos=0.7,
                   layer_cells=None, regions=None):
    """The measures as a dict. points (N, 2); triangles, quads: lists of index tuples; wall_segments
    (W, 2, 2); first_height and thickness: the layer settings asked for. layer_cells: a bool per
    cell (the triangles, then the quads) saying which are the layer's (None: no thickness jumps);
    regions: {name: (x0, y0, x1, y1)} for the jumps per region."""
    points = np.asarray(points, dtype=float)
    segments = np.asarray(wall_segments, dtype=float)
    cells = [tuple(c) for c in triangles] + [tuple(c) for c in quads]
    scale = float(np.ptp(points, axis=0).max())
    on_wall_tol = max(1e-3 * first_height, 1e-12 * scale)
    d = wall_distance(points, segments)
    wall = d < on_wall_tol

    neighbours = [set() for _ in range(len(points))]
    cells_of_edge = {}
    for ci, c in enumerate(cells):
        for k in range(len(c)):
            i, j = c[k], c[(k + 1) % len(c)]
            neighbours[i].add(j)
            neighbours[j].add(i)
            cells_of_edge.setdefault((min(i, j), max(i, j)), []).append(ci)

    # Wall edges: both ends and the midpoint on a wall.
    wall_edges = []
    for (i, j), owners in cells_of_edge.items():
        if wall[i] and wall[j]:
            mid = 0.5 * (points[i] + points[j])
            if wall_distance(mid[None, :], segments)[0] < on_wall_tol:
                wall_edges.append((i, j, owners))

    # First heights, and each wall node's inward normal (mean of its wall edges' normals, each
    # pointing to its cell's other corners).
    heights, errors, within = [], [], 0
    normal_sum = {}
    for i, j, owners in wall_edges:
        e = points[j] - points[i]
        length = math.hypot(*e)
        n = np.array([-e[1], e[0]]) / length
        for ci in owners:
            others = [v for v in cells[ci] if v != i and v != j]
            h = [(points[v] - points[i]) @ n for v in others]
            if np.mean(h) < 0:
                h, n_in = [-x for x in h], -n
            else:
                n_in = n
            err = max(abs(x / first_height - 1.0) for x in h)
            heights += h
            errors.append(err)
            within += err <= 0.02
            for v in (i, j):
                normal_sum[v] = normal_sum.get(v, np.zeros(2)) + n_in

    # Columns along the normals.
    ratios, ratio_at = [], []
    for w, ns in normal_sum.items():
        norm = math.hypot(*ns)
        if norm == 0:
            continue
        direction = ns / norm
        column, cur = [w], w
        while d[cur] <= thickness and len(column) < 10000:
            best = step_up(points, d, neighbours[cur], cur, direction, min_cos)
            if best is None:
                break
            column.append(best)
            direction = (points[best] - points[cur]) / math.hypot(*(points[best] - points[cur]))
            cur = best
        dist = d[column]
        for k in range(1, len(column) - 1):
            below, above = dist[k] - dist[k - 1], dist[k + 1] - dist[k]
            if below > 0:
                ratios.append(above / below)
                ratio_at.append(dist[k])

    angles_max, above_150, core_min, core_count = 0.0, 0, 180.0, 0
    for c in cells:
        a = cell_angles(points, c)
        angles_max = max(angles_max, max(a))
        above_150 += sum(x > 150.0 for x in a)
        if len(c) == 3 and all(d[v] > thickness for v in c):
            core_min = min(core_min, min(a))
            core_count += 1

    # The fan: cells around the wall node whose two wall edges turn most.
    turn_of = {}
    edges_of_node = {}
    for i, j, _ in wall_edges:
        edges_of_node.setdefault(i, []).append(j)
        edges_of_node.setdefault(j, []).append(i)
    for v, ends in edges_of_node.items():
        if len(ends) == 2:
            u1, u2 = points[ends[0]] - points[v], points[ends[1]] - points[v]
            turn_of[v] = math.degrees(math.acos(np.clip(u1 @ u2 / (math.hypot(*u1) * math.hypot(*u2)), -1, 1)))
    fan = None
    if turn_of:
        sharp = min(turn_of, key=turn_of.get)
        fan = {"node_angle_deg": turn_of[sharp], "cells": sum(sharp in c for c in cells),
               "at": [float(points[sharp][0]), float(points[sharp][1])]}

    jumps = None
    if layer_cells is not None:
        jumps = thickness_jumps(points, cells, layer_cells, d, wall_edges, regions or {}, min_cos)

    ratios = np.array(ratios)
    worst = int(np.argmax(ratios)) if len(ratios) else None
    return {
        "nodes": int(len(points)), "triangles": len(triangles), "quads": len(quads),
        "wall_cells": len(errors),
        "first_height_within_2pct": 100.0 * within / len(errors) if errors else float("nan"),
        "first_height_max_error": float(max(errors)) if errors else float("nan"),
        "first_height_median": float(np.median(heights)) if heights else float("nan"),
        "growth_median": _percentile(ratios, 50), "growth_p95": _percentile(ratios, 95),
        "growth_max": float(ratios.max()) if len(ratios) else float("nan"),
        "growth_max_at_distance": float(ratio_at[worst]) if worst is not None else float("nan"),
        "growth_above_1_25_pct": 100.0 * float((ratios > 1.25).mean()) if len(ratios) else float("nan"),
        "max_angle": angles_max, "angles_above_150": int(above_150),
        "core_min_angle": core_min if core_count else float("nan"), "core_triangles": core_count,
        "fan": fan, "thickness_jumps": jumps,
    }


def step_up(points, d, candidates, cur, direction, min_cos):
    """Of the candidates farther from the wall than cur (wall distance d), the one whose step from cur
    is best aligned with direction (cosine above min_cos); None when there is none."""
    best, best_cos = None, min_cos
    for v in candidates:
        step = points[v] - points[cur]
        length = math.hypot(*step)
        if d[v] <= d[cur] or length == 0:
            continue
        c = (step @ direction) / length
        if c > best_cos:
            best, best_cos = v, c
    return best


def thickness_jumps(points, cells, layer_cells, d, wall_edges, regions, min_cos):
    """The layer thickness at both ends of each wall edge (the columns walked along the layer cells'
    edges best aligned with the edge's normal, up to the last layer node), and their ratio:
    {"all": {...}, region: {...}}, each with edges, max, at, above_1_3."""
    layer_neighbours = {}
    for c, in_layer in zip(cells, layer_cells):
        if not in_layer:
            continue
        for k in range(len(c)):
            i, j = c[k], c[(k + 1) % len(c)]
            layer_neighbours.setdefault(i, set()).add(j)
            layer_neighbours.setdefault(j, set()).add(i)

    def column_top(w, direction):
        cur = w
        for _ in range(10000):
            best = step_up(points, d, layer_neighbours.get(cur, ()), cur, direction, min_cos)
            if best is None:
                break
            direction = (points[best] - points[cur]) / math.hypot(*(points[best] - points[cur]))
            cur = best
        return float(d[cur])

    out = {name: {"edges": 0, "max": 1.0, "at": None, "above_1_3": 0} for name in ["all"] + list(regions)}
    for i, j, owners in wall_edges:
        # Both columns start along this edge's normal into its layer cell: at a fan corner, the
        # fan's ray next to the edge.
        inside = [ci for ci in owners if layer_cells[ci]]
        if not inside:
            continue
        e = points[j] - points[i]
        n = np.array([-e[1], e[0]]) / math.hypot(*e)
        if np.mean([(points[v] - points[i]) @ n for v in cells[inside[0]] if v not in (i, j)]) < 0:
            n = -n
        lo, hi = sorted((column_top(i, n), column_top(j, n)))
        if hi == 0.0:
            continue
        jump = math.inf if lo == 0.0 else hi / lo
        mid = 0.5 * (points[i] + points[j])
        for name, box in [("all", None)] + list(regions.items()):
            if box is not None and not (box[0] <= mid[0] <= box[2] and box[1] <= mid[1] <= box[3]):
                continue
            r = out[name]
            r["edges"] += 1
            r["above_1_3"] += jump > 1.3
            if jump > r["max"]:
                r["max"], r["at"] = jump, [float(mid[0]), float(mid[1])]
    return out


def format_measures(name, m):
    fan = m["fan"]
    fan_text = f"{fan['cells']} cells at a {fan['node_angle_deg']:.1f} deg wall corner" if fan else "-"
    return (f"{name}: {m['nodes']} nodes, {m['triangles']} triangles, {m['quads']} quads; "
            f"wall cells {m['wall_cells']}, within ±2 % of h1 {m['first_height_within_2pct']:.1f} % "
            f"(max error {100 * m['first_height_max_error']:.2f} %); growth median/p95/max "
            f"{m['growth_median']:.3f} / {m['growth_p95']:.3f} / {m['growth_max']:.2f} "
            f"(max at d = {m['growth_max_at_distance']:.4g}; {m['growth_above_1_25_pct']:.1f} % above 1.25); "
            f"max angle {m['max_angle']:.1f} deg, {m['angles_above_150']} above 150; core min angle "
            f"{m['core_min_angle']:.2f} deg ({m['core_triangles']} triangles); fan {fan_text}"
            + "".join(f"\n  thickness jump {name}: max {r['max']:.3f} over {r['edges']} wall edges, "
                      f"{r['above_1_3']} above 1.3" for name, r in (m.get("thickness_jumps") or {}).items()))
