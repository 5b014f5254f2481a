// build_limited_field: corner bookkeeping (positions, base and source values, limited values and the
// source each came from), the limit-refine rounds, and the flat arrays of the final field.
#include "spacing/limited_field.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "spacing/inverse_square_integral.hpp"

namespace pdmesh {

namespace {

using Cell = BackgroundBuilder::Cell;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Safety net: each round refines where the last limit lowered q; a handful of rounds converge.
constexpr int kMaxRounds = 12;
// A later round re-examines the leaves whose corners the limit lowered by more than this fraction of
// the interpolation tolerance (smaller changes cannot change a refinement decision much).
constexpr double kLowered = 0.25;

// Points per SizeSources::at_many call of the sources' loops.
constexpr std::size_t kSourceBlock = 64;

// A thread's seed for the sources' closest-segment search (parallel_for_scratch).
using Seed = FeatureSize::SearchSeed;

class LimitedField {
 public:
  LimitedField(BackgroundBuilder& b, const SizeSources& sources, double g, const std::vector<PointSource>& points,
               LimitedFieldStats& stats)
      : b_(b), sources_(sources), g_(g), points_(points), stats_(stats) {}

  BackgroundFieldData run() {
    segment_sources();
    std::vector<std::int32_t> leaf_corner;
    for (int round = 1; round <= kMaxRounds; ++round) {
      stats_.rounds = round;
      std::vector<int> leaves = b_.leaves();
      if (round == 1) {
        // The base tree's corners, registered in the leaves' order. Later rounds have no new ones: each
        // cell that refine() made got its corners registered when it asked for their values
        // (corner_value), and a corner left unregistered would throw in corner_id below.
        std::vector<std::uint64_t> keys(4 * leaves.size());
        std::vector<std::int32_t> ids(4 * leaves.size());
        for (std::size_t n = 0; n < leaves.size(); ++n) {
          const Cell& c = b_.cells()[static_cast<std::size_t>(leaves[n])];
          const std::uint32_t s = b_.span(c.level);
          keys[4 * n] = BackgroundBuilder::key(c.x, c.y);
          keys[4 * n + 1] = BackgroundBuilder::key(c.x + s, c.y);
          keys[4 * n + 2] = BackgroundBuilder::key(c.x, c.y + s);
          keys[4 * n + 3] = BackgroundBuilder::key(c.x + s, c.y + s);
          for (std::size_t a = 0; a < 4; ++a) ids[4 * n + a] = c.corner[a];
        }
        add_corners(keys, ids);
      }
      // Each leaf's four corner ids, written in place by leaf (lookups only: on all cores).
      leaf_corner.resize(4 * leaves.size());
      parallel_for(
          leaves.size(),
          [&](std::size_t n) {
            const Cell& c = b_.cells()[static_cast<std::size_t>(leaves[n])];
            for (std::size_t a = 0; a < 4; ++a) leaf_corner[4 * n + a] = corner_id(c.corner[a]);
          },
          4096, b_.options().loop_threads());
      // The values before this round's limit, which later rounds compare against (round 1 compares
      // against the base field instead).
      std::vector<double> before;
      if (round > 1) before = q_;
      const double tolerance = b_.options().tolerance;
      limit(leaf_corner, round == 1);
      check_nodes(leaves, leaf_corner);
      // Refine the leaves whose corners the limit lowered this round (round 1: below the base field).
      // Each leaf's test only reads, so the flags are set on all cores and gathered in the leaves' order.
      std::vector<std::uint8_t> refine_leaf(leaves.size(), 0);
      parallel_for(
          leaves.size(),
          [&](std::size_t n) {
            bool lowered = false;
            for (int a = 0; a < 4 && !lowered; ++a) {
              const auto i = static_cast<std::size_t>(leaf_corner[4 * n + static_cast<std::size_t>(a)]);
              lowered = round == 1 ? q_[i] < base_[i] : q_[i] < (1.0 - kLowered * tolerance) * before[i];
            }
            // Round 1 also takes the boundary leaves where a segment asks for less than the corners do:
            // a gap or a curve narrower than the leaf may lie between its corners and test points.
            if (!lowered && round == 1) {
              const Cell& c = b_.cells()[static_cast<std::size_t>(leaves[n])];
              double q_max = 0.0;
              for (int a = 0; a < 4; ++a)
                q_max = std::max(q_max, q_[static_cast<std::size_t>(leaf_corner[4 * n + static_cast<std::size_t>(a)])]);
              lowered = segment_minimum(c) < q_max;
            }
            refine_leaf[n] = lowered ? 1 : 0;
          },
          4096, b_.options().loop_threads());
      std::vector<int> candidates;
      for (std::size_t n = 0; n < leaves.size(); ++n)
        if (refine_leaf[n]) candidates.push_back(leaves[n]);
      if (candidates.empty()) break;
      const auto start = Clock::now();
      const std::size_t splits = b_.refine(
          std::move(candidates), [this](const Cell& c, const double q[4]) { return decide(c, q); },
          [this](const Cell& c, const double q[4], const double exact[9], const std::int32_t ids[9], int count) {
            return test(c, q, exact, ids, count);
          },
          [this](const Cell& c, std::uint32_t x, std::uint32_t y, std::int32_t id) {
            return corner_value(c, x, y, id);
          },
          [this](const std::vector<std::uint64_t>& sampled, const std::vector<std::int32_t>& ids) {
            add_sources(sampled, ids);
          });
      stats_.refine_seconds += seconds_since(start);
      if (splits == 0) break;
    }
    if (sources_.has_floor()) {
      // Next to input boundary points the field may not fall far below their spacing (the first node
      // row would not match the boundary row); the floor is g-Lipschitz like the limited field, so the
      // max of the two still is.
      const auto start = Clock::now();
      parallel_for(
          q_.size(), [&](std::size_t i) { q_[i] = sources_.floor_at(pos_[i], q_[i]); }, 256,
          b_.options().loop_threads());
      stats_.source_seconds += seconds_since(start);
    }
    for (std::size_t i = 0; i < q_.size(); ++i)
      if (q_[i] < base_[i]) ++stats_.reduced_corners;
    return b_.emit([this](std::int32_t id) { return q_[static_cast<std::size_t>(corner_id(id))]; });
  }

