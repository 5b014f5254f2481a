// `pdmesh quality`: reads a mesh in any supported format, prints the thesis-style quality table
// and optionally writes the JSON summary and a picture of the mesh. Spacing conformance needs the desired spacing q,
// which comes from a case file (its geometry and [spacing]) or a bare geometry file (eq. 3.6).
#pragma once
#include <array>
#include <iosfwd>
#include <optional>
#include <string>
#include <utility>

namespace pdmesh {

// `--picture`: the mesh drawn as a PNG or SVG, optionally zoomed and filled by a metric.
struct QualityPicture {
  std::string path;                                      // .png or .svg
  std::optional<std::array<double, 4>> window;           // x0, y0, x1, y1; default the mesh's extents + 3%
  std::string color_by = "none";                         // none, a metric name (metric_values) or region
  std::optional<std::pair<double, double>> color_range;  // colour scale; default the values' range
};

// geometry_path: a case .toml, or a geometry file (.crv/.dat/.poly) for the boundary spacing
// field; when absent, spacing conformance is skipped. out_json: "-" prints the JSON to `out`,
// an existing directory gets DIR/quality.json, anything else is the JSON file's path (written
// atomically). Reader notes (skipped elements, reoriented triangles) go to `err`.
// Returns 0; errors are thrown (InputError and friends) for main() to turn into exit codes.
// picture: also draw the mesh (written atomically; its path goes to `err`).
int run_quality(const std::string& mesh_path, const std::optional<std::string>& geometry_path,
                const std::optional<std::string>& out_json, std::ostream& out, std::ostream& err,
                const std::optional<QualityPicture>& picture = std::nullopt);
// The same printing to std::cout and std::cerr.
int run_quality(const std::string& mesh_path, const std::optional<std::string>& geometry_path,
                const std::optional<std::string>& out_json, const std::optional<QualityPicture>& picture);

}  // namespace pdmesh
