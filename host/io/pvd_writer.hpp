// ParaView data collection (.pvd): a time series of mesh files, one <DataSet timestep="t" file="..."/>
// per step, the paths relative to the .pvd (docs/motion.md). ParaView, VTK's vtkPVDReader and
// meshio-style readers open it.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace pdmesh {

struct PvdEntry {
  double time = 0.0;
  std::string file;  // relative to the .pvd's directory, '/'-separated
};

std::string pvd_string(const std::vector<PvdEntry>& entries);
// Written atomically (core/atomic_file).
void write_pvd(const std::filesystem::path& path, const std::vector<PvdEntry>& entries);

}  // namespace pdmesh
