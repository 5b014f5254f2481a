// CallableSpacing: the (N, 2) points go to Python in one array, the sizes come back in one array.
#include "callable_spacing.hpp"

#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <nanobind/ndarray.h>

#include "core/errors.hpp"

namespace pdmesh::py {

namespace nb = nanobind;

CallableSpacing::CallableSpacing(nb::object sample) : sample_(std::move(sample)) {}

CallableSpacing::~CallableSpacing() {
  // The last reference may go away while the GIL is released (a Mesher freed from C++).
  nb::gil_scoped_acquire gil;
  sample_.reset();
}

double CallableSpacing::at(Vec2 p) const {
  std::vector<double> q;
  at_many({p}, q);
  return q[0];
}

void CallableSpacing::at_many(const std::vector<Vec2>& p, std::vector<double>& q) const {
  q.resize(p.size());
  if (p.empty()) return;
  const auto start = std::chrono::steady_clock::now();
  nb::gil_scoped_acquire gil;
  // The callable may keep the array it is given, so it gets its own copy (16 bytes a point, next to
  // the Python work per point this is nothing), owned by the array.
  auto* xy = new std::vector<Vec2>(p);
  nb::capsule owner(xy, [](void* v) noexcept { delete static_cast<std::vector<Vec2>*>(v); });
  nb::ndarray<nb::numpy, double, nb::shape<-1, 2>> array(xy->data(), {p.size(), 2}, owner);
  ++calls_;
  points_ += p.size();
  nb::object result = sample_(array);
  const auto h = nb::cast<nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>>(result);
  if (h.shape(0) != p.size())
    throw InputError(fmt::format("size: the callable returned {} sizes for {} points; it must return one per point",
                                 h.shape(0), p.size()));
  const double* v = h.data();
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!(std::isfinite(v[i]) && v[i] > 0.0))
      throw InputError(fmt::format("size: the callable returned {} at ({}, {}); a size must be finite and > 0", v[i],
                                   p[i].x, p[i].y));
    q[i] = v[i];
  }
  nanoseconds_ +=
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace pdmesh::py
