// Reading metric data on a background triangle mesh, for spacing/mesh_metric_field's
// MeshMetricField: a .vtu or .msh mesh with a 3-component point array (m11, m12, m22), read as
// io/spacing_mesh_file reads the scalar spacing data field, or mmg's Medit pair, a .mesh with a .sol
// whose SolAtVertices block holds one symmetric tensor (type 3) per vertex (io/medit_reader).
// Not yet read from case files: docs/metric-fields.md.
#pragma once
#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/vec2.hpp"
#include "spacing/mesh_metric_field.hpp"
#include "spacing/metric.hpp"

namespace pdmesh {

// Points, counter-clockwise triangles and one checked SPD metric per point.
struct MetricMeshData {
  std::vector<Vec2> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<Metric> metrics;
  std::string what;  // the file(s) and array, for MeshMetricField's messages
};

// Reads FILE (.vtu or .msh by extension) and its point-data array `array` of 3 components per point,
// m11 m12 m22. Throws InputError naming the file (and the array's line) when the file cannot be read,
// has no triangles, has no such array (listing those it has), the array does not have 3 components,
// a vertex of a triangle has no value (an MSH $NodeData may give a subset), or a value is not finite
// or not SPD (naming the point, its coordinates and the three values).
MetricMeshData load_metric_mesh(const std::filesystem::path& file, const std::string& array);

// Scalar data on a background triangle mesh (the function a Hessian metric is built from).
struct ScalarMeshData {
  std::vector<Vec2> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<double> values;
  std::string what;  // the file and array, for messages
};

// Reads FILE (.vtu or .msh) and its point-data array `array` of 1 component. Throws InputError naming
// the file (and the array's line) when it cannot be read, has no triangles, has no such array (listing
// those it has), the array is not a scalar, or a vertex of a triangle has no value or a value that is
// not finite (naming the point, its coordinates and the value).
ScalarMeshData load_scalar_mesh(const std::filesystem::path& file, const std::string& array);

// The field of the data (MeshMetricField's own checks follow: triangle areas, indices).
std::unique_ptr<MeshMetricField> make_mesh_metric_field(MetricMeshData data);

}  // namespace pdmesh
