# Writes tests/data/layer_tags/cylinder.msh with Gmsh 4.15.2 (tools/.venv-anchors):
#   tools/.venv-anchors/bin/python tests/data/layer_tags/make_cylinder.py tests/data/layer_tags/cylinder.msh 0.5
# A channel with a cylinder beside a separate block: wall (1, 5) on the circle, farfield (1, 7) the
# channel's inlet and outlet, slip (1, 8) its top and bottom, block (1, 9) the block's four sides;
# surfaces fluid (2, 11, the channel) and solid (2, 22, the block).
import gmsh, sys
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("cylinder")
occ = gmsh.model.occ
channel = occ.addRectangle(-1.5, -1, 0, 3, 2)
block = occ.addRectangle(2, -0.5, 0, 1, 1)
disk = occ.addDisk(0, 0, 0, 0.25, 0.25)
occ.cut([(2, channel)], [(2, disk)])
occ.synchronize()
wall, far, slip, sides = [], [], [], []
for _, t in gmsh.model.getEntities(1):
    x0, y0, _, x1, y1, _ = gmsh.model.getBoundingBox(1, t)
    if x0 > 1.9: sides.append(t)
    elif x1 - x0 < 0.6 and y1 - y0 < 0.6: wall.append(t)
    elif abs(x1 - x0) < 1e-5: far.append(t)
    else: slip.append(t)
fluid = [t for _, t in gmsh.model.getEntities(2) if gmsh.model.getBoundingBox(2, t)[0] < 0]
solid = [t for _, t in gmsh.model.getEntities(2) if t not in fluid]
gmsh.model.addPhysicalGroup(1, wall, 5, "wall")
gmsh.model.addPhysicalGroup(1, far, 7, "farfield")
gmsh.model.addPhysicalGroup(1, slip, 8, "slip")
gmsh.model.addPhysicalGroup(1, sides, 9, "block")
gmsh.model.addPhysicalGroup(2, fluid, 11, "fluid")
gmsh.model.addPhysicalGroup(2, solid, 22, "solid")
gmsh.option.setNumber("Mesh.MeshSizeMax", float(sys.argv[2]))
gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 12)
gmsh.model.mesh.generate(2)
gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
gmsh.write(sys.argv[1])
print(wall, far, slip, sides, fluid, solid)
gmsh.finalize()
