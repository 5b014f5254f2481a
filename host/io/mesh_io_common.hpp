// Pieces every mesh writer and reader shares: curve labels as files can hold them, the checks
// a mesh passes before it is written, and what a reader reports besides the mesh.
#pragma once
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mesh/mesh.hpp"
#include "mesh/periodic_links.hpp"

namespace pdmesh {

// What a reader saw besides the mesh: elements it skipped (unsupported types, counted per reader)
// and clockwise triangles it turned counter-clockwise (Mesh promises counter-clockwise).
struct MeshReadReport {
  std::size_t skipped_elements = 0;
  std::size_t reoriented_triangles = 0;
  // The indices (into Mesh::triangles) of those triangles, in order: a mesh whose triangles are not
  // all of one orientation has inverted ones (pdmesh smooth names the first).
  std::vector<std::size_t> reoriented;
  std::vector<std::string> notes;  // one line each, e.g. "skipped 4 elements of type 3 (quadrangle)"
  // An MSH file's $Periodic links between curves (dimension 1), in the mesh's curve and point
  // indices, each with the largest |A p_source - p_image| by its affine transform (NaN without one).
  std::vector<PeriodicLink> periodic;
  // Where the first point off the plane z = 0 is ("FILE:LINE: node 7 has z = 0.5" for MSH, "FILE:
  // point 6 has z = 0.5" for VTU), empty when every point is at z = 0 (the readers keep x and y): a
  // mesh as the geometry must be planar (io/mesh_geometry.hpp). SU2 and Medit refuse such files.
  std::string off_plane;
};

// A point-data array read beside a mesh: `components` values per point, point-major. An MSH
// $NodeData may give values for a subset of the nodes: then `given` holds 1 per point that has one
// (the others are NaN); empty means every point has its values.
struct PointDataArray {
  std::string name;
  int components = 1;
  std::vector<double> values;
  std::vector<std::uint8_t> given;
  std::string where;     // "FILE:LINE" of the array, for messages
  bool integer = false;  // stored as integers in the file (a .vtu's Int32, UInt8, ...): exact in `values`
};

// What a reader found besides the mesh, for data fields (spacing.field = "mesh"), solution transfer
// and Python's Mesh.read. The caller names the arrays it wants; the reader decodes only those, in the
// one pass that reads the mesh, and lists the names of the others.
struct MeshPointData {
  std::string wanted;                   // in: a point-data array to decode into `array`
  std::optional<PointDataArray> array;  // out: that array, when the file has it
  // in: the point-data arrays to decode into `arrays`, by name, or every one with decode_all.
  std::vector<std::string> decode;
  bool decode_all = false;
  // out: those the file has, each name once, in file order (an MSH view given in several $NodeData
  // blocks, the time steps of a solution, from the last of them).
  std::vector<PointDataArray> arrays;
  std::vector<std::string> point_arrays;  // out: the name of every point-data array, in file order
  std::vector<std::string> other_arrays;  // out: other data ("NAME (cell data)"), for messages
  std::vector<long long> point_ids;       // out: MSH node tag of each point (messages name nodes by
                                          // tag); empty for VTU (points by index, ParaView's point id)
  bool decodes(std::string_view name) const {
    return decode_all || std::find(decode.begin(), decode.end(), name) != decode.end();
  }
};

// The quadrangles a reader takes beside the Mesh's triangles when it is handed one (only `pdmesh
// quality` does; every other caller reads triangles alone and the quads are skipped with a note), and
// which cells lie in the region named `region` (a layered run's "boundary_layer"): in an MSH file the
// 2-D physical group of that name, in a VTU file the cell-data array of that name (1 in it, 0 not);
// SU2 has no volume markers, so an SU2 reader never finds it. The quads are counter-clockwise
// (orient_quads_ccw); triangle_in_region follows Mesh::triangles, quad_in_region follows quads.
struct SurfaceCells {
  std::string region;                                            // in
  std::vector<std::array<int, 4>> quads;                         // out
  std::vector<std::uint8_t> triangle_in_region, quad_in_region;  // out: 1 in the region
  bool region_found = false;                                     // out: the file names the region
};

// The name of curve c as written: its name, or "curve<c>" when empty, as writable_name makes it.
std::string curve_label(const Mesh& mesh, std::size_t c, bool no_blanks = false);

// Throws InputError naming the triangle/edge/curve when an index is out of range or when
// `kind` is neither empty nor one per point. Every writer calls this first.
void check_mesh_for_writing(const Mesh& mesh, const std::string& what);

// A name as a file can hold it: double quotes and line breaks become '_' (MSH quotes names), and with
// `no_blanks` also spaces and tabs (SU2 markers).
std::string writable_name(std::string name, bool no_blanks = false);

// The name Mesh::region_names gives regional attribute `attribute`; empty when it has none.
std::string_view region_name(const Mesh& mesh, double attribute);

// The name of regional attribute `attribute` as written: its region_name (writable_name), else
// "region_<attribute>".
std::string region_label(const Mesh& mesh, double attribute);

// The triangles' subdomains as the writers name them: one "domain" without regional attributes
// (Mesh::region empty), otherwise one region_label per distinct attribute, ascending, and per
// triangle the index of its attribute there (MSH physical surfaces, Medit triangle references).
// Each has a tag (MSH dimension-2 physical tag, Medit triangle reference): an attribute that is a
// positive integer (at most 2^31 - 1: a mesh file's physical tag or reference, a .poly's whole
// attribute) is its own tag; any other (0 outside every region, a fraction, a negative number) and
// "domain" take `first` + its index in `names`, or the next number up no other surface takes.
struct RegionSurfaces {
  std::vector<std::string> names;
  std::vector<long long> tags;     // per name
  std::vector<double> attributes;  // the attribute each name stands for; empty for the one "domain"
  std::vector<int> of_triangle;    // index into names per triangle
  bool regions() const { return names.size() != 1 || names.front() != "domain"; }
};
RegionSurfaces region_surfaces(const Mesh& mesh, long long first);
// The attribute a region_surfaces name "region_<a>" stands for (the readers take regions back by it);
// nullopt for any other name ("domain", "boundary_layer", a name a user gave).
// A reader's group or reference names other than these stand for their own attribute (the group's tag,
// the reference) and go into Mesh::region_names.
std::optional<double> region_attribute(std::string_view name);

// The tags the writers give the curves (MSH dimension-1 physical tags, Medit edge references, SU2
// markers, Triangle segment markers): a curve in a physical group (Mesh::curve_groups, the first that
// lists it) has its group's tag; the others, in curve order, the smallest numbers from 1 that no group
// and no earlier curve takes (curve c has c + 1 when there are no groups).
struct CurveTags {
  struct Group {
    long long tag = 0;
    std::string name;         // the group's name, or the curve's curve_label (not yet writable_name'd)
    std::vector<int> curves;  // ascending
  };
  std::vector<long long> of_curve;                // per curve
  std::vector<Group> groups;                      // one per tag, ascending by tag; a curve in no group is a group alone
  std::size_t group_of_tag(long long tag) const;  // index into groups
};
CurveTags curve_tags(const Mesh& mesh);

// Boundary edge indices grouped by curve (stable: curve order, then file order within a curve).
std::vector<std::size_t> boundary_edges_by_curve(const Mesh& mesh);

// Coordinates are written with 17 significant digits, which reads back to the same double.
std::string coord(double v);

// Reader post-processing: turns clockwise triangles counter-clockwise (exact orientation test),
// counting them in `report`.
void orient_triangles_ccw(Mesh& mesh, MeshReadReport& report);
// The same for quadrangles, by the sign of their area (shoelace), with the note "FILE: turned N
// clockwise quadrangles counter-clockwise".
void orient_quads_ccw(const std::vector<Vec2>& points, std::vector<std::array<int, 4>>& quads, const std::string& file,
                      MeshReadReport& report);

}  // namespace pdmesh
