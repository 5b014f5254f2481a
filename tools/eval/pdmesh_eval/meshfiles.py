"""pdmesh node files (docs/node-file.md) and triangle meshes (.msh 4.1 / 2.2 ASCII, .vtu data
arrays, ASCII or binary) read into plain lists, and the angles of their triangles."""

import base64
import math
import re
import struct


def read_node_file(path):
    """Reads a pdmesh node file: returns (nodes, curves) with nodes as (x, y, kind, curve, q) and
    curves as (name, [indices])."""
    with open(path) as f:
        lines = [ln.split() for ln in f.read().splitlines()[1:]
                 if ln.strip() and not ln.lstrip().startswith("#")]
    count = int(lines[0][0])
    nodes = [(float(t[0]), float(t[1]), t[2], int(t[3]), float(t[4])) for t in lines[1:1 + count]]
    curves = [(t[0], [int(i) for i in t[2:]]) for t in lines[2 + count:]]
    return nodes, curves


def boundary_loops(curves):
    """Chains the curves into closed loops of node indices (the closing node not repeated)."""
    unused = list(range(len(curves)))
    loops = []
    while unused:
        chain = list(curves[unused.pop(0)][1])
        while chain[-1] != chain[0]:
            for k in unused:
                pts = curves[k][1]
                if pts[0] == chain[-1] or pts[-1] == chain[-1]:
                    chain += (pts if pts[0] == chain[-1] else pts[::-1])[1:]
                    unused.remove(k)
                    break
            else:
                raise ValueError(f"boundary curve chain ending at node {chain[-1]} does not close")
        loops.append(chain[:-1])
    return loops


_VTU_TYPES = {"Float64": "d", "Float32": "f", "Int64": "q", "Int32": "i", "Int16": "h", "Int8": "b",
              "UInt64": "Q", "UInt32": "I", "UInt16": "H", "UInt8": "B"}


def vtu_arrays(path):
    """Every inline DataArray of a .vtu file, by name, as a list: an ASCII array's values as strings,
    a binary one's (base64 of a byte count and the data, uncompressed: pdmesh's default) as numbers."""
    with open(path) as f:
        text = f.read()
    head = re.search(r"<VTKFile[^>]*>", text)
    head = head.group(0) if head else ""
    if "compressor=" in head:
        raise ValueError(f"{path}: compressed .vtu arrays are not read")
    order = ">" if 'byte_order="BigEndian"' in head else "<"
    count = order + ("Q" if 'header_type="UInt64"' in head else "I")  # VTK's default header is UInt32
    arrays = {}
    for m in re.finditer(r"<DataArray([^>]*)>(.*?)</DataArray>", text, re.S):
        attributes, body = m.group(1), m.group(2)
        name = re.search(r'Name="([^"]+)"', attributes)
        if not name:
            continue
        if 'format="binary"' in attributes:
            code = _VTU_TYPES[re.search(r'type="(\w+)"', attributes).group(1)]
            raw = base64.b64decode("".join(body.split()))
            (size,) = struct.unpack_from(count, raw)
            values = size // struct.calcsize(code)
            arrays[name.group(1)] = list(struct.unpack_from(f"{order}{values}{code}", raw, struct.calcsize(count)))
        else:
            arrays[name.group(1)] = body.split()
    return arrays


def read_msh(path):
    """Points [(x, y)] and triangles [(a, b, c)] (0-based) of an ASCII Gmsh .msh file, format 4.1
    (as pdmesh and `gmsh -format msh41` write it) or 2.2. Node tags may be sparse."""
    with open(path) as f:
        lines = f.read().split("\n")
    version = None
    tag_of, points, triangles = {}, [], []
    i = 0
    while i < len(lines):
        line = lines[i].strip()
        if line == "$MeshFormat":
            version = lines[i + 1].split()[0]
            i += 2
        elif line == "$Nodes" and version and version.startswith("4"):
            blocks = int(lines[i + 1].split()[0])
            i += 2
            for _ in range(blocks):
                count = int(lines[i].split()[3])
                tags = [int(lines[i + 1 + k]) for k in range(count)]
                for k, tag in enumerate(tags):
                    xyz = lines[i + 1 + count + k].split()
                    tag_of[tag] = len(points)
                    points.append((float(xyz[0]), float(xyz[1])))
                i += 1 + 2 * count
        elif line == "$Nodes":
            count = int(lines[i + 1])
            for k in range(count):
                t = lines[i + 2 + k].split()
                tag_of[int(t[0])] = len(points)
                points.append((float(t[1]), float(t[2])))
            i += 2 + count
        elif line == "$Elements" and version and version.startswith("4"):
            blocks = int(lines[i + 1].split()[0])
            i += 2
            for _ in range(blocks):
                _, _, etype, count = (int(v) for v in lines[i].split())
                if etype == 2:
                    for k in range(count):
                        t = lines[i + 1 + k].split()
                        triangles.append((tag_of[int(t[1])], tag_of[int(t[2])], tag_of[int(t[3])]))
                i += 1 + count
        elif line == "$Elements":
            count = int(lines[i + 1])
            for k in range(count):
                t = [int(v) for v in lines[i + 2 + k].split()]
                if t[1] == 2:
                    triangles.append(tuple(tag_of[v] for v in t[3 + t[2]:6 + t[2]]))
            i += 2 + count
        else:
            i += 1
    if version is None:
        raise ValueError(f"{path}: not a Gmsh .msh file (no $MeshFormat)")
    return points, triangles


def corner_angles(points, triangle):
    """The three angles (degrees) of a triangle, at its vertices in order."""
    out = []
    for k in range(3):
        a, b, c = points[triangle[k]], points[triangle[(k + 1) % 3]], points[triangle[(k + 2) % 3]]
        ux, uy, vx, vy = b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1]
        out.append(math.degrees(math.atan2(abs(ux * vy - uy * vx), ux * vx + uy * vy)))
    return out