 private:
  // The sources and the limit only lower q: before the leaves are refined for them, the nodes their
  // inside leaves ask for, with the limited corners, are held to the node budget as the base tree's
  // levels were (BackgroundBuilder::kEarlyNodeMargin).
  void check_nodes(const std::vector<int>& leaves, const std::vector<std::int32_t>& leaf_corner) const {
    const double max_nodes = b_.options().max_nodes;
    if (!(max_nodes > 0.0)) return;
    const double hex = 2.0 / std::sqrt(3.0);
    const double allowed = BackgroundBuilder::kEarlyNodeMargin * max_nodes;
    // A bound first: the bilinear q is at least its smallest corner, so a leaf's integral of 1/q^2 is at
    // most side^2 / q_min^2 (inverse_square_integral's rounding, ~1e-12 relative, is covered by the
    // 1e-6). Where the bound is clearly within the limit, so is the count, and its logarithms are
    // skipped: the same refusals.
    const double bound = sum_over_inside_leaves(leaves, leaf_corner, [hex](double side, const double* q) {
      const double q_min = std::min(std::min(q[0], q[1]), std::min(q[2], q[3]));
      return hex * side * side / (q_min * q_min);
    });
    if (std::isfinite(bound) && bound * (1.0 + 1e-6) <= allowed) return;
    const double nodes = sum_over_inside_leaves(leaves, leaf_corner, [hex](double side, const double* q) {
      return hex * side * side * inverse_square_integral(q[0], q[1], q[2], q[3]);
    });
    if (nodes <= allowed) return;
    throw LimitError(fmt::format(
        "the spacing field with its limits (feature size, curvature, gradation, point sizes) asks for about {} "
        "nodes on the base quadtree's leaves inside the domain, before they are refined for it, more than "
        "--max-nodes {:.0f}; coarsen the spacing, relax spacing.rows_in_gap or spacing.curvature_angle, or raise "
        "--max-nodes",
        std::isfinite(nodes) ? fmt::format("{:.3g}", nodes) : std::string("infinitely many"), max_nodes));
  }

  // The sum of term(side, corner q's) over the inside leaves whose four corners have a positive q, in
  // the leaves' order: the terms on all cores, then their sum on this thread (the same sum as one loop).
  template <class Term>
  double sum_over_inside_leaves(const std::vector<int>& leaves, const std::vector<std::int32_t>& leaf_corner,
                                Term term) const {
    std::vector<double> terms(leaves.size(), 0.0);
    std::vector<std::uint8_t> counted(leaves.size(), 0);
    parallel_for(
        leaves.size(),
        [&](std::size_t n) {
          const Cell& c = b_.cells()[static_cast<std::size_t>(leaves[n])];
          if (c.tag != kTagInside) return;
          double q[4];
          for (int a = 0; a < 4; ++a)
            q[a] = q_[static_cast<std::size_t>(leaf_corner[4 * n + static_cast<std::size_t>(a)])];
          if (!(q[0] > 0.0 && q[1] > 0.0 && q[2] > 0.0 && q[3] > 0.0)) return;
          counted[n] = 1;
          terms[n] = term(b_.side(c.level), q);
        },
        4096, b_.options().loop_threads());
    double sum = 0.0;
    for (std::size_t n = 0; n < leaves.size(); ++n)
      if (counted[n]) sum += terms[n];
    return sum;
  }

