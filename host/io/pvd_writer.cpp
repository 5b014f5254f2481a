// The .pvd time series writer (pvd_writer.hpp).
#include "io/pvd_writer.hpp"

#include "core/atomic_file.hpp"
#include "core/g17.hpp"

namespace pdmesh {

std::string pvd_string(const std::vector<PvdEntry>& entries) {
  std::string out =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  for (const PvdEntry& e : entries) {
    std::string file = e.file;  // an attribute value: no markup characters
    for (char& ch : file)
      if (ch == '"' || ch == '<' || ch == '>' || ch == '&') ch = '_';
    out += "    <DataSet timestep=\"";
    append_g17(out, e.time);
    out += "\" group=\"\" part=\"0\" file=\"" + file + "\"/>\n";
  }
  out += "  </Collection>\n</VTKFile>\n";
  return out;
}

void write_pvd(const std::filesystem::path& path, const std::vector<PvdEntry>& entries) {
  write_file_atomically(path, pvd_string(entries));
}

}  // namespace pdmesh
