// Stage mesh (mesh_and_measure, mesh_pipeline.hpp) for a caller that owns the simulation's final mesh
// (SimResult::final_mesh) and hands it over: the stage lets it go as soon as it has its own copy, so
// that the cleanup, the quality and the writers do not run beside a second mesh of every node.
#pragma once
#include <memory>

#include "app/pipeline/mesh_pipeline.hpp"

namespace pdmesh {

Mesh mesh_and_measure(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing,
                      const NodeSet& nodes, RunPhases* run, std::shared_ptr<const Mesh>&& triangulated);

}  // namespace pdmesh