  static Vec2 lattice(const BackgroundBuilder& b, std::uint64_t k) {
    return b.point(static_cast<std::uint32_t>(k >> 32), static_cast<std::uint32_t>(k & 0xffffffffu));
  }

  // The per-sample arrays cover every sample the builder has taken (new ones: no source, no corner).
  void grow() {
    if (corner_of_.size() == b_.samples()) return;  // corner_value calls it for every corner it is asked
    source_at_.resize(b_.samples(), std::numeric_limits<double>::quiet_NaN());
    has_source_.resize(b_.samples(), 0);
    corner_of_.resize(b_.samples(), -1);
  }
  // The corner id of a sample that is a known corner.
  std::int32_t corner_id(std::int32_t sample) const {
    const std::int32_t id = corner_of_.at(static_cast<std::size_t>(sample));
    if (id < 0) throw std::logic_error("limited field: a leaf corner that was never registered");
    return id;
  }

  // The sources at lattice points not seen yet (keys[i] is sample ids[i]), in parallel (they are
  // thread-safe), each searching no further than the base field there asks.
  void add_sources(const std::vector<std::uint64_t>& keys, const std::vector<std::int32_t>& ids) {
    grow();
    std::vector<std::size_t> fresh;  // positions in keys
    for (std::size_t i = 0; i < keys.size(); ++i) {
      std::uint8_t& has = has_source_[static_cast<std::size_t>(ids[i])];
      if (has) continue;
      has = 1;
      fresh.push_back(i);
    }
    // Consecutive keys come in spatial order, so each thread's last closest segment seeds its next
    // search well.
    sources_in_blocks(
        fresh.size(),
        [&](std::size_t i, Vec2& p, double& limit) {
          p = lattice(b_, keys[fresh[i]]);
          limit = b_.sample_value(ids[fresh[i]]);
        },
        [&](std::size_t i, double q) { source_at_[static_cast<std::size_t>(ids[fresh[i]])] = q; });
  }

  // The sources at `count` points, in blocks of kSourceBlock through SizeSources::at_many on all
  // cores, each thread's last closest segment seeding its next search: at(i, p, limit) gives point
  // i and how far its search need look, put(i, q) takes its value.
  template <class At, class Put>
  void sources_in_blocks(std::size_t count, const At& at, const Put& put) {
    const auto start = Clock::now();
    const std::size_t blocks = (count + kSourceBlock - 1) / kSourceBlock;
    parallel_for_scratch<Seed>(
        blocks,
        [&](Seed& seed, std::size_t b) {
          const std::size_t first = b * kSourceBlock;
          const std::size_t n = std::min(kSourceBlock, count - first);
          Vec2 p[kSourceBlock];
          double limit[kSourceBlock] = {}, q[kSourceBlock];
          for (std::size_t i = 0; i < n; ++i) at(first + i, p[i], limit[i]);
          sources_.at_many(p, limit, n, q, seed);
          for (std::size_t i = 0; i < n; ++i) put(first + i, q[i]);
        },
        256 / kSourceBlock, b_.options().loop_threads());
    stats_.source_seconds += seconds_since(start);
  }

