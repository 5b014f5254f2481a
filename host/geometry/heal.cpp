// heal_curves(): the healing rules on raw curves (heal.hpp, docs/geometry-input.md "Healing").
#include "geometry/heal.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <unordered_map>

#include <fmt/format.h>

#include "core/predicates.hpp"
#include "geometry/heal_join.hpp"

namespace pdmesh {

const char* to_string(HealKind kind) {
  switch (kind) {
    case HealKind::Merge:
      return "merged vertices";
    case HealKind::Spike:
      return "spikes removed";
    case HealKind::InletClosed:
      return "inlets closed";
    case HealKind::InletOpened:
      return "inlets opened";
    case HealKind::Island:
      return "islands dropped";
    case HealKind::Joined:
      return "rings joined";
  }
  return "?";
}

int HealResult::count(HealKind kind) const {
  return static_cast<int>(
      std::count_if(changes.begin(), changes.end(), [&](const HealChange& c) { return c.kind == kind; }));
}

const HealChange* HealResult::worst(HealKind kind) const {
  const HealChange* w = nullptr;
  for (const HealChange& c : changes)
    if (c.kind == kind && (w == nullptr || c.size < w->size)) w = &c;
  return w;
}

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Pt {
  Vec2 p;
  int line = 0;
};

// One curve while it is healed: its points (a closed curve without the repeated last point).
struct Work {
  std::vector<Pt> pts;
  bool closed = false;
  bool healable = false;  // not a constraint, not fixed points
  bool changed = false;
  bool dropped = false;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// The angle at b between b->a and b->c, degrees in [0, 180].
double angle_deg(Vec2 a, Vec2 b, Vec2 c) {
  const Vec2 u = a - b;
  const Vec2 v = c - b;
  return std::atan2(std::fabs(cross(u, v)), dot(u, v)) * 180.0 / kPi;
}

double signed_area(const std::vector<Vec2>& ring) {
  double a = 0.0;
  for (std::size_t k = 0; k < ring.size(); ++k) a += cross(ring[k], ring[(k + 1) % ring.size()]);
  return 0.5 * a;
}

double perimeter(const std::vector<Vec2>& ring) {
  double l = 0.0;
  for (std::size_t k = 0; k < ring.size(); ++k) l += dist(ring[k], ring[(k + 1) % ring.size()]);
  return l;
}

// The closest point to p on segment a-b, and its parameter in [0, 1].
Vec2 closest_on(Vec2 p, Vec2 a, Vec2 b, double& t) {
  const Vec2 ab = b - a;
  const double l2 = norm2(ab);
  t = l2 > 0.0 ? std::clamp(dot(p - a, ab) / l2, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

class Healer {
 public:
  Healer(std::vector<RawCurve>& curves, const HealOptions& o) : curves_(curves), o_(o) {
    Box box;
    for (const RawCurve& c : curves)
      for (Vec2 p : c.points) box.add(p);
    const double tol = o.join_tolerance * (box.lo.x <= box.hi.x ? box.diagonal() : 0.0);
    std::vector<double> lengths;
    for (const RawCurve& c : curves) {
      Work w;
      w.healable = !c.constraint && !c.fixed_points && c.points.size() >= 2;
      for (std::size_t k = 0; k < c.points.size(); ++k)
        w.pts.push_back({c.points[k], k < c.lines.size() ? c.lines[k] : c.line + static_cast<int>(k)});
      if (w.healable && c.points.size() >= 4 && dist(c.points.front(), c.points.back()) <= tol) {
        w.closed = true;
        w.pts.pop_back();
      }
      if (w.healable)
        for (std::size_t k = 0; k + 1 < c.points.size(); ++k) lengths.push_back(dist(c.points[k], c.points[k + 1]));
      work_.push_back(std::move(w));
    }
    global_h_ = median(lengths) * o.scale;
  }

  HealResult run() {
    for (int round = 0; round < 50; ++round) {
      bool any = joins();
      for (std::size_t c = 0; c < work_.size(); ++c) {
        if (!work_[c].healable || work_[c].dropped) continue;
        // Inlets first: merging first would fold a narrow inlet's end (shorter than the merge
        // distance) into one vertex, a wedge that the inlet rule leaves.
        if (work_[c].closed) any |= inlets(c);
        any |= merge(c);
        any |= spikes(c);
      }
      any |= islands();
      if (!any) break;
    }
    write_back();
    return std::move(result_);
  }

 private:
  std::vector<RawCurve>& curves_;
  HealOptions o_;
  std::vector<Work> work_;
  double global_h_ = 0.0;
  HealResult result_;

  // The local spacing at vertex i of curve c: its sampling spacing times HealOptions::scale, no larger
  // than the case's stated size.
  double h_at(const Work& w, std::size_t i) const { return capped(sampling_at(w, i) * o_.scale, w.pts[i].p); }

  // What merges judge by: the sampling spacing without the scale, no larger than the case's stated size
  // (times the scale, the mesh's spacing there). A merge removes an outlier of the curve's own sampling
  // (a step, extra points on a line), which eq. 3.6 would follow whatever the scale; with the scale, a
  // coarser mesh would take a curve's regular sampling for jogs and merge it away round after round,
  // each merge lengthening the segments the next round's spacing is the median of.
  double merge_h_at(const Work& w, std::size_t i) const { return capped(sampling_at(w, i), w.pts[i].p); }

  // The median length of the kNeighbourhood segments around vertex i along its curve.
  double sampling_at(const Work& w, std::size_t i) const {
    const std::size_t n = w.pts.size();
    const std::size_t segs = w.closed ? n : n - 1;
    std::vector<double> l;
    const int half = HealOptions::kNeighbourhood / 2;
    if (static_cast<int>(segs) <= HealOptions::kNeighbourhood) {
      for (std::size_t k = 0; k < segs; ++k) l.push_back(dist(w.pts[k].p, w.pts[(k + 1) % n].p));
    } else if (w.closed) {
      for (int k = -half; k < half; ++k) {
        const std::size_t s = (i + n + static_cast<std::size_t>(k + static_cast<int>(n))) % n;
        l.push_back(dist(w.pts[s].p, w.pts[(s + 1) % n].p));
      }
    } else {
      const int first = std::clamp(static_cast<int>(i) - half, 0, static_cast<int>(segs) - 2 * half);
      for (int s = first; s < first + 2 * half; ++s) l.push_back(dist(w.pts[s].p, w.pts[s + 1].p));
    }
    return median(std::move(l));
  }

  // h no larger than the case's stated size at p (HealOptions::size).
  double capped(double h, Vec2 p) const { return o_.size ? std::min(h, o_.size(p) * o_.scale) : h; }

  HealChange change(HealKind kind, std::size_t c, int line, Vec2 at, double size, double h) {
    HealChange ch;
    ch.kind = kind;
    ch.curve = curves_[c].name.empty() ? fmt::format("curve{}", c) : curves_[c].name;
    ch.file = curves_[c].file;
    ch.line = line;
    ch.at = at;
    ch.size = size;
    ch.h = h;
    return ch;
  }

  // Whether the run of short segments (below merge_fraction x merge_h_at) through segment i -> i+1 is a jog: the
  // boundary leaves it within kJogTurnDeg of the direction it came in (steps where polygons were
  // merged, collinear extra points). A run across which the boundary turns further is a feature (a
  // blunt trailing edge, a chamfer, an inlet's end) that stays; the field follows it
  // (spacing/short_arcs.hpp). An open curve's run that reaches an end point is a jog.
  static constexpr double kJogTurnDeg = 45.0;
  bool is_jog(const Work& w, std::size_t i) const {
    const std::size_t n = w.pts.size();
    const auto short_seg = [&](std::size_t k) {
      return dist(w.pts[k].p, w.pts[(k + 1) % n].p) < o_.merge_fraction * merge_h_at(w, k);
    };
    std::size_t first = i, last = (i + 1) % n;  // the run's end vertices
    for (std::size_t steps = 0; steps < n; ++steps) {
      if (!w.closed && first == 0) return true;
      const std::size_t prev = (first + n - 1) % n;
      if (!short_seg(prev)) break;
      first = prev;
    }
    for (std::size_t steps = 0; steps < n; ++steps) {
      if (!w.closed && last == n - 1) return true;
      if (!short_seg(last)) break;
      last = (last + 1) % n;
    }
    const Vec2 in = w.pts[first].p - w.pts[(first + n - 1) % n].p;
    const Vec2 out = w.pts[(last + 1) % n].p - w.pts[last].p;
    return std::atan2(std::fabs(cross(in, out)), dot(in, out)) * 180.0 / kPi < kJogTurnDeg;
  }

  // Consecutive vertices closer than merge_fraction x merge_h_at become their midpoint where they are a jog;
  // an open curve's end points stay (the vertex next to one goes instead).
  bool merge(std::size_t c) {
    Work& w = work_[c];
    bool any = false;
    std::size_t i = 0;
    while (true) {
      const std::size_t n = w.pts.size();
      const std::size_t pairs = w.closed ? n : n - 1;
      if (i >= pairs || (w.closed && n <= 3) || (!w.closed && n <= 2)) break;
      const std::size_t j = (i + 1) % n;
      const double d = dist(w.pts[i].p, w.pts[j].p);
      const double h = merge_h_at(w, i);
      if (!(d < o_.merge_fraction * h) || !is_jog(w, i)) {
        ++i;
        continue;
      }
      const Vec2 before = w.pts[(i + n - 1) % n].p;
      const Vec2 after = w.pts[(j + 1) % n].p;
      Vec2 m = 0.5 * (w.pts[i].p + w.pts[j].p);
      std::size_t erase = j;
      if (!w.closed && i == 0) {
        m = w.pts[0].p;  // keep the end point
      } else if (!w.closed && j == n - 1) {
        m = w.pts[j].p;
        erase = i;
      }
      HealChange ch = change(HealKind::Merge, c, w.pts[i].line, m, d, h);
      ch.removed = {w.pts[i].p, w.pts[j].p};
      if (w.closed || i > 0) ch.removed.insert(ch.removed.begin(), before);
      if (w.closed || j < n - 1) ch.removed.push_back(after);
      ch.added = ch.removed;
      ch.added.erase(ch.added.begin() + ((w.closed || i > 0) ? 1 : 0),
                     ch.added.begin() + ((w.closed || i > 0) ? 3 : 2));
      ch.added.insert(ch.added.begin() + ((w.closed || i > 0) ? 1 : 0), m);
      result_.changes.push_back(std::move(ch));
      const std::size_t keep = erase == j ? i : j;
      w.pts[keep].p = m;
      w.pts.erase(w.pts.begin() + static_cast<std::ptrdiff_t>(erase));
      if (erase < i) --i;
      w.changed = any = true;
    }
    return any;
  }

  // A vertex sharper than spike_angle_deg whose triangle with its neighbours is below h², where the
  // boundary on both sides continues in the same direction (the segments before and after the spike
  // point the same way): a genuine sharp corner (a trailing edge) turns back instead and stays.
  bool spikes(std::size_t c) {
    Work& w = work_[c];
    bool any = false;
    std::size_t i = w.closed ? 0 : 2;
    while (true) {
      const std::size_t n = w.pts.size();
      if (w.closed ? (n < 5 || i >= n) : (n < 5 || i + 2 >= n)) break;
      const auto at = [&](std::ptrdiff_t k) {
        return w
            .pts[static_cast<std::size_t>((static_cast<std::ptrdiff_t>(i) + k + static_cast<std::ptrdiff_t>(n)) %
                                          static_cast<std::ptrdiff_t>(n))]
            .p;
      };
      const Vec2 a2 = at(-2), a = at(-1), p = at(0), b = at(1), b2 = at(2);
      const double angle = angle_deg(a, p, b);
      const double h = h_at(w, i);
      const double area = 0.5 * std::fabs(cross(a - p, b - p));
      if (angle < o_.spike_angle_deg && area < h * h && dot(a - a2, b2 - b) > 0.0) {
        HealChange ch = change(HealKind::Spike, c, w.pts[i].line, p, angle, h);
        ch.removed = {a, p, b};
        ch.added = {a, b};
        result_.changes.push_back(std::move(ch));
        w.pts.erase(w.pts.begin() + static_cast<std::ptrdiff_t>(i));
        if (i > 0) --i;
        w.changed = any = true;
        continue;
      }
      ++i;
    }
    return any;
  }

  // Whether the interior of closed curve c is in the domain: even-odd over every other boundary curve.
  bool interior_is_domain(std::size_t c) const { return inside_others(c, work_[c].pts.front().p); }

  // Whether q is inside an odd number of the boundary curves other than c.
  bool inside_others(std::size_t c, Vec2 q) const {
    int count = 0;
    for (std::size_t o = 0; o < work_.size(); ++o)
      if (o != c && !work_[o].dropped && !curves_[o].constraint) count += crossings(work_[o], q);
    return count % 2 == 0;
  }

  // How many segments of curve w a ray from q in +x crosses (the even-odd rule's count).
  static int crossings(const Work& w, Vec2 q) {
    int count = 0;
    const std::size_t n = w.pts.size();
    const std::size_t segs = w.closed ? n : n - 1;
    for (std::size_t k = 0; k < segs; ++k) {
      const Vec2 a = w.pts[k].p, b = w.pts[(k + 1) % n].p;
      if ((a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) * (b.x - a.x) / (b.y - a.y)) ++count;
    }
    return count;
  }

  struct Cut {
    std::vector<Pt> keep, gone;  // the two pieces, each from one end of the cut to the other
    double width = 0.0, gone_area = 0.0, h = 0.0;
    bool gone_is_lobe = false;  // the removed piece has the curve's orientation (a lobe of its interior)
    int line = 0;
  };

  // Narrow inlets and intrusions: a vertex within width_fraction x h of a non-adjacent segment of its
  // own closed curve splits the curve there into two pieces. The smaller one (by area) goes when it is
  // thin and about as wide as its mouth all along (try_cut), is a real fold (perimeter above 3x the
  // gap) and has no vertex sharper than 30 degrees besides the cut's ends (a wedge meeting at one
  // vertex is a sharp corner, which stays). Of the candidates the one removing the most area is cut first, at the
  // mouth.
  bool inlets(std::size_t c) {
    Work& w = work_[c];
    bool any = false;
    while (w.pts.size() >= 6) {
      const std::size_t n = w.pts.size();
      std::vector<Vec2> ring;
      for (const Pt& p : w.pts) ring.push_back(p.p);
      const double ring_area = signed_area(ring);
      std::vector<double> wid(n);
      double cell = 0.0;
      for (std::size_t i = 0; i < n; ++i) cell = std::max(cell, wid[i] = o_.width_fraction * h_at(w, i));
      if (!(cell > 0.0)) break;
      // Segments by grid cell (side: the largest threshold), for the near-segment search.
      std::unordered_map<std::uint64_t, std::vector<std::size_t>> grid;
      const auto key = [&](std::int64_t x, std::int64_t y) {
        return (static_cast<std::uint64_t>(x) << 32) ^ static_cast<std::uint64_t>(y & 0xffffffff);
      };
      const Vec2 origin = ring.front();
      const auto cell_of = [&](double v, double o) { return static_cast<std::int64_t>(std::floor((v - o) / cell)); };
      for (std::size_t k = 0; k < n; ++k) {
        const Vec2 a = ring[k], b = ring[(k + 1) % n];
        for (std::int64_t x = cell_of(std::min(a.x, b.x), origin.x); x <= cell_of(std::max(a.x, b.x), origin.x); ++x)
          for (std::int64_t y = cell_of(std::min(a.y, b.y), origin.y); y <= cell_of(std::max(a.y, b.y), origin.y); ++y)
            grid[key(x, y)].push_back(k);
      }
      std::optional<Cut> best;
      for (std::size_t i = 0; i < n; ++i) {
        const Vec2 p = ring[i];
        const std::int64_t cx = cell_of(p.x, origin.x), cy = cell_of(p.y, origin.y);
        for (std::int64_t x = cx - 1; x <= cx + 1; ++x)
          for (std::int64_t y = cy - 1; y <= cy + 1; ++y) {
            const auto it = grid.find(key(x, y));
            if (it == grid.end()) continue;
            for (const std::size_t j : it->second) {
              if (j == i || (j + 1) % n == i) continue;
              std::optional<Cut> cut = try_cut(w, ring, ring_area, i, j, wid[i]);
              if (cut && (!best || cut->gone_area > best->gone_area)) best = std::move(cut);
            }
          }
      }
      if (!best) break;
      const bool gains = best->gone_is_lobe != interior_is_domain(c);
      const Vec2 mouth_a = best->gone.front().p, mouth_b = best->gone.back().p;
      HealChange ch = change(gains ? HealKind::InletOpened : HealKind::InletClosed, c, best->line,
                             0.5 * (mouth_a + mouth_b), best->width, best->h / o_.width_fraction);
      for (const Pt& q : best->gone) ch.removed.push_back(q.p);
      ch.added = {mouth_a, mouth_b};
      result_.changes.push_back(std::move(ch));
      w.pts = std::move(best->keep);
      w.changed = any = true;
    }
    return any;
  }

  std::optional<Cut> try_cut(const Work& w, const std::vector<Vec2>& ring, double ring_area, std::size_t i,
                             std::size_t j, double threshold) const {
    const std::size_t n = ring.size();
    double t = 0.0;
    const Vec2 q = closest_on(ring[i], ring[j], ring[(j + 1) % n], t);
    const double d = dist(ring[i], q);
    if (!(d < threshold)) return std::nullopt;
    // The cut's far end: a vertex of segment j when the closest point is one, else a new point.
    const std::size_t jn = (j + 1) % n;
    const bool at_j = t <= 0.0, at_jn = t >= 1.0;
    if ((at_j && j == i) || (at_jn && jn == i)) return std::nullopt;
    const Pt far{q, w.pts[j].line};
    // Forward piece: i, i+1, ..., j, [q]; backward piece: [q], j+1, ..., i.
    std::vector<Pt> fwd, bwd;
    for (std::size_t k = i;; k = (k + 1) % n) {
      fwd.push_back(w.pts[k]);
      if (k == j) break;
    }
    if (at_jn)
      fwd.push_back(w.pts[jn]);
    else if (!at_j)
      fwd.push_back(far);
    if (!at_j && !at_jn) bwd.push_back(far);
    for (std::size_t k = at_j ? j : jn;; k = (k + 1) % n) {
      bwd.push_back(w.pts[k]);
      if (k == i) break;
    }
    if (fwd.size() < 3 || bwd.size() < 3) return std::nullopt;
    const auto points = [](const std::vector<Pt>& v) {
      std::vector<Vec2> r;
      for (const Pt& p : v) r.push_back(p.p);
      return r;
    };
    const std::vector<Vec2> f = points(fwd), b = points(bwd);
    const double af = signed_area(f), ab = signed_area(b);
    const bool fwd_gone = std::fabs(af) <= std::fabs(ab);
    const std::vector<Vec2>& g = fwd_gone ? f : b;
    const double ag = fwd_gone ? af : ab;
    const double pg = perimeter(g);
    // The mean width along the piece's sides (the mouth left out): below the threshold, and at least
    // 0.7 of the mouth's width. A wedge (a trailing edge, a V-shaped bay) narrows from the mouth to
    // its tip, about half the mouth on average, and stays: its sharpness is the input's.
    const double mean_width = 2.0 * std::fabs(ag) / (pg - d);
    if (g.size() < 4 || !(pg > 3.0 * d) || !(mean_width < threshold) || !(mean_width >= 0.7 * d)) return std::nullopt;
    for (std::size_t k = 1; k + 1 < g.size(); ++k)
      if (angle_deg(g[k - 1], g[k], g[k + 1]) < 30.0) return std::nullopt;
    Cut cut;
    cut.keep = fwd_gone ? bwd : fwd;
    cut.gone = fwd_gone ? fwd : bwd;
    if (cut.keep.size() < 3) return std::nullopt;
    cut.width = d;
    cut.gone_area = std::fabs(ag);
    cut.h = threshold;
    cut.gone_is_lobe = (ag > 0.0) == (ring_area > 0.0);
    cut.line = w.pts[i].line;
    return cut;
  }

  // The ring of closed curve c with the domain on its left (even-odd over the other curves).
  std::vector<Pt> domain_left(std::size_t c) const {
    std::vector<Pt> pts = work_[c].pts;
    std::vector<Vec2> ring;
    for (const Pt& p : pts) ring.push_back(p.p);
    // A vote of up to 9 vertices spread along it: a ring that crosses another has some vertices on the
    // wrong side of it.
    int votes = 0;
    const std::size_t step = std::max<std::size_t>(1, pts.size() / 9);
    for (std::size_t k = 0; k < pts.size(); k += step) votes += inside_others(c, pts[k].p) ? 1 : -1;
    if ((signed_area(ring) > 0.0) != (votes >= 0)) std::reverse(pts.begin(), pts.end());
    return pts;
  }

  // Closed curves that touch or overlap in one place become one ring (detail::join_rings): the later
  // curve joins the earlier one (an outer ring before its holes) and is gone.
  bool joins() {
    bool any = false;
    std::vector<Box> boxes(work_.size());
    const auto ring_curve = [&](std::size_t c) { return work_[c].healable && work_[c].closed && !work_[c].dropped; };
    for (std::size_t c = 0; c < work_.size(); ++c)
      if (ring_curve(c))
        for (const Pt& p : work_[c].pts) boxes[c].add(p.p);
    for (std::size_t a = 0; a < work_.size(); ++a) {
      if (!ring_curve(a)) continue;
      for (std::size_t b = a + 1; b < work_.size(); ++b) {
        if (!ring_curve(b) || boxes[b].hi.x < boxes[a].lo.x || boxes[a].hi.x < boxes[b].lo.x ||
            boxes[b].hi.y < boxes[a].lo.y || boxes[a].hi.y < boxes[b].lo.y)
          continue;
        const std::vector<Pt> pa = domain_left(a), pb = domain_left(b);
        std::vector<Vec2> ra, rb;
        for (const Pt& p : pa) ra.push_back(p.p);
        for (const Pt& p : pb) rb.push_back(p.p);
        const auto h = [&](Vec2 q) {
          double best = INFINITY;
          for (const std::size_t c : {a, b}) {
            std::size_t near = 0;
            for (std::size_t k = 1; k < work_[c].pts.size(); ++k)
              if (dist(work_[c].pts[k].p, q) < dist(work_[c].pts[near].p, q)) near = k;
            best = std::min(best, h_at(work_[c], near));
          }
          return best;
        };
        const std::optional<detail::JoinedRings> joined = detail::join_rings(ra, rb, h);
        if (!joined || chords_meet_others(*joined, a, b)) continue;
        std::vector<Pt> pts;
        for (std::size_t k = 0; k < joined->ring.size(); ++k) {
          const auto [which, origin] = joined->origin[k];
          pts.push_back({joined->ring[k], (which == 0 ? pa : pb)[static_cast<std::size_t>(origin)].line});
        }
        const int line = pb[static_cast<std::size_t>(joined->origin.back().second)].line;
        HealChange ch = change(HealKind::Joined, b, line, joined->centre, joined->radius, joined->h);
        ch.removed = joined->removed;
        ch.added = joined->added;
        result_.changes.push_back(std::move(ch));
        work_[a].pts = std::move(pts);
        work_[a].changed = true;
        work_[b].dropped = any = true;
        for (const Pt& p : work_[b].pts) boxes[a].add(p.p);
      }
    }
    return any;
  }

  // Whether a chord of `joined` meets a curve other than a and b.
  bool chords_meet_others(const detail::JoinedRings& joined, std::size_t a, std::size_t b) const {
    const std::vector<Vec2>& ch = joined.added;
    for (std::size_t o = 0; o < work_.size(); ++o) {
      if (o == a || o == b || work_[o].dropped) continue;
      const std::vector<Pt>& other = work_[o].pts;
      const std::size_t segments = work_[o].closed ? other.size() : other.size() - 1;
      for (std::size_t j = 0; j < segments; ++j)
        for (const std::size_t k : {std::size_t{0}, std::size_t{2}})
          if (segments_intersect(ch[k], ch[k + 1], other[j].p, other[(j + 1) % other.size()].p)) return true;
    }
    return false;
  }

  // Whether a segment of closed curve c meets a segment of another curve still there: such a loop is
  // no island but crosses or touches the rest, which build_geometry reports (or joins) as given.
  bool meets_other_curve(std::size_t c) const {
    const std::vector<Pt>& ring = work_[c].pts;
    Box box;
    for (const Pt& p : ring) box.add(p.p);
    for (std::size_t o = 0; o < work_.size(); ++o) {
      if (o == c || work_[o].dropped) continue;
      const std::vector<Pt>& other = work_[o].pts;
      const std::size_t segments = work_[o].closed ? other.size() : other.size() - 1;
      for (std::size_t j = 0; j < segments; ++j) {
        const Vec2 a = other[j].p, b = other[(j + 1) % other.size()].p;
        if (std::max(a.x, b.x) < box.lo.x || std::min(a.x, b.x) > box.hi.x || std::max(a.y, b.y) < box.lo.y ||
            std::min(a.y, b.y) > box.hi.y)
          continue;
        for (std::size_t i = 0; i < ring.size(); ++i)
          if (segments_intersect(ring[i].p, ring[(i + 1) % ring.size()].p, a, b)) return true;
      }
    }
    return false;
  }

  // Whether a stated hole point (HealOptions::holes) lies inside closed curve c (even-odd).
  bool holds_hole_point(std::size_t c) const {
    return std::any_of(o_.holes.begin(), o_.holes.end(), [&](Vec2 q) { return crossings(work_[c], q) % 2 == 1; });
  }

  // Closed curves with an area below area_fraction x h² (h: the median input segment) that meet no
  // other curve and hold no stated hole point, except the largest one when no other curve bounds the
  // domain (it is the domain then).
  bool islands() {
    bool open_boundary = false;
    for (const Work& w : work_) open_boundary |= w.healable && !w.closed && !w.dropped;
    std::size_t largest = work_.size();
    double largest_area = -1.0;
    std::vector<double> areas(work_.size(), 0.0);
    for (std::size_t c = 0; c < work_.size(); ++c) {
      if (!work_[c].healable || !work_[c].closed || work_[c].dropped) continue;
      std::vector<Vec2> ring;
      for (const Pt& p : work_[c].pts) ring.push_back(p.p);
      areas[c] = std::fabs(signed_area(ring));
      if (!open_boundary && areas[c] > largest_area) largest_area = areas[c], largest = c;
    }
    bool any = false;
    for (std::size_t c = 0; c < work_.size(); ++c) {
      if (c == largest || !work_[c].healable || !work_[c].closed || work_[c].dropped) continue;
      const double h = capped(global_h_, work_[c].pts.front().p);
      if (!(areas[c] < o_.area_fraction * h * h) || meets_other_curve(c) || holds_hole_point(c)) continue;
      HealChange ch = change(HealKind::Island, c, work_[c].pts.front().line, work_[c].pts.front().p, areas[c], h);
      for (const Pt& p : work_[c].pts) ch.removed.push_back(p.p);
      ch.removed.push_back(work_[c].pts.front().p);
      result_.changes.push_back(std::move(ch));
      work_[c].dropped = any = true;
    }
    return any;
  }

  void write_back() {
    std::vector<RawCurve> out;
    for (std::size_t c = 0; c < work_.size(); ++c) {
      const Work& w = work_[c];
      if (w.dropped) continue;
      RawCurve curve = std::move(curves_[c]);
      if (w.changed) {
        curve.points.clear();
        curve.lines.clear();
        for (const Pt& p : w.pts) {
          curve.points.push_back(p.p);
          curve.lines.push_back(p.line);
        }
        if (w.closed) {
          curve.points.push_back(w.pts.front().p);
          curve.lines.push_back(w.pts.front().line);
        }
        curve.line = curve.lines.front();
      }
      out.push_back(std::move(curve));
    }
    curves_ = std::move(out);
  }
};

}  // namespace

HealResult heal_curves(std::vector<RawCurve>& curves, const HealOptions& options) {
  return Healer(curves, options).run();
}

}  // namespace pdmesh
