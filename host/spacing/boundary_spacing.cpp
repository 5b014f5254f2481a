// BoundarySpacing: thesis eq. 3.6, q = sum_s(l_s/d_s) / sum_s(1/d_s) over the closest segment s of
// each curve, with its continuous limit on the boundary (see docs/spacing.md).
#include <algorithm>
#include <exception>
#include <thread>
#include <vector>

#include "spacing/spacing_field.hpp"

namespace pdmesh {

BoundarySpacing::BoundarySpacing(const GeometryTree& tree) : tree_(tree) {}

double BoundarySpacing::at(Vec2 p) const {
  thread_local std::vector<ClosestHit> hits;
  tree_.closest_per_curve(p, hits);
  const auto& segs = tree_.geometry().segments;
  double d_min = -1.0;
  for (const ClosestHit& h : hits)
    if (h.segment >= 0 && (d_min < 0.0 || h.distance < d_min)) d_min = h.distance;
  if (d_min < 0.0) return 0.0;  // no segments at all: nothing to weight
  // Multiplying numerator and denominator by d_min gives weights d_min/d_s in (0, 1], which cannot
  // overflow however small d_min is. At d_min == 0 the weights become 1 for the curves at distance 0
  // and 0 for the others: exactly the limit of eq. 3.6, so q is continuous onto the boundary.
  double num = 0.0;
  double den = 0.0;
  for (const ClosestHit& h : hits) {
    if (h.segment < 0) continue;
    double w;
    if (d_min == 0.0) {
      w = h.distance == 0.0 ? 1.0 : 0.0;
    } else {
      w = d_min / h.distance;
    }
    num += w * segs[h.segment].length;
    den += w;
  }
  return num / den;
}

void BoundarySpacing::at_many(const std::vector<Vec2>& p, std::vector<double>& q) const {
  q.resize(p.size());
  // Every point is independent and at() is thread-safe, so splitting the range among threads gives the
  // same values as one loop. Below a few thousand points a thread costs more than it saves.
  constexpr std::size_t kPerThread = 4096;
  const std::size_t hardware = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t threads = std::min({hardware, kMaxThreads, (p.size() + kPerThread - 1) / kPerThread});
  std::vector<std::exception_ptr> errors(threads);
  auto run = [&](std::size_t t, std::size_t begin, std::size_t end) {
    try {
      for (std::size_t i = begin; i < end; ++i) q[i] = at(p[i]);
    } catch (...) {
      errors[t] = std::current_exception();  // rethrown on the calling thread below
    }
  };
  if (threads <= 1) {
    for (std::size_t i = 0; i < p.size(); ++i) q[i] = at(p[i]);
    return;
  }
  std::vector<std::thread> workers;
  const std::size_t chunk = (p.size() + threads - 1) / threads;
  for (std::size_t t = 1; t < threads; ++t)
    workers.emplace_back(run, t, std::min(p.size(), t * chunk), std::min(p.size(), (t + 1) * chunk));
  run(0, 0, std::min(p.size(), chunk));
  for (std::thread& w : workers) w.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace pdmesh