  // Registers new corners: position, base sample and min(base, sources); their limited value is set
  // when a cell first asks for it (corner_value). The ids go to the new corners in the keys' order
  // (as add_corner numbers them one by one); their data is then written on all cores, each corner
  // its own entries.
  void add_corners(const std::vector<std::uint64_t>& keys, const std::vector<std::int32_t>& ids) {
    add_sources(keys, ids);
    const std::size_t first = pos_.size();
    std::vector<std::size_t> fresh;  // positions in keys of the new corners, by corner id - first
    for (std::size_t i = 0; i < keys.size(); ++i) {
      std::int32_t& corner = corner_of_[static_cast<std::size_t>(ids[i])];
      if (corner >= 0) continue;
      corner = static_cast<std::int32_t>(first + fresh.size());
      fresh.push_back(i);
    }
    size_corners(first + fresh.size());
    parallel_for(
        fresh.size(), [&](std::size_t f) { set_corner(first + f, keys[fresh[f]], ids[fresh[f]]); }, 4096,
        b_.options().loop_threads());
  }
  // The per-corner arrays at `total` corners; a new corner's q is NaN until it is limited.
  void size_corners(std::size_t total) {
    pos_.resize(total);
    base_.resize(total);
    q0_.resize(total);
    q_.resize(total, std::numeric_limits<double>::quiet_NaN());
    source_.resize(total);
  }
  // Corner i (its slot sized) at lattice key k with base sample `id`: its position, base value,
  // min(base, sources) and itself as its source.
  void set_corner(std::size_t i, std::uint64_t k, std::int32_t id) {
    pos_[i] = b_.point(static_cast<std::uint32_t>(k >> 32), static_cast<std::uint32_t>(k & 0xffffffffu));
    base_[i] = b_.sample_value(id);
    q0_[i] = std::min(base_[i], source_at_[static_cast<std::size_t>(id)]);
    source_[i] = static_cast<std::int32_t>(i);
  }
  // One corner (a known one is skipped); its sources are computed here only when add_sources has not
  // seen its sample (the builder passes every sample it takes to add_sources, `sampled`, first).
  void add_corner(std::uint64_t k, std::int32_t id) {
    const auto sample = static_cast<std::size_t>(id);
    if (corner_of_[sample] >= 0) return;
    if (!has_source_[sample]) add_sources({k}, {id});
    const std::size_t i = pos_.size();
    corner_of_[sample] = static_cast<std::int32_t>(i);
    size_corners(i + 1);
    set_corner(i, k, id);
  }

  // The sources at each segment's midpoint, seen from the boundary (so a gap narrower than the leaves
  // around it is still found).
  void segment_sources() {
    const auto& segs = b_.geometry().segments;
    segment_q_.resize(segs.size());
    sources_in_blocks(
        segs.size(),
        [&](std::size_t i, Vec2& p, double& limit) {
          p = 0.5 * (segs[i].a + segs[i].b);
          limit = std::numeric_limits<double>::max();
        },
        [&](std::size_t i, double q) { segment_q_[i] = q; });
  }
  double segment_minimum(const Cell& c) const {
    double m = std::numeric_limits<double>::infinity();
    for (const int s : b_.segments(c)) m = std::min(m, segment_q_[static_cast<std::size_t>(s)]);
    return m;
  }
  // The base rules; a boundary leaf is also split while its side exceeds size_factor times the least
  // its segments ask for.
  BackgroundBuilder::Decision decide(const Cell& c, const double q[4]) const {
    const BackgroundBuilder::Decision d = b_.default_decide(c, q);
    if (d != BackgroundBuilder::Decision::Split && c.tag == kTagBoundary && c.level < b_.options().max_depth &&
        b_.side(c.level) > b_.options().size_factor * segment_minimum(c))
      return BackgroundBuilder::Decision::Split;
    return d;
  }

  // Sources: >= 0 a corner (its q0), < 0 the point source -1 - s.
  Vec2 source_point(std::int32_t s) const {
    return s >= 0 ? pos_[static_cast<std::size_t>(s)] : points_[static_cast<std::size_t>(-1 - s)].p;
  }
  double source_q(std::int32_t s) const {
    return s >= 0 ? q0_[static_cast<std::size_t>(s)] : points_[static_cast<std::size_t>(-1 - s)].q;
  }
  double cone(std::int32_t s, Vec2 p) const {
    return g_ > 0.0 ? source_q(s) + g_ * dist(p, source_point(s)) : std::numeric_limits<double>::infinity();
  }

  // Round 1: the whole sweep. Later rounds continue it from the corners of the leaves that have a
  // corner added since the last sweep (only those can lower anything).
  void limit(const std::vector<std::int32_t>& leaf_corner, bool first) {
    const auto start = Clock::now();
    const GradationGraph graph(pos_, leaf_corner);
    const auto n = static_cast<std::int32_t>(pos_.size());
    // The graph's numbering of sources: corners, then point k as n + k.
    std::vector<std::int32_t> source(source_.size());
    for (std::size_t i = 0; i < source.size(); ++i) source[i] = source_[i] >= 0 ? source_[i] : n + (-1 - source_[i]);
    if (first) {
      std::vector<std::vector<std::int32_t>> point_corners;
      for (const PointSource& p : points_) {
        const Cell& c = b_.cells()[static_cast<std::size_t>(b_.locate(p.p))];
        std::vector<std::int32_t> ids;
        for (const std::int32_t sample : c.corner) ids.push_back(corner_id(sample));
        point_corners.push_back(std::move(ids));
      }
      graph.limit(g_, q0_, q_, source, points_, point_corners);
    } else {
      std::vector<std::int32_t> seeds;
      for (std::size_t l = 0; l < leaf_corner.size(); l += 4) {
        const bool fresh = std::any_of(leaf_corner.begin() + static_cast<std::ptrdiff_t>(l),
                                       leaf_corner.begin() + static_cast<std::ptrdiff_t>(l) + 4,
                                       [&](std::int32_t c) { return static_cast<std::size_t>(c) >= limited_; });
        if (fresh)
          seeds.insert(seeds.end(), leaf_corner.begin() + static_cast<std::ptrdiff_t>(l),
                       leaf_corner.begin() + static_cast<std::ptrdiff_t>(l) + 4);
      }
      graph.relimit(g_, q0_, q_, source, seeds, points_);
    }
    for (std::size_t i = 0; i < source.size(); ++i) source_[i] = source[i] < n ? source[i] : -1 - (source[i] - n);
    limited_ = pos_.size();
    stats_.limit_seconds += seconds_since(start);
  }

