// VTK XML UnstructuredGrid (.vtu) writer: triangles with per-triangle quality metrics (and the
// regional attribute "region" when Mesh::region is set) as CellData,
// the node kind and the spacing field as PointData, and the boundary edges and curve names as
// FieldData. Binary (base64) by default, as VTK and meshio write; ASCII on request.
#pragma once
#include <string>
#include <string_view>

#include "core/text_sink.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

enum class VtuFormat {
  // format="binary": each array base64-encoded inline after a UInt64 byte count, in this machine's
  // byte order (declared in byte_order). Exact, about half the size of ASCII and several times
  // faster to write and read; still well-formed XML (unlike raw appended data).
  Binary,
  // format="ascii": numbers as text (%.17g for doubles, so they read back exactly).
  Ascii,
};

// Non-finite metric values (degenerate triangles) are written as +-1e300 in both forms, because
// VTK's ASCII parser does not read "inf". Kind is -1 for every point when the mesh does not know it.
// The <FieldData> element of every pdmesh .vtu, at `indent`: the boundary edges (point a, point b,
// curve) and the curve names as bytes, each followed by a 0 byte, so that a reader gets the curves back.
void write_vtu_curves(const Mesh& mesh, TextSink& sink, VtuFormat format, std::string_view indent);

// write_vtu appends the file's text to `sink` in pieces; vtu_string returns it whole.
void write_vtu(const Mesh& mesh, TextSink& sink, VtuFormat format = VtuFormat::Binary);
std::string vtu_string(const Mesh& mesh, VtuFormat format = VtuFormat::Binary);

}  // namespace pdmesh
