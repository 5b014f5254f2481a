// MeshSpacing: a spacing field given as point data on a triangle mesh read from a file
// (spacing.field = "mesh", thesis ch. 7 "Spacing Field Adapted to Flow Solution"): q is linear in
// each triangle, and outside the mesh it is the value at the nearest point of the mesh.
#pragma once
#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "geometry/geometry.hpp"
#include "spacing/spacing_field.hpp"
#include "spacing/triangle_locator.hpp"

namespace pdmesh {

// How far outside the background mesh a point of the geometry may lie: the larger of
//   kMeshCoverTolerance x the geometry's bounding-box diagonal (coordinates rounded to about 7
//   significant digits still pass), and
//   kMeshCoverEdgeFraction x the length of the nearest boundary edge of the mesh. A mesh of the same
//   geometry whose boundary edges are chords that cut the corners of curved boundaries passes: pdmesh's
//   own meshes are such (boundary nodes slide off the curve points), and so is a coarser mesh of the
//   same curves (a chord of length e on radius R leaves points e^2 / (8R) outside, 1/16 e at e = R/2;
//   a chord cutting a 30-degree vertex, 0.134 e). A mesh of another domain is many edges away.
inline constexpr double kMeshCoverTolerance = 1e-6;
inline constexpr double kMeshCoverEdgeFraction = 0.25;

// The data MeshSpacing is built from, with what messages need to name points and the file.
struct MeshFieldData {
  std::vector<Vec2> points;
  std::vector<std::array<int, 3>> triangles;  // counter-clockwise (the readers turn clockwise ones)
  std::vector<double> q;                      // one value per point
  std::vector<std::uint8_t> given;            // per point: 1 when the file gives q there; empty = all
  std::string file;                           // for messages
  std::string array = "q";                    // for messages
  std::string array_where;                    // "FILE:LINE" of the array
  std::vector<long long> point_ids;           // MSH node tags (messages); empty: "point i"
};

class MeshSpacing final : public SpacingField {
 public:
  // Checks the data and builds the point-location structure. Throws InputError naming the file and
  // the value: no triangles; a vertex of a triangle without a value, or with a value that is not a
  // finite positive number; a triangle of zero area; an edge of more than two triangles; two
  // triangles that overlap (on the same side of a shared edge, or one's centroid inside another).
  explicit MeshSpacing(MeshFieldData data);

  // Linear interpolation in the triangle holding p; outside the mesh (or in a hole of it) the value
  // at the nearest point of its boundary. Always within the range of the data. Thread-safe.
  double at(Vec2 p) const override;
  // The same for many points; remembers the last triangle, so coherent batches skip most lookups,
  // and splits large batches among up to kMaxThreads threads. Bit-identical to at().
  void at_many(const std::vector<Vec2>& p, std::vector<double>& q) const override;
  static constexpr std::size_t kMaxThreads = 8;

  // Throws InputError naming the first geometry point (curve, index, coordinates, file) that lies
  // outside the mesh by more than allowed (kMeshCoverTolerance, kMeshCoverEdgeFraction above).
  void check_covers(const Geometry& geometry) const;

  const TriangleLocator& locator() const { return *locator_; }
  const MeshFieldData& data() const { return data_; }

 private:
  double outside(Vec2 p) const;
  std::string point_label(int i) const;
  void check_values() const;
  void check_triangles() const;
  void check_overlaps() const;

  MeshFieldData data_;
  std::unique_ptr<TriangleLocator> locator_;
};

}  // namespace pdmesh
