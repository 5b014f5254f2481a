// A triangle mesh: points, counter-clockwise triangles, and the boundary edges per curve.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/vec2.hpp"
#include "nodes/node_set.hpp"

namespace pdmesh {

struct BoundaryEdge {
  int a = 0, b = 0;  // point indices, in curve order
  int curve = 0;     // index into Mesh::curve_names
};

// A point-data array beside a mesh's own (a motion run's "node_id", the arrays `pdmesh transfer`
// interpolates): `components` values per point, point-major; `integer` writes them as integers.
// The name of a regional attribute (Mesh::region): the writers call its region `name` instead of
// "region_<attribute>" (io/mesh_io_common.hpp, region_surfaces).
struct RegionName {
  double attribute = 0.0;
  std::string name;
};

// A physical group of curves with the tag a mesh file gave it (a Gmsh physical line): the writers
// give the edges of all its curves that tag and name (io/mesh_io_common.hpp, curve_tags).
struct CurveGroupTag {
  long long tag = 0;  // > 0
  std::string name;
  std::vector<int> curves;  // indices into Mesh::curve_names
};

struct PointValues {
  std::string name;
  int components = 1;
  std::vector<double> values;
  bool integer = false;
};

struct Mesh {
  std::vector<Vec2> points;
  std::vector<std::array<int, 3>> triangles;  // counter-clockwise
  std::vector<BoundaryEdge> boundary_edges;
  std::vector<std::string> curve_names;
  // Per curve_names entry, when known: 1 for an embedded constraint, whose edges have triangles on
  // both sides (docs/geometry-input.md, "Embedded constraints"). Empty: every curve bounds the domain.
  std::vector<std::uint8_t> constraint_curves;
  std::vector<NodeKind> kind;  // per point, when known (empty for meshes read from files)
  // Per point, when known: the spacing field q there. Written as point data "q" (VTU PointData, MSH
  // $NodeData), so that a run's field can be read back as spacing.field = "mesh". Not read back.
  std::vector<double> spacing;
  // Per triangle, when the geometry has regional attributes (.poly files): the attribute of the
  // region it lies in, 0 outside every region (mesh/region_tags.hpp). Written as the physical surface
  // of each triangle (MSH), cell data "region" (VTU) and the triangle attribute (Triangle .ele).
  std::vector<double> region;
  // Names of attributes of `region`, ascending by attribute, at most one per attribute (from the
  // geometry's regions or a mesh file's group names); an attribute without one is "region_<a>".
  std::vector<RegionName> region_names;
  // The curves' physical groups where a mesh file gave them (read from an MSH file, or kept from a
  // mesh file used as the geometry); a curve in none is numbered by its index (curve_tags). Empty for
  // geometry from curve, .poly and GIS files.
  std::vector<CurveGroupTag> curve_groups;
  // More point data, written by the VTU writer after "kind" and "q" (empty for a normal run).
  std::vector<PointValues> point_data;
};

}  // namespace pdmesh
