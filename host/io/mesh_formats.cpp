// Dispatch of the mesh writers by format name and of the readers by file extension.
#include "io/mesh_formats.hpp"

#include <algorithm>
#include <iterator>
#include <functional>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "core/text_sink.hpp"
#include "io/cgns_writer.hpp"
#include "io/fort14_writer.hpp"
#include "io/medit_reader.hpp"
#include "io/medit_writer.hpp"
#include "io/mesh_text.hpp"
#include "io/msh_reader.hpp"
#include "io/msh_writer.hpp"
#include "io/openfoam_writer.hpp"
#include "io/su2_reader.hpp"
#include "io/sms2dm_writer.hpp"
#include "io/su2_writer.hpp"
#include "io/text_file.hpp"
#include "io/triangle_reader.hpp"
#include "io/triangle_writer.hpp"
#include "io/vtu_reader.hpp"
#include "io/vtu_writer.hpp"

namespace pdmesh {

namespace {

struct MeshFormat {
  std::string name;
  std::vector<std::string> extensions;
};

// Every format write_mesh knows, in documentation order, with the files it writes.
const std::vector<MeshFormat>& mesh_formats() {
  static const std::vector<MeshFormat> formats = {
      {"msh", {".msh"}},
      {"msh22", {".msh"}},
      {"vtu", {".vtu"}},
      {"su2", {".su2"}},
      {"triangle", {".node", ".ele", ".poly"}},
      {"fort14", {".14"}},
      {"2dm", {".2dm"}},
      {"mesh", {".mesh"}},
      {"openfoam", {"_openfoam"}},
      {"cgns", {".cgns"}},
  };
  return formats;
}

}  // namespace

const std::vector<std::string>& mesh_format_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const MeshFormat& f : mesh_formats()) n.push_back(f.name);
    return n;
  }();
  return names;
}

const std::vector<std::string>& mesh_format_extensions(const std::string& name) {
  for (const MeshFormat& f : mesh_formats())
    if (f.name == name) return f.extensions;
  throw InputError(fmt::format("unknown mesh format '{}' (known: {})", name, fmt::join(mesh_format_names(), ", ")));
}

std::vector<std::filesystem::path> mesh_format_files(const std::string& name, const std::string& stem) {
  std::vector<std::filesystem::path> files;
  if (name == "openfoam") {
    for (const std::string& file : openfoam_file_names()) files.push_back(openfoam_polymesh_dir("", stem) / file);
    return files;
  }
  for (const std::string& ext : mesh_format_extensions(name)) files.emplace_back(stem + ext);
  return files;
}

bool mesh_format_is_read(const std::string& name) {
  return is_mesh_format(name) && name != "fort14" && name != "2dm" && name != "openfoam" && name != "cgns";
}

bool is_mesh_format(const std::string& name) {
  const auto& n = mesh_format_names();
  return std::find(n.begin(), n.end(), name) != n.end();
}

