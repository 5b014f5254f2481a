// pdmesh._core.motion_steps and transfer: a [motion] case's steps (app/pipeline/motion_pipeline), each
// handed to a Python callable with its mesh and persistent node ids, and the solution transfer between
// two meshes (mesh/transfer), from a mesh in memory or from a file's point arrays as pdmesh transfer
// and pdmesh adapt carry them; pdmesh.motion wraps them (docs/motion.md, "From Python").
#include <fmt/format.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "app/pipeline/motion_pipeline.hpp"
#include "app/pipeline/solution_transfer.hpp"
#include "bindings.hpp"
#include "core/errors.hpp"
#include "mesh/transfer.hpp"

namespace pdmesh::py {

namespace {

using Values = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using Points = nb::ndarray<const double, nb::shape<-1, 2>, nb::c_contig, nb::device::cpu>;

}  // namespace

nb::list point_value_list(const std::vector<PointValues>& data) {
  nb::list out;
  for (const PointValues& d : data) {
    const std::size_t k = static_cast<std::size_t>(d.components);
    // Integers as the file stored them (a .vtu's node ids, markers): int64, exact.
    if (d.integer) {
      auto* v = new std::vector<std::int64_t>(d.values.begin(), d.values.end());
      nb::capsule owner(v, [](void* p) noexcept { delete static_cast<std::vector<std::int64_t>*>(p); });
      out.append(nb::make_tuple(nb::str(d.name.c_str()),
                                nb::ndarray<nb::numpy, std::int64_t>(v->data(), {v->size() / k, k}, owner)));
      continue;
    }
    auto* v = new std::vector<double>(d.values);
    nb::capsule owner(v, [](void* p) noexcept { delete static_cast<std::vector<double>*>(p); });
    out.append(
        nb::make_tuple(nb::str(d.name.c_str()), nb::ndarray<nb::numpy, double>(v->data(), {v->size() / k, k}, owner)));
  }
  return out;
}

void bind_motion(nb::module_& m) {
  m.def(
      "motion_steps",
      [](const CaseConfig& c, const std::string& out_dir, nb::callable each) {
        if (!c.motion.enabled) throw InputError(fmt::format("{}: the case has no [motion] section", c.source.string()));
        CaseConfig config = c;
        config.quiet = true;
        config.write_outputs = !out_dir.empty();
        if (!out_dir.empty()) config.out_dir = out_dir;
        nb::gil_scoped_release release;
        run_motion_steps(config, [&](const MotionStep& s) {
          nb::gil_scoped_acquire acquire;
          MeshHandle handle;
          handle.mesh = std::make_shared<const Mesh>(s.mesh);
          handle.name = config.name;
          nb::dict record = motion_record_dict(s.record);
          record["node_id"] = s.nodes.id;
          each(handle, record);
        });
      },
      nb::arg("config"), nb::arg("out_dir"), nb::arg("each"),
      "Runs a [motion] case's steps; each(mesh, record) after every step (record['node_id']: the ids).");
  m.def(
      "transfer",
      [](const MeshHandle& from, Values values, Points at) {
        const Mesh& mesh = *from.mesh;
        if (values.shape(0) != mesh.points.size())
          throw InputError(
              fmt::format("transfer: {} rows of values for a mesh of {} points", values.shape(0), mesh.points.size()));
        const auto nc = static_cast<int>(values.shape(1));
        std::vector<double> v(values.data(), values.data() + values.shape(0) * values.shape(1));
        std::vector<Vec2> p(at.shape(0));
        for (std::size_t i = 0; i < p.size(); ++i) p[i] = {at(i, 0), at(i, 1)};
        std::vector<double> out;
        {
          nb::gil_scoped_release release;
          out = transfer_point_values(mesh, v, nc, p);
        }
        return out;
      },
      nb::arg("mesh"), nb::arg("values"), nb::arg("points"),
      "Point values (N, k) of `mesh` interpolated linearly at points (M, 2); a flat list of M * k values.");
  m.def(
      "transfer_file",
      [](const std::string& from, const std::vector<std::string>& arrays, Points at) {
        Mesh target;
        target.points.resize(at.shape(0));
        for (std::size_t i = 0; i < target.points.size(); ++i) target.points[i] = {at(i, 0), at(i, 1)};
        {
          nb::gil_scoped_release release;
          TransferCounts counts;
          (void)transfer_point_arrays(from, arrays, target, counts);
        }
        return point_value_list(target.point_data);
      },
      nb::arg("path"), nb::arg("arrays"), nb::arg("points"),
      "The point arrays of a .vtu or .msh file (empty: all but kind, q and node_id) interpolated at points "
      "(M, 2), as pdmesh transfer and pdmesh adapt carry them: [(name, (M, k) values)].");
}

}  // namespace pdmesh::py
