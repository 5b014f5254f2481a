#!/usr/bin/env python3
"""The communication a distributed pdmesh run would need, measured on a real run's nodes (docs/scaling.md).

Reads a run directory's final.nodes (x, y, kind, q: the simulation's last state) and, if present, its
Triangle-format mesh (mesh.node / mesh.ele, `--formats triangle`). Orders the nodes along a Hilbert
curve over their bounding square and cuts the curve into P ranges of equal node weight (every node
weighs the same: a node's pair count is near constant because the cut-off scales with q). For each P
and each list radius it counts, per part:

- pairs: interior nodes' neighbours within radius x q_i (the force loop's work, docs/simulation.md);
- ghosts: the other parts' nodes some owned node needs: an interior node's neighbours within the
  radius, a boundary node's prev / next along its curve (the halo a rank receives each iteration);
- messages: the parts those ghosts come from;
- interface triangles (with a mesh): triangles whose corners lie in more than one part, and the
  triangles sharing a corner with one (what a cleanup pass with frozen interfaces may not edit).

Bytes per ghost are position, q and a 64-bit id holding the kind (4 x 8 = 32 B, in double).
A network model (bandwidth, latency) turns them into time per iteration beside the measured compute.

Usage: python3 tools/bench/partition_halo.py RUN_DIR [--parts 2,4,...] [--radius 1.5,2.7]
                                             [--iteration-s S] [--json OUT] [--nodes FILE]
(--nodes: another node file, or an interrupted run's checkpoint.pdmesh)
Needs numpy only.
"""

import argparse
import json
import math
import os
import sys
import time

import numpy as np

GHOST_BYTES = 32  # x, y, q as doubles and a 64-bit global id whose top bits hold the kind
KIND = {"fixed": 0, "boundary": 1, "interior": 2}


def read_node_file(path):
    """final.nodes (docs/node-file.md): x, y, kind, curve, q and the curves' node chains."""
    with open(path) as f:
        if f.readline().strip() != "# pdmesh nodes v1":
            sys.exit(f"{path}:1: not a pdmesh node file")
        n = int(f.readline())
        body = [f.readline() for _ in range(n)]
        text = "".join(body)
        for word, code in KIND.items():
            text = text.replace(word, str(code))
        a = np.fromstring(text, sep=" ").reshape(n, 5)
        chains = []
        header = f.readline().split()
        for _ in range(int(header[1])):
            parts = f.readline().split()
            chains.append(np.array(parts[2:], dtype=np.int64))
    return a[:, 0], a[:, 1], a[:, 2].astype(np.int8), a[:, 4], chains


def read_checkpoint(path):
    """checkpoint.pdmesh (docs/checkpoint.md, version 2): the same fields from an interrupted run's state."""
    with open(path) as f:
        if not f.readline().startswith("pdmesh-checkpoint"):
            sys.exit(f"{path}:1: not a pdmesh checkpoint")
        line = f.readline()
        while not line.startswith("nodes "):
            line = f.readline()
        n = int(line.split()[1])
        rows = [f.readline().split() for _ in range(n)]
        a = np.array([[float.fromhex(r[0]), float.fromhex(r[1]), float.fromhex(r[2]), float(r[3])] for r in rows])
        chains = []
        for _ in range(int(f.readline().split()[1])):
            fields = f.readline().split()
            chains.append(np.array([int(e.split(":")[0]) for e in fields[3:]], dtype=np.int64))
    return a[:, 0], a[:, 1], a[:, 3].astype(np.int8), a[:, 2], chains


def read_nodes(path):
    """A node file or a checkpoint, by its first line."""
    with open(path) as f:
        first = f.readline()
    return read_checkpoint(path) if first.startswith("pdmesh-checkpoint") else read_node_file(path)


def read_numbered(path, columns):
    """A Triangle .node / .ele file's rows (the header line and '#' comments skipped)."""
    with open(path) as f:
        lines = [line for line in f if line.strip() and not line.lstrip().startswith("#")]
    count = int(lines[0].split()[0])
    text = "".join(lines[1:count + 1])
    values = np.fromstring(text, sep=" ")
    return values.reshape(count, -1)[:, :columns]


def square_frame(x, y):
    """The points' bounding square: lower corner and side."""
    lo_x, lo_y = x.min(), y.min()
    return lo_x, lo_y, max(x.max() - lo_x, y.max() - lo_y) or 1.0


