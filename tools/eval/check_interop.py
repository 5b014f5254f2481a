#!/usr/bin/env python3
"""The round trips pdmesh's users make with its files, checked with the tools they use:

    tools/.venv-anchors/bin/python tools/eval/check_interop.py mmg2d   PDMESH RUN CASE [LAYERED]
    tools/.venv-anchors/bin/python tools/eval/check_interop.py gmsh    PDMESH RUN CASE [LAYERED]
    tools/.venv-anchors/bin/python tools/eval/check_interop.py formats PDMESH RUN [LAYERED]

With --python-path DIR (a build's python folder) the mmg2d and gmsh checks also read the files with
pdmesh.Mesh.read.

RUN is a `pdmesh mesh CASE` directory of tests/data/interop/two_regions.toml (two regions beside a
constraint, a curve per segment: CURVES); LAYERED one of layered.toml (quad layers on the bottom).
Each step prints ok/FAIL.

- mmg2d (mmgpy's mmg2d_O3): RUN/mesh.mesh through a pass that changes nothing (-noinsert -noswap
  -nomove) and a remesh (-hmax); mmg2d keeps the triangle references (regions), the edge references
  (curves) and pdmesh's Corners; `pdmesh quality`, `pdmesh transfer` (onto mmg2d's mesh: the VTU it
  writes holds the regions and the fixed nodes as pdmesh reads them) and `pdmesh smooth` read its
  output. With LAYERED, what mmg2d does to a file with quadrilaterals (kept; the layer's top added
  as edges of reference 0, which are no curve when read back).
- gmsh (the gmsh module, 4.15.2): RUN/mesh.msh opens with the physical groups (curves, regions),
  element types and Gmsh's quality measures, and saved again by Gmsh reads back in pdmesh. A mesh
  Gmsh makes of the same geometry, with named physical groups (and quads by recombination), reads in
  `pdmesh quality`, `transfer` and `smooth` with the physical names as curve names and the surfaces
  as regions; so do the Medit .mesh files Gmsh and meshio write of it (Dimension 3, z = 0).
- formats: RUN/mesh.su2 against the SU2 native format's rules, and RUN/mesh.vtu in VTK's own XML
  reader (pyvista's vtk).

Exit status 0 when every check passed, 1 otherwise, 77 when a tool is missing (ctest's skip)."""
import json
import os
import subprocess
import sys
import tempfile

FAILURES = []
PDMESH_PY = None  # the pdmesh Python module, with --python-path DIR
CURVES = ["bottom_left", "bottom_right", "right", "top_right", "top_left", "left", "middle"]
LAYERED_CURVES = ["bottom", "right", "top", "left"]


def check(ok, what):
    print(f"{'ok  ' if ok else 'FAIL'} {what}")
    if not ok:
        FAILURES.append(what)
    return ok


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        print(f"$ {' '.join(cmd)}\n{r.stdout}{r.stderr}")
    return r


def skip(why):
    print(f"{why}: skipped")
    sys.exit(77)


def read_medit(path):
    """The sections of an ASCII .mesh: vertices, edges, triangles, quads (vertex lists 0-based, the
    reference last), corners and required vertices (0-based), and the '#' comment lines."""
    tokens, comments = [], []
    with open(path, encoding="utf-8") as f:
        for line in f:
            s = line.strip()
            if s.startswith("#"):
                comments.append(s)
            else:
                tokens += s.split()
    out = {"Vertices": [], "Edges": [], "Triangles": [], "Quadrilaterals": [], "Corners": [],
           "RequiredVertices": [], "comments": comments}
    width = {"Vertices": 3, "Edges": 3, "Triangles": 4, "Quadrilaterals": 5}
    k = 0
    while k < len(tokens):
        kw = tokens[k]
        k += 1
        if kw in ("MeshVersionFormatted", "Dimension"):
            if kw == "Dimension":
                width["Vertices"] = int(tokens[k]) + 1
            k += 1
        elif kw == "End":
            break
        else:
            n = int(tokens[k])
            k += 1
            w = width.get(kw, 1)
            rows = [tokens[k + i * w:k + (i + 1) * w] for i in range(n)]
            k += n * w
            if kw == "Vertices":
                out[kw] = [(float(r[0]), float(r[1]), int(r[-1])) for r in rows]
            elif kw in width:  # meshio writes a section per cell block: they add up
                out[kw] = out.get(kw, []) + [tuple(int(x) - 1 for x in r[:-1]) + (int(r[-1]),) for r in rows]
            else:
                out[kw] = out.get(kw, []) + [int(r[0]) - 1 for r in rows]
    return out