  // The 4 corner ids of a cell's parent (whose corners are known when the cell is new).
  void parent_corners(const Cell& c, std::int32_t out[4]) const {
    const Cell& parent = b_.cells().at(static_cast<std::size_t>(c.parent));
    for (int k = 0; k < 4; ++k) out[k] = corner_id(parent.corner[k]);
  }

  // A known corner keeps its limited value; a new one (a child's) takes min(base, sources) and the
  // cones of its parent's corners' sources, the same min the next limit would give it locally.
  double corner_value(const Cell& c, std::uint32_t x, std::uint32_t y, std::int32_t sample) {
    grow();
    add_corner(BackgroundBuilder::key(x, y), sample);
    const auto i = static_cast<std::size_t>(corner_id(sample));
    if (!std::isnan(q_[i])) return q_[i];
    q_[i] = q0_[i];
    if (c.level > 0) {
      std::int32_t parent[4];
      parent_corners(c, parent);
      for (const std::int32_t p : parent) {
        const std::int32_t s = source_[static_cast<std::size_t>(p)];
        const double v = cone(s, pos_[i]);
        if (v < q_[i]) {
          q_[i] = v;
          source_[i] = s;
        }
      }
    }
    return q_[i];
  }

  // Interpolation test against the limited field at the test points: min of the base sample, the
  // sources there and the cones of the cell's corners' sources.
  bool test(const Cell& c, const double q[4], const double exact[9], const std::int32_t ids[9], int count) const {
    const std::uint32_t s = b_.span(c.level), quarter = s / 4;
    std::int32_t corner_source[4];
    for (int k = 0; k < 4; ++k) corner_source[k] = source_[static_cast<std::size_t>(corner_id(c.corner[k]))];
    const double tolerance = b_.options().tolerance;
    for (int t = 0; t < count; ++t) {
      const std::uint32_t x = c.x + quarter * static_cast<std::uint32_t>(BackgroundBuilder::kTests[t][0]);
      const std::uint32_t y = c.y + quarter * static_cast<std::uint32_t>(BackgroundBuilder::kTests[t][1]);
      const Vec2 p = b_.point(x, y);
      double target = std::min(exact[t], source_at_[static_cast<std::size_t>(ids[t])]);
      for (const std::int32_t cs : corner_source) target = std::min(target, cone(cs, p));
      const double u = BackgroundBuilder::kTests[t][0] / 4.0, v = BackgroundBuilder::kTests[t][1] / 4.0;
      const double bilinear = (1.0 - v) * ((1.0 - u) * q[0] + u * q[1]) + v * ((1.0 - u) * q[2] + u * q[3]);
      if (std::fabs(bilinear - target) > 0.5 * tolerance * target) return true;
    }
    return false;
  }

  BackgroundBuilder& b_;
  const SizeSources& sources_;
  const double g_;
  const std::vector<PointSource>& points_;
  LimitedFieldStats& stats_;
  // By the builder's sample id: the sources there (once has_source_), and the corner id (-1: none).
  std::vector<double> source_at_;
  std::vector<std::uint8_t> has_source_;
  std::vector<std::int32_t> corner_of_;
  std::vector<Vec2> pos_;
  std::vector<double> base_, q0_, q_;
  std::vector<std::int32_t> source_;
  std::vector<double> segment_q_;  // the sources at each segment's midpoint
  std::size_t limited_ = 0;        // corners [0, limited_) took part in the last sweep
};

}  // namespace

BackgroundFieldData build_limited_field(BackgroundBuilder& builder, const SizeSources& sources, double g,
                                        const std::vector<PointSource>& points, LimitedFieldStats& stats) {
  return LimitedField(builder, sources, g, points, stats).run();
}

}  // namespace pdmesh
