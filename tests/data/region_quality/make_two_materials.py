"""Writes two_materials.msh: Gmsh's mesh of the rectangle [0, 2] x [0, 1] split at x = 1 into two
physical surfaces, "steel" (left, size 0.25) and "copper" (right, refined to size 0.08), MSH 2.2.
Run with the gmsh Python module: python make_two_materials.py"""
import gmsh

gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("two_materials")
geo = gmsh.model.geo
p = [geo.addPoint(x, y, 0) for x, y in [(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (0, 1)]]
bottom_left, bottom_right = geo.addLine(p[0], p[1]), geo.addLine(p[1], p[2])
right, top_right = geo.addLine(p[2], p[3]), geo.addLine(p[3], p[4])
top_left, left = geo.addLine(p[4], p[5]), geo.addLine(p[5], p[0])
middle = geo.addLine(p[1], p[4])
steel = geo.addPlaneSurface([geo.addCurveLoop([bottom_left, middle, top_left, left])])
copper = geo.addPlaneSurface([geo.addCurveLoop([bottom_right, right, top_right, -middle])])
geo.synchronize()
gmsh.model.addPhysicalGroup(1, [bottom_left, bottom_right, right, top_right, top_left, left], 1, "wall")
gmsh.model.addPhysicalGroup(2, [steel], 1, "steel")
gmsh.model.addPhysicalGroup(2, [copper], 2, "copper")
gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
gmsh.model.mesh.setSize(gmsh.model.getEntities(0), 0.25)
field = gmsh.model.mesh.field
box = field.add("Box")
field.setNumber(box, "VIn", 0.08)
field.setNumber(box, "VOut", 0.25)
field.setNumber(box, "XMin", 1.0)
field.setNumber(box, "XMax", 2.0)
field.setNumber(box, "YMin", 0.0)
field.setNumber(box, "YMax", 1.0)
field.setAsBackgroundMesh(box)
gmsh.model.mesh.generate(2)
gmsh.option.setNumber("Mesh.MshFileVersion", 2.2)
gmsh.write("two_materials.msh")
gmsh.finalize()