def quality_json(pdmesh, mesh, tmp):
    out = os.path.join(tmp, os.path.basename(mesh) + ".quality.json")
    r = run([pdmesh, "quality", mesh, "--json", out])
    check(r.returncode == 0, f"pdmesh quality {os.path.basename(mesh)}: exit {r.returncode}")
    if r.returncode != 0:
        return None
    with open(out, encoding="utf-8") as f:
        return json.load(f)


def transfer(pdmesh, run_dir, mesh, tmp):
    """`pdmesh transfer` of the run's q onto MESH: the VTU it writes is MESH as pdmesh read it."""
    out = os.path.join(tmp, os.path.basename(mesh) + ".vtu")
    r = run([pdmesh, "transfer", os.path.join(run_dir, "mesh.vtu"), mesh, "--arrays", "q", "--out", out, "-q"])
    check(r.returncode == 0, f"pdmesh transfer onto {os.path.basename(mesh)}: exit {r.returncode}")
    return out if r.returncode == 0 else None


def vtu_curve_names(m):
    raw = bytes(int(x) for x in m.field_data.get("curve_names", []))
    return [s.decode() for s in raw.split(b"\0")[:-1]]


def smooth(pdmesh, mesh, case, tmp):
    out = os.path.join(tmp, os.path.basename(mesh) + ".smooth")
    r = run([pdmesh, "smooth", mesh, "-g", case, "--out", out, "-q", "--device", "host", "--formats", "mesh,msh"])
    check(r.returncode == 0 and os.path.exists(os.path.join(out, "mesh.mesh")),
          f"pdmesh smooth {os.path.basename(mesh)} -g {os.path.basename(case)}: exit {r.returncode}")
    return out


def python_read(label, path, regions, curves, quads=0, fixed=None):
    """pdmesh.Mesh.read of PATH (with --python-path): the regions' values, the curve names, the
    number of quads and of fixed nodes."""
    if PDMESH_PY is None:
        return
    m = PDMESH_PY.Mesh.read(path)
    got = sorted({float(r) for r in m.regions})
    check(got == [float(r) for r in regions] and list(m.curve_names) == curves and len(m.quads) == quads,
          f"{label}: Mesh.read: regions {got}, curves {list(m.curve_names)}, {len(m.quads)} quads")
    if fixed is not None:
        n = int((m.kinds == 0).sum()) if len(m.kinds) else 0
        check(n == fixed, f"{label}: Mesh.read: {n} fixed nodes (want {fixed})")


def at(mesh, i):
    """Vertex i's coordinates to 12 digits: mmg2d writes 15 significant digits, pdmesh 17."""
    return tuple(round(c, 12) for c in mesh["Vertices"][i][:2])


def cell_keys(mesh, section, n):
    """Per cell of `section` (n vertices): its sorted vertex coordinates and its reference."""
    return sorted((tuple(sorted(at(mesh, i) for i in c[:n])), c[n]) for c in mesh[section])