std::vector<std::filesystem::path> write_mesh(const Mesh& mesh, const std::filesystem::path& dir,
                                              const std::string& stem, const std::vector<std::string>& formats,
                                              const MeshWriteOptions& options) {
  for (const auto& f : formats) {
    if (!is_mesh_format(f)) {
      throw InputError(fmt::format("unknown mesh format '{}' (known: {})", f, fmt::join(mesh_format_names(), ", ")));
    }
  }
  const auto asked = [&](const char* name) { return std::find(formats.begin(), formats.end(), name) != formats.end(); };
  if (asked("msh") && asked("msh22")) {
    throw InputError("mesh formats 'msh' and 'msh22' both write STEM.msh; ask for one of them");
  }
  std::vector<std::filesystem::path> written;
  const auto put = [&](const std::string& ext, const std::string& content) {
    const auto path = dir / (stem + ext);
    write_text_file(path, content);
    written.push_back(path);
  };
  // The large formats go out in pieces (core/text_sink.hpp): a writer holds a few megabytes of its
  // file, not the whole file, beside the mesh.
  const auto stream = [&](const std::string& ext, const std::function<void(TextSink&)>& write) {
    const auto path = dir / (stem + ext);
    write_text_atomically(path, write);
    written.push_back(path);
  };
  for (const auto& f : formats) {
    const std::string& ext = mesh_format_extensions(f).front();
    if (f == "msh") {
      stream(ext, [&](TextSink& sink) {
        write_msh41(mesh, sink, options.periodic);
        if (options.msh_point_data) append_msh_point_data(sink, mesh);
      });
    } else if (f == "msh22") {
      stream(ext, [&](TextSink& sink) {
        write_msh22(mesh, sink, options.periodic);
        if (options.msh_point_data) append_msh_point_data(sink, mesh);
      });
    } else if (f == "vtu") {
      stream(ext, [&](TextSink& sink) { write_vtu(mesh, sink); });
    } else if (f == "su2") {
      stream(ext, [&](TextSink& sink) { write_su2(mesh, sink); });
    } else if (f == "fort14") {
      stream(ext, [&](TextSink& sink) { write_fort14(mesh, options.open_boundaries, sink); });
    } else if (f == "2dm") {
      stream(ext, [&](TextSink& sink) { write_sms2dm(mesh, sink); });
    } else if (f == "mesh") {
      stream(ext, [&](TextSink& sink) { write_medit(mesh, sink); });
    } else if (f == "openfoam") {
      // The regions as cellZones, named as the other formats name them.
      const RegionSurfaces surfaces = region_surfaces(mesh, 1);
      const OpenFoamZones zones{surfaces.names, surfaces.of_triangle};
      for (auto& p : write_openfoam(mixed_mesh_of(mesh, SurfaceCells{}), dir, stem, options.walls, mesh.curve_groups,
                                    surfaces.regions() ? &zones : nullptr))
        written.push_back(std::move(p));
    } else if (f == "cgns") {
      check_mesh_for_writing(mesh, "CGNS writer");
      // The regions as sections, BCs and families, named as the other formats name them.
      const RegionSurfaces surfaces = region_surfaces(mesh, 1);
      const CgnsRegions regions{surfaces.names, surfaces.of_triangle};
      const auto path = dir / (stem + ext);
      write_cgns(mixed_mesh_of(mesh, SurfaceCells{}), path, options.walls, mesh.curve_groups, &regions);
      written.push_back(path);
    } else if (f == "triangle") {
      const auto files = triangle_strings(mesh);
      const auto& exts = mesh_format_extensions(f);
      put(exts[0], files.node);
      put(exts[1], files.ele);
      put(exts[2], files.poly);
    }
  }
  return written;
}

std::vector<std::string> written_names(const std::filesystem::path& dir,
                                       const std::vector<std::filesystem::path>& written) {
  std::vector<std::string> names;
  for (const std::filesystem::path& p : written) {
    const std::filesystem::path relative = p.lexically_relative(dir);
    const bool nested = std::distance(relative.begin(), relative.end()) > 1;
    const std::string name = nested ? relative.begin()->string() + "/" : p.filename().string();
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  return names;
}

Mesh read_mesh(const std::filesystem::path& path, MeshReadReport& report, SurfaceCells* cells, MeshPointData* data) {
  const std::string ext = lower_extension(path);
  if (ext == ".msh") return read_msh(path, report, data, cells);
  if (ext == ".vtu") return read_vtu(path, report, data, cells);
  if (ext == ".su2") return read_su2(path, report, cells);
  if (ext == ".mesh" || ext == ".meshb") return read_medit_mesh(path, report, cells);
  if (ext == ".ele" || ext == ".node" || ext == ".poly") {
    auto ele = path;
    ele.replace_extension(".ele");
    return read_triangle(ele, report);
  }
  throw InputError(
      fmt::format("{}: unknown mesh file extension '{}' (known: .msh, .vtu, .su2, .mesh, .ele)", path.string(), ext));
}

Mesh read_mesh(const std::filesystem::path& path) {
  MeshReadReport report;
  return read_mesh(path, report);
}

}  // namespace pdmesh