def hilbert_keys(x, y, frame, bits=20):
    """Hilbert index of each point on a 2^bits grid over the square `frame` (points outside are clamped)."""
    lo_x, lo_y, span = frame
    side = 1 << bits
    gx = np.clip(((x - lo_x) / span * side).astype(np.int64), 0, side - 1)
    gy = np.clip(((y - lo_y) / span * side).astype(np.int64), 0, side - 1)
    d = np.zeros_like(gx)
    s = side >> 1
    while s > 0:
        rx = (gx & s) > 0
        ry = (gy & s) > 0
        d += s * s * ((3 * rx.astype(np.int64)) ^ ry.astype(np.int64))
        # Rotate the quadrant so that the curve continues in the next level's frame.
        flip = ~ry & rx
        gx = np.where(flip, s - 1 - gx, gx)
        gy = np.where(flip, s - 1 - gy, gy)
        swap = ~ry
        gx, gy = np.where(swap, gy, gx), np.where(swap, gx, gy)
        s >>= 1
    return d


def partition(order, weight, parts):
    """Part of each node: the Hilbert order cut into `parts` ranges of equal cumulative weight."""
    cum = np.cumsum(weight[order])
    bounds = cum[-1] * np.arange(1, parts) / parts
    cut = np.searchsorted(cum, bounds, side="left") + 1
    part_in_order = np.zeros(len(order), dtype=np.int32)
    for c in cut:
        part_in_order[c:] += 1
    part = np.empty(len(order), dtype=np.int32)
    part[order] = part_in_order
    return part