def mmg2d_checks(pdmesh, run_dir, case, layered, tmp):
    try:
        import meshio
    except ImportError as e:
        skip(e)
    mmg2d = os.path.join(os.path.dirname(sys.executable), "mmg2d_O3")
    if not os.path.exists(mmg2d):
        skip(f"{mmg2d}: missing (mmgpy is not installed)")
    r = subprocess.run([mmg2d, "-h"], capture_output=True, text=True)
    version = next((line.strip() for line in (r.stdout + r.stderr).splitlines() if "Release" in line), "?")
    print(f"mmg2d: {version}")
    ours_path = os.path.join(run_dir, "mesh.mesh")
    ours = read_medit(ours_path)
    refs = sorted({t[3] for t in ours["Triangles"]})
    edge_refs = sorted({e[2] for e in ours["Edges"]})
    check(refs == [1, 2] and any("region region_1" in c for c in ours["comments"]),
          f"pdmesh's {ours_path}: triangle references {refs}, named region_1 and region_2")
    lengths = [((ours["Vertices"][a][0] - ours["Vertices"][b][0]) ** 2 +
                (ours["Vertices"][a][1] - ours["Vertices"][b][1]) ** 2) ** 0.5 for a, b, _ in ours["Edges"]]
    hmax = 0.5 * sum(lengths) / len(lengths)
    corners = {at(ours, i) for i in ours["Corners"]}
    runs = {"noop": ["-noinsert", "-noswap", "-nomove"], "hmax": ["-hmax", f"{hmax:.6g}"]}
    for name, options in runs.items():
        path = os.path.join(tmp, f"mmg2d_{name}.mesh")
        r = run([mmg2d, "-in", ours_path, "-out", path, "-v", "0"] + options)
        if not check(r.returncode == 0 and os.path.exists(path), f"mmg2d {' '.join(options)}: exit {r.returncode}"):
            continue
        a = read_medit(path)
        check(not any("region" in c for c in a["comments"]), f"{name}: mmg2d writes no comments back")
        got = sorted({t[3] for t in a["Triangles"]})
        check(got == refs, f"{name}: mmg2d kept the triangle references {refs} (has {got})")
        got = sorted({e[2] for e in a["Edges"]})
        check(got == edge_refs, f"{name}: mmg2d kept the edge references {edge_refs} (has {got})")
        kept = {at(a, i) for i in a["Corners"] + a["RequiredVertices"]}
        check(corners <= kept, f"{name}: mmg2d kept pdmesh's {len(corners)} Corners among its {len(kept)} "
              f"Corners and RequiredVertices")
        if name == "noop":
            check(cell_keys(a, "Triangles", 3) == cell_keys(ours, "Triangles", 3),
                  "noop: the same triangles with the same references")
        else:
            check(len(a["Triangles"]) > len(ours["Triangles"]),
                  f"hmax: mmg2d refined {len(ours['Triangles'])} triangles to {len(a['Triangles'])}")
        q = quality_json(pdmesh, path, tmp)
        if q is not None:
            check(q["points"] == len(a["Vertices"]) and q["triangles"] == len(a["Triangles"]),
                  f"{name}: pdmesh quality reads {q['points']} points, {q['triangles']} triangles "
                  f"(the file: {len(a['Vertices'])}, {len(a['Triangles'])})")
        vtu = transfer(pdmesh, run_dir, path, tmp)
        if vtu is not None:
            m = meshio.read(vtu)
            region = [int(x) for x in m.cell_data["region"][0]] if "region" in m.cell_data else []
            check(region == [t[3] for t in a["Triangles"]],
                  f"{name}: the regions pdmesh reads are mmg2d's triangle references")
            names = vtu_curve_names(m)
            check(names == [f"ref{k}" for k in edge_refs], f"{name}: curves {names}")
            kind = [int(x) for x in m.point_data.get("kind", [])]
            fixed = sorted(i for i, k in enumerate(kind) if k == 0)
            check(fixed == sorted(set(a["Corners"] + a["RequiredVertices"])),
                  f"{name}: {len(fixed)} fixed nodes, mmg2d's Corners and RequiredVertices")
        python_read(f"{name}", path, refs, [f"ref{k}" for k in edge_refs],
                    fixed=len(set(a["Corners"] + a["RequiredVertices"])))
        out = smooth(pdmesh, path, case, tmp)
        s = os.path.join(out, "mesh.mesh")
        if os.path.exists(s):
            back = read_medit(s)
            check(sorted({t[3] for t in back["Triangles"]}) == refs and
                  any("region region_2" in c for c in back["comments"]),
                  f"{name}: pdmesh smooth's mesh has the regions {refs}")
    if layered is None:
        return
    # A layered run's file: the quads with reference 1 (the layer), its triangles 0 and 1.
    lay_path = os.path.join(layered, "mesh.mesh")
    lay = read_medit(lay_path)
    print(f"layered: {len(lay['Triangles'])} triangles, {len(lay['Quadrilaterals'])} quadrilaterals")
    for name, options in runs.items():
        if name == "hmax":
            options = ["-hmax", "0.05"]
        path = os.path.join(tmp, f"mmg2d_layered_{name}.mesh")
        r = run([mmg2d, "-in", lay_path, "-out", path, "-v", "0"] + options)
        if not check(r.returncode == 0 and os.path.exists(path),
                     f"layered: mmg2d {' '.join(options)}: exit {r.returncode}"):
            continue
        a = read_medit(path)
        quads, want = cell_keys(a, "Quadrilaterals", 4), cell_keys(lay, "Quadrilaterals", 4)
        check(quads == want, f"layered {name}: mmg2d kept the {len(want)} quadrilaterals as they were "
              f"(has {len(quads)})")
        print(f"layered {name}: {len(a['Triangles'])} triangles, {len(a['Quadrilaterals'])} quadrilaterals, "
              f"triangle references {sorted({t[3] for t in a['Triangles']})}, "
              f"quad references {sorted({c[4] for c in a['Quadrilaterals']})}")
        q = quality_json(pdmesh, path, tmp)
        if q is not None:
            check(q["points"] == len(a["Vertices"]) and q["triangles"] == len(a["Triangles"]),
                  f"layered {name}: pdmesh quality reads {q['points']} points, {q['triangles']} triangles")
        # mmg2d adds the layer's top as edges of reference 0 between quads and triangles: not a curve.
        inner = sum(1 for e in a["Edges"] if e[2] == 0)
        vtu = transfer(pdmesh, run_dir, path, tmp)
        if vtu is not None:
            names = vtu_curve_names(meshio.read(vtu))
            check(names == [f"ref{k}" for k in sorted({e[2] for e in lay["Edges"]})],
                  f"layered {name}: curves {names} ({inner} edges of reference 0 in mmg2d's file)")
        python_read(f"layered {name}", path, [], [f"ref{k}" for k in sorted({e[2] for e in lay["Edges"]})],
                    quads=len(want))


