// Shared declarations of the pdmesh._core extension (nanobind): the objects the binding files
// hand to each other, and one registration function per file.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include "app/config/case_file.hpp"
#include "app/pipeline/layer_pipeline.hpp"
#include "app/pipeline/mesh_inputs.hpp"
#include "app/pipeline/periodic_pipeline.hpp"
#include "app/pipeline/motion_stepper.hpp"
#include "io/mixed_mesh.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh::py {

namespace nb = nanobind;

// A validated case and the pipeline's first stages built from it (the inputs: geometry, tree, base
// field; the final spacing field), shared by a Mesher and every mesh it makes: a mesh measures its
// spacing conformance with the same field. With [[boundary_layer]] (as `pdmesh mesh`), `config`,
// `inputs` and `spacing` are the core's (the case on the layer fronts) and `layered` holds the case
// as given, its stages and the layers.
struct LayeredSession {
  CaseConfig config;
  std::unique_ptr<MeshInputs> inputs;
  std::unique_ptr<SpacingStage> spacing;  // over *inputs; the core's field refers to it
  std::unique_ptr<LayeredCase> layers;
};

// With [[periodic]]: the case as given and its stages; `inputs` and `spacing` of the Session are the
// case on the periodic nodes (PeriodicCase::core), whose field refers to this one's.
struct PeriodicSession {
  std::unique_ptr<MeshInputs> inputs;
  std::unique_ptr<SpacingStage> spacing;
  std::unique_ptr<PeriodicCase> periodic;
};

struct Session {
  std::unique_ptr<LayeredSession> layered;    // first: the core's field below refers to its field
  std::unique_ptr<PeriodicSession> periodic;  // the same
  CaseConfig config;
  std::unique_ptr<MeshInputs> inputs;
  std::unique_ptr<SpacingStage> spacing;  // over *inputs
  // Held (with the GIL released) while C++ uses the inputs: ExpressionSpacing is not thread-safe,
  // and two Python threads may drive one Mesher or measure its meshes at once.
  std::mutex mutex;
};

// The cells of a mesh with boundary layers beyond its triangles: the quadrangles, which triangles are
// the layer's, the merged mesh as the writers take it, and the core's mesh (its quality).
struct LayerParts {
  MixedMesh mixed;
  std::vector<std::array<int, 4>> quads;
  std::vector<std::uint8_t> triangle_layer;  // per triangle of MeshHandle::mesh: 1 in the layer
  Mesh core;
  std::vector<std::string> walls;  // the layers' wall curves (wall_curves): walls of an OpenFOAM mesh
};

// A mesh's periodic pairs, one link per [[periodic]] table (or per curve link of a file's $Periodic
// section), as mesh.msh's $Periodic holds them; for a mesh a run made also each table's transform as
// the run applied it (empty for a mesh read from a file: a file holds the affine matrix only).
struct PeriodicPairs {
  std::vector<PeriodicLink> links;
  std::vector<PeriodicTransform> transforms;
};

// A finished mesh and the session it came from (nullptr for a mesh read from a file). With layers,
// `mesh` holds every point and every triangle (core and layer), and `layers` the rest.
struct MeshHandle {
  std::shared_ptr<const Mesh> mesh;
  std::shared_ptr<Session> session;
  std::string name;  // picture titles
  std::shared_ptr<const LayerParts> layers;
  // Never null: no links without [[periodic]] (a motion step, a file without $Periodic).
  std::shared_ptr<const PeriodicPairs> periodic = std::make_shared<const PeriodicPairs>();
};

// A read-only numpy view of `count` rows of `Cols` values at `data`, kept alive by `keep` (a
// shared_ptr to whatever owns the memory): no copy is made.
template <class T, std::size_t Cols, class Keep>
nb::ndarray<nb::numpy, const T> shared_view(const T* data, std::size_t count, std::shared_ptr<Keep> keep) {
  auto* holder = new std::shared_ptr<Keep>(std::move(keep));
  nb::capsule owner(holder, [](void* p) noexcept { delete static_cast<std::shared_ptr<Keep>*>(p); });
  if constexpr (Cols == 1) {
    return nb::ndarray<nb::numpy, const T>(data, {count}, owner);
  } else {
    return nb::ndarray<nb::numpy, const T>(data, {count, Cols}, owner);
  }
}

// Point arrays as (name, (N, components) float64 array) pairs, copied: the transferred values that
// pdmesh.transfer and pdmesh.adapt return and Mesh.point_data holds (bind_motion.cpp).
nb::list point_value_list(const std::vector<PointValues>& data);

// Python's pdmesh.errors module (imported on first use).
nb::object errors_module();

// A motion step's row of motion.json as a dict (bind_stepper.cpp): the records of `run_motion` and
// `MovingMesher`.
nb::dict motion_record_dict(const MotionStepRecord& r);

void bind_config(nb::module_& m);
void bind_mesher(nb::module_& m);
void bind_mesh(nb::module_& m);
void bind_cli(nb::module_& m);
void bind_motion(nb::module_& m);
void bind_stepper(nb::module_& m);

}  // namespace pdmesh::py
