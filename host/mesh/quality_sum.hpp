// Quality figures of a whole mesh measured triangle by triangle, keeping no per-triangle array: the
// summary (as summarize_quality computes it, bit for bit) and the values of one metric for pictures.
#pragma once
#include <string>
#include <vector>

#include "mesh/mesh.hpp"
#include "mesh/quality.hpp"

namespace pdmesh {

// summarize_quality's figures from the triangles' metrics added one at a time, in triangle order
// (the same sums in the same order: the same figures bit for bit), so that a multi-million-triangle
// mesh's summary needs no per-triangle array.
class QualityAccumulator {
 public:
  explicit QualityAccumulator(const QualityOptions& options = {});
  void add(const TriangleQuality& t);
  QualitySummary summary() const;

 private:
  QualityOptions options_;
  QualitySummary s_;
  double ar_sum_ = 0.0, skew_sum_ = 0.0, k_sum_ = 0.0;
};

// The per-triangle part of summarize_quality(mesh) (no points, constraints or spacing conformance).
// Throws InputError naming a triangle that refers to a point the mesh does not have.
QualitySummary summarize_quality_of(const Mesh& mesh, const QualityOptions& options = {});

// metric_values measured on the mesh's triangles (InputError for an unknown metric name).
std::vector<double> mesh_metric_values(const Mesh& mesh, const std::string& metric);

}  // namespace pdmesh