class PairScan:
    """Every (i, j) with |x_j - x_i| <= radius q_i for interior i, in bands of similar q_i.

    A band's queries search a 3x3 block of a uniform grid whose cell is at least the band's largest
    radius, over all nodes; bands of ratio 2^(1/4) keep the block close to the query circle.
    """

    def __init__(self, x, y, q, query):
        self.x, self.y, self.q, self.query = x, y, q, query

    def bands(self, radius):
        r = radius * self.q[self.query]
        level = np.floor(4 * np.log2(r / r.min())).astype(np.int64)
        for lev in np.unique(level):
            members = self.query[level == lev]
            yield members, r.min() * 2 ** ((lev + 1) / 4) * (1 + 1e-12)

    def pairs(self, radius, chunk=4_000_000):
        x, y, q = self.x, self.y, self.q
        for members, cell in self.bands(radius):
            cx = np.floor(x / cell).astype(np.int64)
            cy = np.floor(y / cell).astype(np.int64)
            key = (cx + (1 << 30)) * (1 << 31) + (cy + (1 << 30))
            order = np.argsort(key, kind="stable")
            sorted_key = key[order]
            step = max(1, chunk // 200)
            for start in range(0, len(members), step):
                qi = members[start:start + step]
                yield from self._block_pairs(qi, cx, cy, sorted_key, order, radius * q[qi])

    def _block_pairs(self, qi, cx, cy, sorted_key, order, r):
        x, y = self.x, self.y
        for ox in (-1, 0, 1):
            for oy in (-1, 0, 1):
                k = (cx[qi] + ox + (1 << 30)) * (1 << 31) + (cy[qi] + oy + (1 << 30))
                lo = np.searchsorted(sorted_key, k, side="left")
                hi = np.searchsorted(sorted_key, k, side="right")
                count = hi - lo
                if count.sum() == 0:
                    continue
                i = np.repeat(qi, count)
                rr = np.repeat(r, count)
                offs = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
                j = order[np.repeat(lo, count) + offs]
                dx = x[j] - x[i]
                dy = y[j] - y[i]
                keep = (dx * dx + dy * dy <= rr * rr) & (i != j)
                yield i[keep], j[keep]


def chain_pairs(chains, kind):
    """A boundary node's force partners: its prev and next along its curve (both directions)."""
    i_all, j_all = [], []
    for c in chains:
        a, b = c[:-1], c[1:]
        i_all += [a, b]
        j_all += [b, a]
    i = np.concatenate(i_all)
    j = np.concatenate(j_all)
    keep = kind[i] == KIND["boundary"]
    return i[keep], j[keep]


def scan_radius(scan, radius, parts_of, chains, kind):
    """Per P: pairs per part and the (part, ghost node) set; one pass over the pairs for every P."""
    n_parts = [p.max() + 1 for p in parts_of]
    pairs = [np.zeros(p, dtype=np.int64) for p in n_parts]
    ghost_keys = [[] for _ in parts_of]
    n = len(kind)
    total = 0
    ci, cj = chain_pairs(chains, kind)
    for i, j in [*scan.pairs(radius), (ci, cj)]:
        interior = kind[i] == KIND["interior"]
        total += int(interior.sum())
        for k, part in enumerate(parts_of):
            pi, pj = part[i], part[j]
            pairs[k] += np.bincount(pi[interior], minlength=n_parts[k])
            cross = pi != pj
            if cross.any():
                ghost_keys[k].append(np.unique(pi[cross].astype(np.int64) * n + j[cross]))
    out = []
    for k, part in enumerate(parts_of):
        keys = np.unique(np.concatenate(ghost_keys[k])) if ghost_keys[k] else np.zeros(0, np.int64)
        receiver = keys // n
        sender = part[keys % n]
        ghosts = np.bincount(receiver, minlength=n_parts[k])
        links = np.unique(receiver * n_parts[k] + sender)
        messages = np.bincount(links // n_parts[k], minlength=n_parts[k])
        out.append({"pairs": pairs[k], "ghosts": ghosts, "messages": messages})
    return total, out


def interface_triangles(tri, part):
    """Triangles with corners in more than one part, and those plus every triangle sharing a corner with one."""
    a, b, c = part[tri[:, 0]], part[tri[:, 1]], part[tri[:, 2]]
    crossing = (a != b) | (b != c)
    touched = np.zeros(part.shape[0], dtype=bool)
    touched[tri[crossing].ravel()] = True
    ring = touched[tri].any(axis=1)
    return int(crossing.sum()), int(ring.sum())


def network_time(ghosts, messages, bandwidth, latency):
    """Seconds per iteration for each part's halo receive: latency per message plus bytes over bandwidth."""
    return messages * latency + ghosts * GHOST_BYTES / bandwidth


def summarize(args, keys, frame, kind, part_list, results, mesh):
    rows = []
    n = len(kind)
    for radius, (total, per_p) in results.items():
        for parts, part, r in zip(args.parts, part_list, per_p):
            nodes = np.bincount(part, minlength=parts)
            row = {
                "radius": radius, "P": parts, "nodes_mean": n / parts, "nodes_max": int(nodes.max()),
                "pairs_total": total, "pairs_max": int(r["pairs"].max()), "pairs_mean": total / parts,
                "ghosts_total": int(r["ghosts"].sum()), "ghosts_max": int(r["ghosts"].max()),
                "ghost_fraction": float(r["ghosts"].sum() / n), "messages_mean": float(r["messages"].mean()),
                "messages_max": int(r["messages"].max()),
                "bytes_max": int(r["ghosts"].max()) * GHOST_BYTES,
                "bytes_total": int(r["ghosts"].sum()) * GHOST_BYTES,
            }
            t_net = network_time(r["ghosts"], r["messages"], args.bandwidth, args.latency)
            row["network_s_max"] = float(t_net.max())
            if args.iteration_s:
                # The measured iteration spread over P ranks in proportion to their pairs.
                row["compute_s_max"] = args.iteration_s * float(r["pairs"].max()) / total
                row["allreduce_s"] = 2 * math.ceil(math.log2(parts)) * args.latency
            if mesh is not None:
                row["triangles"] = int(len(mesh[1]))
                row["interface_triangles"], row["frozen_triangles"] = interface_triangles(
                    mesh[1], mesh_parts(mesh[0], keys, part, frame, args.bits))
            rows.append(row)
    return rows


def mesh_parts(mesh_xy, node_keys, part, frame, bits):
    """The mesh's nodes on the same Hilbert cut: each takes the part of its key's range."""
    mesh_keys = hilbert_keys(mesh_xy[:, 0], mesh_xy[:, 1], frame, bits)
    parts = part.max() + 1
    starts = np.array([node_keys[part == p].min() for p in range(1, parts)], dtype=np.int64)
    return np.searchsorted(starts, mesh_keys, side="right").astype(np.int32)


def print_table(rows, args):
    head = ("| radius (x q) | P | nodes per part | pairs max/mean | ghosts per part, max | ghosts / nodes (all parts) "
            "| messages per part, mean / max | halo bytes per part, max | network s, max part |")
    extra = []
    if args.iteration_s:
        extra += ["compute s, max part", "allreduce s"]
    if any("interface_triangles" in r for r in rows):
        extra += ["triangles crossing parts", "frozen (sharing a corner with those)"]
    print(head[:-1] + "".join(f"| {e} " for e in extra) + "|")
    print("|" + "---|" * (9 + len(extra)))
    for r in rows:
        line = (f"| {r['radius']:g} | {r['P']} | {r['nodes_mean']:,.0f} | {r['pairs_max'] / r['pairs_mean']:.3f} "
                f"| {r['ghosts_max']:,} | {r['ghost_fraction']:.4f} | {r['messages_mean']:.1f} / {r['messages_max']} "
                f"| {r['bytes_max'] / 1e3:,.1f} kB | {r['network_s_max'] * 1e6:,.1f} µs |")
        if args.iteration_s:
            line += f" {r['compute_s_max'] * 1e3:,.2f} ms | {r['allreduce_s'] * 1e6:.0f} µs |"
        if "interface_triangles" in r:
            line += (f" {r['interface_triangles']:,} ({r['interface_triangles'] / r['triangles']:.2%}) "
                     f"| {r['frozen_triangles']:,} ({r['frozen_triangles'] / r['triangles']:.2%}) |")
        print(line)


def fit_exponents(rows, smallest_p=2):
    """Slope of log(ghosts / nodes) against log P per radius over P >= smallest_p: 0.5 is surface-to-volume
    in 2-D; few parts of a long domain cut it into strips, whose interfaces grow as P (slope 1)."""
    out = {}
    for radius in sorted({r["radius"] for r in rows}):
        sel = [r for r in rows if r["radius"] == radius and r["P"] >= max(2, smallest_p)]
        if len(sel) >= 2:
            lp = np.log([r["P"] for r in sel])
            lg = np.log([r["ghost_fraction"] for r in sel])
            out[radius] = float(np.polyfit(lp, lg, 1)[0])
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run_dir")
    ap.add_argument("--parts", default="2,4,8,16,64,256")
    ap.add_argument("--radius", default="1.5,2.7",
                    help="list radii in units of q_i: the cut-off (1.5) and the cut-off with the default Verlet skin "
                    "of a run with momentum (1.5 x 1.8 = 2.7)")
    ap.add_argument("--bandwidth", type=float, default=10e9, help="network bytes per second per rank (10 GB/s)")
    ap.add_argument("--latency", type=float, default=2e-6, help="seconds per message (2 µs)")
    ap.add_argument("--iteration-s", type=float, default=0.0,
                    help="measured seconds per iteration of the whole run on one machine, spread over P ranks")
    ap.add_argument("--nodes", help="the node file or checkpoint to read instead of RUN_DIR/final.nodes")
    ap.add_argument("--bits", type=int, default=20)
    ap.add_argument("--json", help="write the rows here")
    args = ap.parse_args()
    args.parts = [int(p) for p in args.parts.split(",")]
    radii = [float(r) for r in args.radius.split(",")]

    t0 = time.time()
    x, y, kind, q, chains = read_nodes(args.nodes or os.path.join(args.run_dir, "final.nodes"))
    print(f"{len(x):,} nodes ({int((kind == KIND['interior']).sum()):,} interior, "
          f"{int((kind != KIND['interior']).sum()):,} on curves), read in {time.time() - t0:.1f} s")
    frame = square_frame(x, y)
    keys = hilbert_keys(x, y, frame, args.bits)
    order = np.lexsort((np.arange(len(x)), keys))
    part_list = [partition(order, np.ones(len(x)), p) for p in args.parts]
    mesh = None
    node_file, ele_file = (os.path.join(args.run_dir, f) for f in ("mesh.node", "mesh.ele"))
    if os.path.exists(node_file) and os.path.exists(ele_file):
        mesh_xy = read_numbered(node_file, 3)[:, 1:3]
        tri = read_numbered(ele_file, 4)[:, 1:4].astype(np.int64) - 1
        mesh = (mesh_xy, tri)
        print(f"mesh: {len(mesh_xy):,} nodes, {len(tri):,} triangles")
    scan = PairScan(x, y, q, np.flatnonzero(kind == KIND["interior"]))
    results = {}
    for radius in radii:
        t1 = time.time()
        results[radius] = scan_radius(scan, radius, part_list, chains, kind)
        pairs = results[radius][0]
        print(f"radius {radius:g} q: {pairs:,} interior pairs, {pairs / len(scan.query):.2f} per interior node "
              f"({time.time() - t1:.1f} s)")
    rows = summarize(args, keys, frame, kind, part_list, results, mesh)
    print_table(rows, args)
    print()
    for smallest in (2, 16):
        for radius, slope in fit_exponents(rows, smallest).items():
            print(f"radius {radius:g} q, P >= {smallest}: ghosts / nodes grows as P^{slope:.3f} "
                  "(2-D surface-to-volume: P^0.5)")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
