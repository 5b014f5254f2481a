// `pdmesh smooth MESH --geometry G`: pdmesh as a smoother of a triangle mesh made elsewhere
// (docs/smoothing.md). The mesh is read and checked against the geometry, its nodes start a warm run
// (init.file) and, by default, its own local edge lengths are the spacing field (the user's sizing
// kept); the run is then `pdmesh mesh`'s (run_mesh), with the usual outputs.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// Where the spacing of a smoothing run comes from: the input mesh's own spacing (node_spacing, times
// kSmoothMeshScale), or the case's own field.
enum class SmoothField { Mesh, Case };

// The factor on the mesh's spacing that keeps its node count: the best preset's relax_scale brings the
// mean edge to about q (docs/smoothing.md, "Node count"), and 0.98, a little less than 1, centres the
// counts measured on Gmsh's meshes. Applied as spacing.scale (a case key the user may override).
inline constexpr double kSmoothMeshScale = 0.98;

// The gradation limit of a smoothing run with the mesh's field: Gmsh grows its sizes away from the
// boundary faster than pdmesh's default 0.2 allows (0.2 adds 8-12 % nodes to its airfoil meshes), and
// unlimited growth leaves triangles the relaxation and cleanup do not repair (29-35 degrees on three
// of them). 0.3 keeps the count within 4 % and every angle away from sharp input corners at 38 degrees
// or more on the 13 measured meshes; 0.4 and 0.35 left 37.8 and 38.1 degrees where the size falls
// tenfold within a tenth of the domain's edge (docs/smoothing.md, "Measured"). spacing.gradation.
inline constexpr double kSmoothGradation = 0.3;

// population.stop and simulation.stop_aspect of a smoothing run, which also keeps the automatic step
// (simulation.dt_initial "auto"): the values its measurements were made with (docs/smoothing.md,
// "Measured"). Another mesher's mesh starts further from the count the field asks for than pdmesh's
// fill, so its population control needs longer than the best preset's 0.15 gives it, and its nodes
// the automatic step.
inline constexpr double kSmoothPopulationStop = 0.2;
inline constexpr double kSmoothStopAspect = 7e-4;

// A boundary node of the input mesh may lie this share of its boundary edges' mean length off the
// geometry's curves (and always 1e-6 x the geometry's diagonal, for rounded coordinates).
inline constexpr double kSmoothBoundaryTolerance = 0.1;

// The input mesh read from `file` (any format read_mesh reads) and checked: triangles present; every
// triangle of one orientation and of nonzero area. Throws InputError naming the file, the first
// inverted or degenerate triangle (its index and its nodes' indices and positions); `label` names the
// mesh in those messages (empty: the file).
Mesh read_smooth_mesh(const std::filesystem::path& file, const std::string& label = "");

// The same checks on a mesh given in memory (the Python API); `label` names it in messages. Turns
// clockwise triangles counter-clockwise when all are clockwise.
void check_smooth_mesh(Mesh& mesh, const std::string& label);

// Throws InputError naming `label` when the mesh is not a mesh of `geometry`: its extent does not
// overlap the geometry's, a node on its boundary edges lies farther from the curves than
// kSmoothBoundaryTolerance allows (the first such node: index, position, distance, allowed), or a
// point of the geometry lies outside the mesh (MeshSpacing::check_covers).
void check_mesh_on_geometry(const Mesh& mesh, const std::string& label, const Geometry& geometry,
                            const GeometryTree& tree);

// The mesh's own spacing at each node: on the boundary (a node of an edge of one triangle) the mean
// length of its boundary edges, so that the boundary keeps its division; inside, the edge of the
// equilateral mesh of the same node density, sqrt(2 A / sqrt(3)) with A a third of the area of the
// triangles at the node, so that the count is kept whatever the triangles' shapes (the mean edge at a
// node of a right-triangle grid, 1.14 h, would lose 22 % of its nodes). Nodes in no triangle get 0.
std::vector<double> node_spacing(const Mesh& mesh);

// The case keys a smoothing run sets before the user's --set overrides (which win): preset "best"
// (population control and the converged stop; a thesis case's own preset would keep the count and
// run its 2000 iterations), the cleanup's sharp-corner scores (cleanup.sharp_corners), and with
// SmoothField::Mesh the mesh's field (spacing.scale =
// kSmoothMeshScale, spacing.gradation = kSmoothGradation; no feature size or curvature rule).
std::vector<CaseOverride> smooth_overrides(SmoothField field);

// The smallest angle (degrees) of the mesh's triangles, leaving out the angle of a triangle alone at a
// boundary node where that angle (the domain's there) is below `degrees`: no mesh with a node there does
// better.
double min_angle_apart_from_sharp_corners(const Mesh& mesh, double degrees);

// Makes `config` (a case or geometry file's, with smooth_overrides and the user's overrides applied)
// the smoothing run of `mesh`, read from `file`: init.file = file, and with SmoothField::Mesh the
// spacing field given as the node_spacing on the mesh. Reads the geometry and runs
// check_mesh_on_geometry. A mesh at the cleanup's target already (min_angle_apart_from_sharp_corners at
// least cleanup.min_angle) whose nodes match the curves keeps them (init.kept): no iterations, and the
// cleanup's smoothing sweeps without topology changes.
void make_smooth_config(CaseConfig& config, const Mesh& mesh, const std::filesystem::path& file,
                        const std::string& label, SmoothField field);

// The command: reads and checks MESH, then run_mesh. Nothing is written when a check fails.
int run_smooth(CaseConfig config, const std::filesystem::path& mesh_file, SmoothField field);

}  // namespace pdmesh
