#!/usr/bin/env python3
"""Writes the background-mesh fixtures of tests/test_mesh_spacing.cpp with the tools users have:
VTK's own XML writer in each of its encodings, meshio's writer, and Gmsh's view writer.

Needs the PyPI packages vtk and meshio (e.g. in a throw-away venv) and the gmsh binary; it is not run
by the build. The field is q = 1 + x/2 + y/4 on a 5 x 5 grid of the unit square (interior points
jittered), 32 triangles, with a second 3-component point array "velocity". expected.txt holds
x y q of every point with 17 digits.
"""
import os
import subprocess

import meshio
import numpy as np
import vtk

N = 5


def grid():
    rng = np.random.default_rng(7)
    pts = []
    for j in range(N):
        for i in range(N):
            x, y = i / (N - 1), j / (N - 1)
            if 0 < i < N - 1 and 0 < j < N - 1:
                x += (rng.random() - 0.5) * 0.08
                y += (rng.random() - 0.5) * 0.08
            pts.append((x, y, 0.0))
    tris = []
    for j in range(N - 1):
        for i in range(N - 1):
            a, b, c, d = j * N + i, j * N + i + 1, (j + 1) * N + i + 1, (j + 1) * N + i
            tris += [(a, b, c), (a, c, d)]
    return np.array(pts), np.array(tris)


def vtk_grid(pts, tris, q):
    ug = vtk.vtkUnstructuredGrid()
    vp = vtk.vtkPoints()
    vp.SetDataTypeToDouble()
    for p in pts:
        vp.InsertNextPoint(*p)
    ug.SetPoints(vp)
    for t in tris:
        ids = vtk.vtkIdList()
        for v in t:
            ids.InsertNextId(int(v))
        ug.InsertNextCell(vtk.VTK_TRIANGLE, ids)
    arr = vtk.vtkDoubleArray()
    arr.SetName("q")
    for v in q:
        arr.InsertNextValue(v)
    ug.GetPointData().AddArray(arr)
    vel = vtk.vtkDoubleArray()
    vel.SetName("velocity")
    vel.SetNumberOfComponents(3)
    for p in pts:
        vel.InsertNextTuple3(p[1], -p[0], 0)
    ug.GetPointData().AddArray(vel)
    return ug


def write_vtk(ug, name, mode, encode=True, zlib=True, header=32, big=False):
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetFileName(name)
    w.SetInputData(ug)
    w.SetDataMode(mode)  # 0 ascii, 1 binary (inline base64), 2 appended
    w.SetEncodeAppendedData(encode)
    if not zlib:
        w.SetCompressorTypeToNone()
    w.SetHeaderType(header)
    if big:
        w.SetByteOrderToBigEndian()
    w.SetBlockSize(128)  # several compressed blocks per array, the last one partial
    assert w.Write() == 1


def main():
    os.chdir(os.path.dirname(os.path.abspath(__file__)))
    pts, tris = grid()
    q = 1.0 + 0.5 * pts[:, 0] + 0.25 * pts[:, 1]
    np.savetxt("expected.txt", np.column_stack([pts[:, :2], q]), fmt="%.17g")
    ug = vtk_grid(pts, tris, q)
    write_vtk(ug, "vtk_default.vtu", 2)  # VTK's defaults: appended, base64, zlib
    write_vtk(ug, "vtk_appended_raw_zlib.vtu", 2, encode=False)  # ParaView's "Save Data" default
    write_vtk(ug, "vtk_appended_raw_u64.vtu", 2, encode=False, zlib=False, header=64)
    write_vtk(ug, "vtk_binary_zlib.vtu", 1)
    write_vtk(ug, "vtk_binary_bigendian.vtu", 1, zlib=False, header=64, big=True)
    write_vtk(ug, "vtk_ascii.vtu", 0)
    meshio.write("meshio_binary_zlib.vtu",
                 meshio.Mesh(pts, [("triangle", tris)], point_data={"q": q}))
    # Gmsh: a plain MSH 2.2 file with $NodeData, loaded by Gmsh and saved as a view in both versions.
    with open("hand.msh", "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % len(pts))
        for k, p in enumerate(pts):
            f.write("%d %.17g %.17g 0\n" % (k + 1, p[0], p[1]))
        f.write("$EndNodes\n$Elements\n%d\n" % len(tris))
        for k, t in enumerate(tris):
            f.write("%d 2 2 1 1 %d %d %d\n" % (k + 1, t[0] + 1, t[1] + 1, t[2] + 1))
        f.write('$EndElements\n$NodeData\n1\n"q"\n1\n0\n3\n0\n1\n%d\n' % len(pts))
        for k, v in enumerate(q):
            f.write("%d %.17g\n" % (k + 1, v))
        f.write("$EndNodeData\n")
    with open("save.geo", "w") as f:
        f.write('Mesh.MshFileVersion = 2.2;\nSave View[0] "gmsh_view_22.msh";\nMesh.MshFileVersion = 4.1;\n'
                'Save View[0] "gmsh_view_41.msh";\n')
    subprocess.run(["gmsh", "hand.msh", "save.geo", "-nopopup", "-0"], check=True, capture_output=True)
    for f in ("hand.msh", "save.geo", "hand.geo_unrolled"):
        if os.path.exists(f):
            os.remove(f)


if __name__ == "__main__":
    main()
