// A spacing field given as a Python callable h(xy) -> sizes, evaluated vectorised: one call per
// at_many() (one per sampling pass of the background field), never one per point.
#pragma once
#include <atomic>
#include <cstddef>
#include <vector>

#include <nanobind/nanobind.h>

#include "spacing/spacing_field.hpp"

namespace pdmesh::py {

class CallableSpacing final : public SpacingField {
 public:
  // `sample` takes an (N, 2) float64 array and returns N float64 sizes as a 1-D contiguous array
  // (the Python layer, pdmesh/_size.py, wraps the user's callable so that it does).
  explicit CallableSpacing(nanobind::object sample);
  ~CallableSpacing() override;
  CallableSpacing(const CallableSpacing&) = delete;
  CallableSpacing& operator=(const CallableSpacing&) = delete;

  double at(Vec2 p) const override;
  // Acquires the GIL for the call. InputError naming the point for a size that is not finite and > 0,
  // or a result of the wrong length; the callable's own exceptions pass through.
  void at_many(const std::vector<Vec2>& p, std::vector<double>& q) const override;

  std::size_t calls() const { return calls_.load(); }
  std::size_t points() const { return points_.load(); }
  // Wall time inside at_many(): the hand-over both ways, the callable and the checks.
  double seconds() const { return nanoseconds_.load() * 1e-9; }

 private:
  nanobind::object sample_;
  mutable std::atomic<std::size_t> calls_{0};
  mutable std::atomic<std::size_t> points_{0};
  mutable std::atomic<long long> nanoseconds_{0};
};

}  // namespace pdmesh::py
