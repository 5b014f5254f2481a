// What the stages of `pdmesh mesh` share (app/pipeline/mesh_pipeline.cpp, simulate_stage.cpp, mesh_outputs.cpp,
// and the layer and periodic pipelines): the progress lines, the SVG size limit, the node outputs of a
// stage, the mesh pictures and the case of a core meshed on curves of its own. Internal to those files.
#pragma once
#include <cstddef>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>
#include <fmt/format.h>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "app/pipeline/run_phases.hpp"
#include "cleanup/cleanup.hpp"
#include "core/progress_notes.hpp"
#include "geometry/geometry.hpp"
#include "nodes/node_set.hpp"
#include "render/mesh_picture.hpp"

namespace pdmesh::mesh_detail {

// Every node is an element in an SVG; beyond this many the file would run to hundreds of
// megabytes, so only the PNG pictures (and zoomed views) are written.
inline constexpr std::size_t kSvgNodeLimit = 500'000;

// How long queued pictures wait for a simulation on a CPU device (run_core holds the initial ones before
// they are queued, simulate's run_on_backend for the simulation itself): on such a device the kernels
// keep every core busy, and a picture drawn beside them slows every kernel (each waits for its slowest
// thread); held, they are drawn beside the serial work after the simulation (the cleanup). 2 s at most,
// so that a long run still shows its initial pictures early.
inline constexpr double kPictureHoldSeconds = 2.0;

// One progress line on stderr unless the case is quiet (through the progress sink when run_mesh set
// one, so that the heartbeat knows the run is not silent).
template <class... Args>
void progress(const CaseConfig& config, fmt::format_string<Args...> format, Args&&... args) {
  if (config.quiet) return;
  const std::string line = fmt::format(format, std::forward<Args>(args)...);
  if (has_progress_sink())
    progress_line(line);
  else
    fmt::print(stderr, "{}\n", line);
}

// STAGE.nodes, and (as output.formats asks) STAGE.png and STAGE_<view>.png, STAGE.svg, for one node
// distribution (mesh_outputs.cpp). The pictures go to `run`'s background thread: `nodes` (and the tree
// quads) must stay unchanged until run.wait_pictures(), or, when `keep` owns them, until the pictures
// are drawn (each queued picture holds `keep`, so what it reads goes when the last one is done).
void write_node_outputs(const CaseConfig& config, const MeshInputs& inputs, const NodeSet& nodes,
                        const std::string& stage, const std::string& title, const std::vector<Box>* tree_quads,
                        RunPhases& run, const std::shared_ptr<const void>& keep = nullptr);

// mesh.png and mesh_<view>.png, one per output view (the view's name added to the title), as
// output.formats asks for png, queued on `run`'s background thread with `picture`'s options; returns
// their names (mesh_outputs.cpp). `mesh` and what `picture` points to must stay unchanged until
// run.wait_pictures(), or, when `keep` owns them, until the pictures are drawn.
std::vector<std::string> queue_mesh_views(const CaseConfig& config, const Mesh& mesh, const MeshPictureOptions& picture,
                                          RunPhases& run, const std::shared_ptr<const void>& keep = nullptr);

// The cleanup's options as the case's [cleanup] keys give them (mesh_outputs.cpp); the motion's steps
// start from them too.
CleanupOptions cleanup_options(const CaseConfig& config);

// The case of a core meshed on curves the run built from the case's (the layers' fronts, the periodic
// curves' nodes): `config` with `curves` as its geometry, given polylines already in the meshing plane,
// without its far field and regions (among the curves and in `field` already), and `field` (made from
// the case's field as asked, already scaled) as its base field; the case's relax_scale is kept.
inline CaseConfig core_case_on_curves(const CaseConfig& config, std::vector<RawCurve> curves,
                                      std::shared_ptr<const SpacingField> field) {
  CaseConfig core = config;
  core.geometry.files.clear();
  core.geometry.curve_names.clear();
  core.geometry.given_curves = std::move(curves);
  core.geometry.curves = CurveKind::Polyline;
  core.geometry.projection = ProjectionKind::None;
  core.farfield = {};
  core.spacing.regions.clear();
  core.spacing.given = std::move(field);
  core.spacing.scale = 1.0;
  return core;
}

}  // namespace pdmesh::mesh_detail
