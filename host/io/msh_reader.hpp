// Gmsh MSH reader (ASCII 4.1 and 2.2, detected from $MeshFormat): nodes, 2-node lines as
// boundary edges grouped into curves by physical group, 3-node triangles, and on request $NodeData
// views (point data) and the 4-node quadrangles (SurfaceCells).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "io/mesh_io_common.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// Curves: the dimension-1 physical groups in tag order (named from $PhysicalNames, else
// "physical<tag>"), each with its tag in Mesh::curve_groups, then lines without a physical group per
// elementary entity ("entity<tag>").
// Other element types are skipped and counted in `report`. $Periodic links of curves go into
// report.periodic (their entities resolved to curves as their lines are; links of points and
// surfaces are skipped with a note). The triangles' 2-D physical groups are their regions
// (Mesh::region: a group "region_<a>" gives a, another its tag, and a name other than "domain" goes
// into Mesh::region_names; none when all lie in one group that names no region, or for a layered
// run's file). Throws InputError "FILE:LINE: ..."
// on truncation, bad counts, unknown node tags, binary files and unsupported versions.
// With `data`, the $NodeData view named data->wanted (its first string tag; of several blocks of
// that name, the last: the latest time step) is read into data->array, those data->decodes() into
// data->arrays, with the node tag of every point in data->point_ids, and the names of all views are
// listed.
//
// With `cells`, 4-node quadrangles (type 3) are read too instead of skipped (io/mesh_io_common.hpp
// SurfaceCells: the region is the 2-D physical group of that name).
Mesh parse_msh(const std::string& file_label, std::string content, MeshReadReport& report,
               MeshPointData* data = nullptr, SurfaceCells* cells = nullptr);
Mesh read_msh(const std::filesystem::path& path, MeshReadReport& report, MeshPointData* data = nullptr,
              SurfaceCells* cells = nullptr);

}  // namespace pdmesh
