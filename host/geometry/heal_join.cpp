// join_rings() (heal_join.hpp).
#include "geometry/heal_join.hpp"

#include <algorithm>
#include <cmath>

#include "core/predicates.hpp"

namespace pdmesh::detail {

namespace {

Box segment_box(Vec2 a, Vec2 b) {
  Box box;
  box.add(a);
  box.add(b);
  return box;
}

bool overlap(const Box& x, const Box& y) {
  return !(x.hi.x < y.lo.x || y.hi.x < x.lo.x || x.hi.y < y.lo.y || y.hi.y < x.lo.y);
}

// A point where segments a-b and c-d (which intersect) meet: the crossing of their lines, or for
// a touch or an overlap along a line the end point of one that is closest to the other.
Vec2 meeting_point(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const Vec2 r = b - a, s = d - c;
  const double den = cross(r, s);
  if (std::fabs(den) > 1e-12 * std::sqrt(norm2(r) * norm2(s))) {
    const double t = std::clamp(cross(c - a, s) / den, 0.0, 1.0);
    return a + t * r;
  }
  const auto closest = [](Vec2 p, Vec2 u, Vec2 v) {
    const double l2 = norm2(v - u);
    const double t = l2 > 0.0 ? std::clamp(dot(p - u, v - u) / l2, 0.0, 1.0) : 0.0;
    return u + t * (v - u);
  };
  Vec2 best = a;
  double bd = INFINITY;
  for (const auto& [p, q] : {std::pair{a, closest(a, c, d)}, std::pair{b, closest(b, c, d)},
                             std::pair{c, closest(c, a, b)}, std::pair{d, closest(d, a, b)}})
    if (dist(p, q) < bd) bd = dist(p, q), best = p;
  return best;
}

struct Event {
  std::size_t seg = 0;
  double t = 0.0;
  bool enter = false;
};

// Where ring crosses the circle (centre, r): one entry and one exit, or nothing.
std::optional<std::pair<Event, Event>> crossings(const std::vector<Vec2>& ring, Vec2 centre, double r) {
  std::vector<Event> ev;
  const std::size_t n = ring.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2 a = ring[k], d = ring[(k + 1) % n] - a, f = a - centre;
    const double qa = norm2(d), qb = 2.0 * dot(f, d), qc = norm2(f) - r * r;
    const double disc = qb * qb - 4.0 * qa * qc;
    if (!(qa > 0.0) || !(disc > 0.0)) continue;
    const double sq = std::sqrt(disc);
    const double t1 = (-qb - sq) / (2.0 * qa), t2 = (-qb + sq) / (2.0 * qa);
    if (t1 > 0.0 && t1 < 1.0) ev.push_back({k, t1, true});
    if (t2 > 0.0 && t2 < 1.0) ev.push_back({k, t2, false});
  }
  if (ev.size() != 2 || ev[0].enter == ev[1].enter) return std::nullopt;
  return ev[0].enter ? std::pair{ev[1], ev[0]} : std::pair{ev[0], ev[1]};  // (exit, entry)
}

Vec2 at(const std::vector<Vec2>& ring, const Event& e) {
  return ring[e.seg] + e.t * (ring[(e.seg + 1) % ring.size()] - ring[e.seg]);
}

// Appends ring's part from event `from` to event `to` (forward) to out, with origins.
void walk(const std::vector<Vec2>& ring, int which, const Event& from, const Event& to, JoinedRings& out,
          std::vector<Vec2>* piece) {
  const std::size_t n = ring.size();
  std::size_t m = (to.seg + n - from.seg) % n;
  if (m == 0 && to.t < from.t) m = n;
  const auto push = [&](Vec2 p, std::size_t origin) {
    if (piece) {
      piece->push_back(p);
      return;
    }
    out.ring.push_back(p);
    out.origin.emplace_back(which, static_cast<int>(origin));
  };
  push(at(ring, from), from.seg);
  for (std::size_t k = 1; k <= m; ++k) push(ring[(from.seg + k) % n], (from.seg + k) % n);
  push(at(ring, to), to.seg);
}

}  // namespace

std::optional<JoinedRings> join_rings(const std::vector<Vec2>& a, const std::vector<Vec2>& b,
                                      const std::function<double(Vec2)>& h) {
  if (a.size() < 3 || b.size() < 3) return std::nullopt;
  Box bbox;
  for (Vec2 p : b) bbox.add(p);
  std::vector<Vec2> meets;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Vec2 p = a[i], q = a[(i + 1) % a.size()];
    const Box sa = segment_box(p, q);
    if (!overlap(sa, bbox)) continue;
    for (std::size_t j = 0; j < b.size(); ++j) {
      const Vec2 c = b[j], d = b[(j + 1) % b.size()];
      if (overlap(sa, segment_box(c, d)) && segments_intersect(p, q, c, d)) meets.push_back(meeting_point(p, q, c, d));
    }
  }
  if (meets.empty()) return std::nullopt;
  Vec2 centre{0.0, 0.0};
  for (Vec2 p : meets) centre = centre + p;
  centre = (1.0 / static_cast<double>(meets.size())) * centre;
  double spread = 0.0;
  for (Vec2 p : meets) spread = std::max(spread, dist(p, centre));
  const double hh = h(centre);
  if (!(hh > 0.0) || spread > hh) return std::nullopt;
  JoinedRings out;
  out.centre = centre;
  out.h = hh;
  out.radius = 0.5 * hh + spread;
  const auto ca = crossings(a, centre, out.radius), cb = crossings(b, centre, out.radius);
  if (!ca || !cb) return std::nullopt;
  walk(a, 0, ca->first, ca->second, out, nullptr);  // a from where it leaves the disc to where it enters
  walk(b, 1, cb->first, cb->second, out, nullptr);
  if (out.ring.size() < 6) return std::nullopt;
  walk(a, 0, ca->second, ca->first, out, &out.removed);
  walk(b, 1, cb->second, cb->first, out, &out.removed);
  const Vec2 entry_a = at(a, ca->second), exit_b = at(b, cb->first);
  const Vec2 entry_b = at(b, cb->second), exit_a = at(a, ca->first);
  out.added = {entry_a, exit_b, entry_b, exit_a};
  // The chords must cross neither each other nor the rest of the ring.
  const std::size_t n = out.ring.size();
  const std::size_t chord1 = [&] {
    for (std::size_t k = 0; k + 1 < n; ++k)
      if (out.origin[k].first == 0 && out.origin[k + 1].first == 1) return k;
    return n;
  }();
  if (chord1 == n) return std::nullopt;
  for (const std::size_t c : {chord1, n - 1})
    for (std::size_t k = 0; k < n; ++k) {
      if (k == c || k == (c + 1) % n || (k + 1) % n == c) continue;
      if (segments_intersect(out.ring[c], out.ring[(c + 1) % n], out.ring[k], out.ring[(k + 1) % n]))
        return std::nullopt;
    }
  return out;
}

}  // namespace pdmesh::detail