def gmsh_mesh(gmsh, path, recombine, version):
    """Gmsh's mesh of two_regions.toml's geometry: physical curves named as the case's, physical
    surfaces "fluid" (left) and "solid" (right); with `recombine` the left surface in quads."""
    gmsh.clear()
    gmsh.model.add("two_regions")
    g = gmsh.model.geo
    p = [g.addPoint(x, y, 0, 0.1) for x, y in [(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (0, 1)]]
    lines = [g.addLine(p[a], p[b]) for a, b in [(0, 1), (1, 2), (2, 3), (3, 4), (4, 5), (5, 0), (1, 4)]]
    left = g.addPlaneSurface([g.addCurveLoop([lines[0], lines[6], lines[4], lines[5]])])
    right = g.addPlaneSurface([g.addCurveLoop([lines[1], lines[2], lines[3], -lines[6]])])
    g.synchronize()
    for name, line in zip(CURVES, lines):
        gmsh.model.addPhysicalGroup(1, [line], name=name)
    fluid = gmsh.model.addPhysicalGroup(2, [left], name="fluid")
    solid = gmsh.model.addPhysicalGroup(2, [right], name="solid")
    if recombine:
        gmsh.model.mesh.setRecombine(2, left)
    gmsh.model.mesh.generate(2)
    gmsh.option.setNumber("Mesh.MshFileVersion", version)
    gmsh.write(path)
    triangles = sum(len(t) for t in gmsh.model.mesh.getElementsByType(2)[:1])
    quads = len(gmsh.model.mesh.getElementsByType(3)[0]) if recombine else 0
    return {"fluid": fluid, "solid": solid, "nodes": len(gmsh.model.mesh.getNodes()[0]), "triangles": triangles,
            "quads": quads}


def gmsh_checks(pdmesh, run_dir, case, layered, tmp):
    try:
        import gmsh
        import meshio
    except ImportError as e:
        skip(e)
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    print(f"gmsh {gmsh.__version__}")
    # pdmesh's files in Gmsh.
    for label, directory, surfaces, types in [("two_regions", run_dir, ["region_1", "region_2"], [2]),
                                             ("layered", layered, ["domain", "boundary_layer"], [2, 3])]:
        if directory is None:
            continue
        gmsh.clear()
        gmsh.open(os.path.join(directory, "mesh.msh"))
        names = {d: [gmsh.model.getPhysicalName(d, t) for dd, t in gmsh.model.getPhysicalGroups(d) if dd == d]
                 for d in (1, 2)}
        want_curves = CURVES if label == "two_regions" else LAYERED_CURVES
        check(names[1] == want_curves and names[2] == surfaces,
              f"{label}: Gmsh's physical groups {names[1]} and {names[2]}")
        got = sorted(int(t) for t in gmsh.model.mesh.getElementTypes(2))
        check(got == types, f"{label}: element types {got} in dimension 2")
        for etype in types:
            tags = gmsh.model.mesh.getElementsByType(etype)[0]
            q = gmsh.model.mesh.getElementQualities(tags, "minSICN")
            check(len(q) == len(tags) and min(q) > 0,
                  f"{label}: Gmsh's minSICN of {len(tags)} elements of type {etype}: min {min(q):.3f}, all valid")
        lines = gmsh.model.mesh.getElementsByType(1)[0]
        check(len(lines) > 0, f"{label}: {len(lines)} boundary lines")
        # Saved again by Gmsh, the file reads back in pdmesh with its curves, regions and layer.
        resaved = os.path.join(tmp, f"{label}_resaved.msh")
        gmsh.write(resaved)
        if label == "two_regions":
            vtu = transfer(pdmesh, run_dir, resaved, tmp)
            if vtu is not None:
                m = meshio.read(vtu)
                region = sorted({float(x) for x in m.cell_data["region"][0]}) if "region" in m.cell_data else []
                check(region == [1.0, 2.0] and vtu_curve_names(m) == CURVES,
                      f"{label} saved by Gmsh: regions {region}, curves {vtu_curve_names(m)}")
        else:
            q = quality_json(pdmesh, resaved, tmp)
            layer = q.get("cells", {}).get("layer_cells") if q else None
            check(layer == "boundary_layer", f"{label} saved by Gmsh: pdmesh quality's layer cells: {layer}")
    # Gmsh's meshes in pdmesh.
    for recombine, version in [(False, 4.1), (False, 2.2), (True, 4.1)]:
        label = f"gmsh {version}{' recombined' if recombine else ''}"
        path = os.path.join(tmp, f"gmsh_{version}{'_quads' if recombine else ''}.msh")
        made = gmsh_mesh(gmsh, path, recombine, version)
        q = quality_json(pdmesh, path, tmp)
        if q is not None:
            check(q["points"] == made["nodes"] and q["triangles"] == made["triangles"],
                  f"{label}: pdmesh quality reads {q['points']} points, {q['triangles']} triangles "
                  f"(Gmsh: {made['nodes']}, {made['triangles']})")
            if recombine:
                quads = q.get("cells", {}).get("all", {}).get("quads", 0)
                check(quads == made["quads"], f"{label}: pdmesh quality counts {quads} quads (Gmsh: {made['quads']})")
        vtu = transfer(pdmesh, run_dir, path, tmp)
        if vtu is not None:
            m = meshio.read(vtu)
            names = vtu_curve_names(m)
            check(names == CURVES, f"{label}: the physical names are the curves {names}")
            region = sorted({int(x) for x in m.cell_data["region"][0]}) if "region" in m.cell_data else []
            # Recombined, transfer writes the quads and triangles as a mixed VTU, which carries no regions.
            want = [] if recombine else [made["fluid"], made["solid"]]
            check(region == want, f"{label}: the triangles' physical surfaces are regions {region} (want {want})")
        # Mesh.read: the recombined file's triangles all lie in the named group "solid", one named region.
        python_read(label, path, [made["solid"]] if recombine else [made["fluid"], made["solid"]], CURVES,
                    quads=made["quads"])
        if not recombine:
            smooth(pdmesh, path, case, tmp)
        if recombine or version != 4.1:
            continue
        # The same mesh as a Medit .mesh, by Gmsh and by meshio: Dimension 3, every vertex at z = 0.
        medit = {"Gmsh": os.path.join(tmp, "gmsh.mesh"), "meshio": os.path.join(tmp, "meshio.mesh")}
        gmsh.write(medit["Gmsh"])
        g = meshio.read(path)
        cells = [(c.type, c.data) for c in g.cells if c.type in ("line", "triangle")]
        refs = [g.cell_data["gmsh:physical"][k] for k, c in enumerate(g.cells) if c.type in ("line", "triangle")]
        meshio.write(medit["meshio"], meshio.Mesh(g.points, cells, cell_data={"medit:ref": refs}))
        for writer, mesh in medit.items():
            q = quality_json(pdmesh, mesh, tmp)
            if q is not None:
                check(q["points"] == made["nodes"] and q["triangles"] == made["triangles"],
                      f"{writer}'s .mesh: pdmesh quality reads {q['points']} points, {q['triangles']} triangles")
            vtu = transfer(pdmesh, run_dir, mesh, tmp)
            if vtu is not None:
                m = meshio.read(vtu)
                region = sorted({int(x) for x in m.cell_data["region"][0]}) if "region" in m.cell_data else []
                lines = read_medit(mesh)["Edges"]
                check(len(region) == 2 and len(vtu_curve_names(m)) == len({e[2] for e in lines}),
                      f"{writer}'s .mesh: regions {region}, curves {vtu_curve_names(m)}")
    gmsh.finalize()


def su2_checks(path, want_quads):
    """RUN/mesh.su2 by the SU2 native format's rules (su2code.github.io, "Mesh File")."""
    tokens = [ln.split("%")[0].strip() for ln in open(path, encoding="utf-8")]
    lines = [ln for ln in tokens if ln]
    k = 0

    def value(key):
        nonlocal k
        if not lines[k].startswith(key):
            check(False, f"su2: {key} at line {k + 1} (got '{lines[k][:30]}')")
        v = lines[k].split("=", 1)[1].split()
        k += 1
        return v

    check(value("NDIME=") == ["2"], "su2: NDIME= 2")
    nelem = int(value("NELEM=")[0])
    types = {}
    elements = [[int(x) for x in lines[k + i].split()] for i in range(nelem)]
    for f in elements:
        types[f[0]] = types.get(f[0], 0) + 1
    # A triangle (5) or quadrilateral (9), its nodes, and optionally the element's index.
    bad = [i for i, f in enumerate(elements) if f[0] not in (5, 9) or len(f) - 1 - {5: 3, 9: 4}[f[0]] not in (0, 1)]
    if not check(not bad, f"su2: every element a triangle or quadrilateral (first bad: {bad[:1]})"):
        return [], types
    k += nelem
    npoin = int(value("NPOIN=")[0])
    points = [tuple(float(x) for x in lines[k + i].split()[:2]) for i in range(npoin)]
    k += npoin
    check(all(0 <= n < npoin for f in elements for n in f[1:1 + {5: 3, 9: 4}[f[0]]]),
          f"su2: NELEM= {nelem} ({types}) index the NPOIN= {npoin} points from 0")
    def area(f):
        p = [points[n] for n in f[1:1 + {5: 3, 9: 4}[f[0]]]]
        return sum(p[i][0] * p[(i + 1) % len(p)][1] - p[(i + 1) % len(p)][0] * p[i][1] for i in range(len(p)))

    check(all(area(f) > 0 for f in elements), "su2: every element counter-clockwise (VTK's node order)")
    check((9 in types) == want_quads, f"su2: quadrilaterals (type 9) {'present' if want_quads else 'absent'}")
    nmark = int(value("NMARK=")[0])
    tags = []
    for _ in range(nmark):
        tags.append(value("MARKER_TAG=")[0])
        n = int(value("MARKER_ELEMS=")[0])
        bad = [ln for ln in lines[k:k + n] if ln.split()[0] != "3" or len(ln.split()) != 3]
        if bad:
            check(False, f"su2: marker {tags[-1]}: {n} lines of type 3 (first bad: '{bad[0]}')")
        k += n
    check(k == len(lines), f"su2: {nmark} markers {tags}, each of lines (type 3), nothing after them")
    return tags, types


def formats_checks(pdmesh, run_dir, layered, tmp):
    try:
        import meshio
        import pyvista
        import vtk
    except ImportError as e:
        skip(e)
    print(f"vtk {vtk.vtkVersion.GetVTKVersion()}, meshio {meshio.__version__}")
    for label, directory, curves, quads in [("two_regions", run_dir, CURVES, False),
                                            ("layered", layered, LAYERED_CURVES, True)]:
        if directory is None:
            continue
        with open(os.path.join(directory, "quality.json"), encoding="utf-8") as f:
            run_q = json.load(f)
        tags, types = su2_checks(os.path.join(directory, "mesh.su2"), quads)
        check(tags == curves, f"{label}: su2 markers {tags}")
        m = meshio.read(os.path.join(directory, "mesh.su2"))
        got = {c.type: len(c.data) for c in m.cells}
        check(got.get("triangle", 0) == types.get(5, 0) and got.get("quad", 0) == types.get(9, 0),
              f"{label}: meshio {meshio.__version__} reads the su2 cells {got}")
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(os.path.join(directory, "mesh.vtu"))
        reader.Update()
        grid = pyvista.wrap(reader.GetOutput())
        cell_types = {int(t): int((grid.celltypes == t).sum()) for t in set(grid.celltypes)}
        want = {5: types.get(5, 0)}
        if quads:
            want[9] = types.get(9, 0)
        check(grid.n_points == m.points.shape[0] and cell_types == want,
              f"{label}: VTK's XML reader: {grid.n_points} points, cells by type {cell_types} (su2: {want})")
        arrays = sorted(grid.cell_data.keys())
        want_arrays = ["boundary_layer"] if quads else ["min_angle", "region"]
        check(all(a in arrays for a in want_arrays), f"{label}: VTK's cell data {arrays}")
        if not quads:
            check(grid.n_cells == run_q["triangles"], f"{label}: {grid.n_cells} cells, quality.json's triangles")
            region = sorted(set(float(x) for x in grid.cell_data["region"]))
            check(region == [1.0, 2.0], f"{label}: VTK's region values {region}")


def main():
    global PDMESH_PY
    if "--python-path" in sys.argv:
        k = sys.argv.index("--python-path")
        sys.path.insert(0, sys.argv[k + 1])
        del sys.argv[k:k + 2]
        import pdmesh
        PDMESH_PY = pdmesh
    if len(sys.argv) < 4:
        print(__doc__)
        return 2
    what, pdmesh, run_dir = sys.argv[1], sys.argv[2], sys.argv[3]
    with tempfile.TemporaryDirectory(prefix=f"interop_{what}_") as tmp:
        if what == "formats":
            formats_checks(pdmesh, run_dir, sys.argv[4] if len(sys.argv) > 4 else None, tmp)
        elif what in ("mmg2d", "gmsh"):
            case = sys.argv[4]
            layered = sys.argv[5] if len(sys.argv) > 5 else None
            (mmg2d_checks if what == "mmg2d" else gmsh_checks)(pdmesh, run_dir, case, layered, tmp)
        else:
            print(__doc__)
            return 2
    print(f"{len(FAILURES)} failed" if FAILURES else "all passed")
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())
