// `pdmesh quality`: reads a mesh in any supported format, prints the thesis-style quality table
// and optionally writes the JSON summary. Spacing conformance needs the desired spacing q, which
// comes from a case file (its geometry and [spacing]) or a bare geometry file (eq. 3.6).
#pragma once
#include <iosfwd>
#include <optional>
#include <string>

namespace pdmesh {

// geometry_path: a case .toml, or a geometry file (.crv/.dat/.poly) for the boundary spacing
// field; when absent, spacing conformance is skipped. out_json: "-" prints the JSON to `out`,
// an existing directory gets DIR/quality.json, anything else is the JSON file's path (written
// atomically). Reader notes (skipped elements, reoriented triangles) go to `err`.
// Returns 0; errors are thrown (InputError and friends) for main() to turn into exit codes.
int run_quality(const std::string& mesh_path, const std::optional<std::string>& geometry_path,
                const std::optional<std::string>& out_json, std::ostream& out, std::ostream& err);
// The same printing to std::cout and std::cerr.
int run_quality(const std::string& mesh_path, const std::optional<std::string>& geometry_path,
                const std::optional<std::string>& out_json);

}  // namespace pdmesh
