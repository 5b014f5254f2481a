// A mesh file as a case's geometry (docs/geometry-input.md, "A mesh as the geometry"): the domain is
// the union of the mesh's cells, its boundary the edges of one cell chained into loops and split into
// curves where the file's boundary name changes; named edges between two cells and the edges between
// cells of two regions become embedded constraints, and the regions' attributes region seeds.
#pragma once
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "geometry/geometry_files.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// True for the extensions a mesh geometry file has: .msh, .vtu, .su2, .mesh, .ele (case-insensitive,
// with the dot).
bool is_mesh_geometry_extension(const std::string& ext);

// "I (x, y)": point i of the mesh, for messages.
std::string mesh_node_text(const Mesh& mesh, int i);

// Throws InputError naming `label` when the mesh has no triangles, a triangle of zero area (its index,
// its nodes' indices and positions), or triangles of both orientations (`reoriented`: the triangles a
// reader turned counter-clockwise; the first of the smaller class is named as inverted).
void check_mesh_triangles(const Mesh& mesh, const std::vector<std::size_t>& reoriented, const std::string& label);

// The geometry of the cells (mesh.triangles, counter-clockwise, and `quads`, counter-clockwise):
//  - boundary curves: the edges of exactly one cell, chained into closed loops with the domain on
//    their left and split where the name of mesh.boundary_edges changes along a loop; a loop of one
//    name starts at its sharpest vertex. A curve keeps its name (characters other than letters,
//    digits and _ . + - turned into '_'); a stretch no boundary edge names is "boundary<k>".
//  - constraints (RawCurve::constraint): the named edges between two cells and, where mesh.region is
//    given, the edges between triangles of two attributes, chained between points where the name
//    changes, where three or more constraint edges meet, or on the boundary; unnamed ones
//    "interface<k>".
//  - a name given to more than one curve: the later ones become NAME_2, NAME_3, ... and a CurveGroup
//    NAME lists them all (a note says so), which selects them all by NAME.
//  - a physical group of the file (mesh.curve_groups): a CurveGroup with its tag over the curves made
//    from it (the same group as above where its name is on several curves), which the outputs write
//    as one group with that tag.
//  - regions: with mesh.region, a seed at a triangle's centroid per part of the domain the
//    constraints enclose, with that triangle's attribute (none for attribute 0).
//  - points: mesh.kind's Fixed nodes (Medit corners and required vertices) that are on the boundary
//    but not a curve's end, or inside on no quad (a layered mesh's fronts are Fixed).
// Holes need no points: the loops' even-odd interior is the union of the cells. InputError naming
// `file` for no cells, a zero-area triangle or quad, an edge of three or more cells, or a point where
// the boundary pinches (two loops through it: its index and coordinates).
RawGeometry mesh_as_geometry(const Mesh& mesh, const std::vector<std::array<int, 4>>& quads, const std::string& file);

// Reads `path` with read_mesh (triangles and quads), refuses a point off the plane z = 0 (a 3-D
// mesh: MeshReadReport::off_plane), inverted and zero-area triangles (check_mesh_triangles) and
// returns mesh_as_geometry.
RawGeometry read_mesh_geometry(const std::string& path);

// The reader read_geometry takes for mesh files (ReadSteps::other_files); their groups are handed on.
OtherGeometryFile mesh_geometry_files();

}  // namespace pdmesh
