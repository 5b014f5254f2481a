// Recursive structured/random/hexagonal/hybrid filling of one initialization-tree leaf and the keep rule.
#include "init/quad_fill.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "core/errors.hpp"
#include "fmt/format.h"

namespace pdmesh {

namespace {

// Levels a fill may split below its leaf; deeper quads are filled as they are (9 nodes at most),
// so a pathological spacing cannot recurse without end.
constexpr int kMaxFillDepth = 30;

// The hexagonal fill places the points of one global equilateral lattice per spacing level: level k
// has spacing h_k = 2^(k / kHexLevelsPerOctave), rows h_k sqrt(3)/2 apart from the geometry's lower
// left corner, odd rows shifted by h_k / 2. A quad takes the level nearest its centre spacing
// (within 4.4%), so neighbouring quads of nearly the same spacing continue one lattice without a
// seam; seams remain only where the level changes (where q is graded, which a lattice cannot follow
// anyway).
constexpr double kHexLevelsPerOctave = 8.0;

// The hybrid fill puts the lattice only where it starts near equilibrium, and the structured patterns
// elsewhere (docs/initialization.md, "The hybrid fill", with the shares of quads that pass on the
// bench annuli): in a quad at least kHybridClearance q beyond its half-diagonal from the boundary
// (the lattice's rows meet a curved boundary as grain boundaries the relaxation has to anneal), where
// q at its centre and at its eight neighbours' centres spans at most a factor 1 + InitOptions::hybrid_spread
// (where q is graded more, neighbouring quads take lattices of other levels that meet with arbitrary phase).
constexpr double kHybridClearance = 2.0;

// With a density d (InitOptions::density) the hybrid fill starts every quad wholly inside the domain
// at d times the hexagonal-packing estimate of its part beyond the keep rule's clearance: the
// structured patterns overfill that estimate by a share that depends on where the quads' area ratios
// fall (0.72-1.61 on the uniform fields of tools/studies/edge_calib.py, 1.15-1.25 on its graded ones). Its lattice
// quads then take the spacing level nearest q_mid / sqrt(d) on a scale of kHybridLatticeLevels levels per octave
// (within 4.4 %), one global lattice per level, so that neighbouring quads of one level continue one lattice whatever
// their sizes; InitOptions::lattice_levels sets another number of levels.
constexpr int kHybridLatticeLevels = 8;

struct FillContext {
  const GeometryTree& tree;
  const SpacingField& spacing;
  InitMethod method;
  UnitRandom& rng;
  NodeSet& nodes;
  std::size_t added = 0;
  // Distance from `centre` to the boundary for the quad being filled, or -1: by the triangle
  // inequality every candidate p is at least distance - |p - centre| from the boundary, which
  // spares most closest-point queries in quads away from the boundary.
  Vec2 centre;
  double centre_distance = -1.0;
  FillState* state = nullptr;  // hexagonal and hybrid fills only
};

void place(FillContext& ctx, Vec2 p, bool known_inside) {
  double q = 0.0;
  const double bound = ctx.centre_distance >= 0.0 ? ctx.centre_distance - dist(p, ctx.centre) : -1.0;
  if (keep_interior_candidate(ctx.tree, ctx.spacing, p, known_inside, q, bound)) {
    ctx.nodes.add(p, q, NodeKind::Interior, -1);
    ++ctx.added;
  }
}

void place_structured(FillContext& ctx, const Box& b, int count, bool known_inside) {
  const double w = b.width(), h = b.height();
  auto at = [&](double u, double v) { return Vec2{b.lo.x + u * w, b.lo.y + v * h}; };
  if (count == 1 || count == 5) place(ctx, at(0.5, 0.5), known_inside);
  if (count == 4 || count == 5) {
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) place(ctx, at((i + 0.5) / 2.0, (j + 0.5) / 2.0), known_inside);
  }
  if (count == 9) {
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) place(ctx, at((i + 0.5) / 3.0, (j + 0.5) / 3.0), known_inside);
  }
}

// The smallest and largest q of a quad's centre and its eight same-sized neighbours' centres: q is flat
// around the quad where they lie within a factor 1 + a spread; the quad lies on a plateau of q where
// its centre's q is one of the two (inside a region of constant size up to its rim, or on a capped far
// field; on a graded field the centre's q lies strictly between its neighbours').
struct QSpan {
  double lo, hi;
  bool within(double spread) const { return hi <= (1.0 + spread) * lo; }
  bool plateau(double q_mid) const { return q_mid <= lo || q_mid >= hi; }
};

QSpan q_span_around(FillContext& ctx, const Box& b, double q_mid) {
  const Vec2 c = b.centre();
  double q_lo = q_mid, q_hi = q_mid;
  for (int j = -1; j <= 1; ++j) {
    for (int i = -1; i <= 1; ++i) {
      // A neighbour centre without a positive finite q says nothing about the lattice here: skipped.
      const double q = ctx.spacing.at(Vec2{c.x + i * b.width(), c.y + j * b.height()});
      if (!(q > 0.0) || !std::isfinite(q)) continue;
      q_lo = std::fmin(q_lo, q);
      q_hi = std::fmax(q_hi, q);
    }
  }
  return {q_lo, q_hi};
}

// The hybrid fill's first test for a lattice: is quad b (a leaf's final quad wholly inside, q_mid at its
// centre, its centre `centre_distance` from the boundary) far enough from the boundary? The second is
// q_span_around.
bool hybrid_clear_of_boundary(const Box& b, double q_mid, double centre_distance) {
  const double half_diagonal = 0.5 * std::hypot(b.width(), b.height());
  return centre_distance >= kHybridClearance * q_mid + half_diagonal;
}

// The points of the lattice of spacing h inside quad b (closed), each placed once: `level` names the
// lattice, so quads of one level continue one lattice without a seam.
void place_lattice(FillContext& ctx, const Box& b, std::int64_t level, double h, bool known_inside) {
  const double v = 0.5 * std::sqrt(3.0) * h;
  const Vec2 origin = ctx.tree.geometry().extents.lo;
  const auto j_lo = static_cast<std::int64_t>(std::ceil((b.lo.y - origin.y) / v));
  const auto j_hi = static_cast<std::int64_t>(std::floor((b.hi.y - origin.y) / v));
  for (std::int64_t j = j_lo; j <= j_hi; ++j) {
    const double shift = (j % 2 != 0) ? 0.5 * h : 0.0;
    const auto i_lo = static_cast<std::int64_t>(std::ceil((b.lo.x - origin.x - shift) / h));
    const auto i_hi = static_cast<std::int64_t>(std::floor((b.hi.x - origin.x - shift) / h));
    for (std::int64_t i = i_lo; i <= i_hi; ++i) {
      // Level, row and column packed into one key (21 bits each, far more than any lattice needs).
      const std::uint64_t key = (static_cast<std::uint64_t>(level & 0x1FFFFF) << 42) |
                                (static_cast<std::uint64_t>(j & 0x1FFFFF) << 21) |
                                static_cast<std::uint64_t>(i & 0x1FFFFF);
      if (!ctx.state->lattice.insert(key).second) continue;
      place(ctx, Vec2{origin.x + static_cast<double>(i) * h + shift, origin.y + static_cast<double>(j) * v},
            known_inside);
    }
  }
}

// The hexagonal fill: the lattice of q's level.
void place_hexagonal(FillContext& ctx, const Box& b, double q, bool known_inside) {
  const auto level = static_cast<std::int64_t>(std::lround(kHexLevelsPerOctave * std::log2(q)));
  place_lattice(ctx, b, level, std::exp2(static_cast<double>(level) / kHexLevelsPerOctave), known_inside);
}

// The hybrid fill's lattice quad. Without a density: a lattice as dense as the structured pattern the
// quad would get (structured_count(ratio) nodes over its area), so a region holds the patterns' count
// whichever of the two fills each of its quads; the spacing follows from the quad's size and count
// alone, so same-sized quads with the same count (a flat field) continue one lattice, its level log2 h
// in 1/1024 octaves. With a density d: the lattice of the level nearest q_mid / sqrt(d), which holds d
// times the estimate, as the patterns around it do. With DensityWhere::Flat, a quad on a plateau of q
// (QSpan::plateau) keeps the patterns' density whatever the levels: such quads fill the core of a region
// of constant size, whose graded rim (patterns) holds the patterns' band-dependent share (1.65 x the
// estimate in the cores of tests/test_refine_regions.cpp's squares); a core at d x the estimate starts the
// whole square ~5 % short, which population control does not refill, and the edges around the region
// come out that much longer (docs/initialization.md, "The lattice's levels").
void place_hybrid_lattice(FillContext& ctx, const Box& b, double ratio, double q_mid, bool plateau, bool known_inside) {
  // With DensityWhere::Flat and no lattice_levels the lattice keeps the patterns' density: 8 levels per
  // octave meet at seams that population control fills, which prolongs a large run; 4 levels leave fewer
  // seams (docs/initialization.md, "The lattice's levels").
  const int levels = ctx.state->lattice_levels > 0                      ? ctx.state->lattice_levels
                     : ctx.state->density_where == DensityWhere::Inside ? kHybridLatticeLevels
                                                                        : 0;
  const bool patterns_density = plateau && ctx.state->density_where == DensityWhere::Flat;
  const double d = levels > 0 && !patterns_density ? ctx.state->density : 0.0;
  if (d > 0.0) {
    const double per_octave = static_cast<double>(levels);
    const auto level = static_cast<std::int64_t>(std::lround(per_octave * std::log2(q_mid / std::sqrt(d))));
    place_lattice(ctx, b, level, std::exp2(static_cast<double>(level) / per_octave), known_inside);
    return;
  }
  const double area = b.width() * b.height();
  const double h = std::sqrt(2.0 * area / (std::sqrt(3.0) * static_cast<double>(structured_count(ratio))));
  const auto level = static_cast<std::int64_t>(std::lround(1024.0 * std::log2(h)));
  place_lattice(ctx, b, level, h, known_inside);
}

// The share of quad b (wholly inside, centre ctx.centre at ctx.centre_distance from the boundary, or
// -1) whose points pass the keep rule, from 4 x 4 samples: the part the estimate counts for the fill.
double kept_share(FillContext& ctx, const Box& b) {
  int kept = 0;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      const Vec2 p{b.lo.x + (i + 0.5) / 4.0 * b.width(), b.lo.y + (j + 0.5) / 4.0 * b.height()};
      const double bound = ctx.centre_distance >= 0.0 ? ctx.centre_distance - dist(p, ctx.centre) : -1.0;
      double q = 0.0;
      kept += keep_interior_candidate(ctx.tree, ctx.spacing, p, true, q, bound);
    }
  }
  return kept / 16.0;
}

// The hybrid fill's pattern quad wholly inside, with a density d: the pattern of {1, 4, 5, 9} nodes
// nearest to its target (d times the estimate of its kept part) plus what the quads filled before it fell
// short by (error diffusion along the fill's depth-first order), so that any stretch of such quads holds
// its target to within a few nodes whatever their area ratios.
void place_hybrid_pattern(FillContext& ctx, const Box& b, double q_mid, double centre_distance) {
  ctx.centre_distance = centre_distance;
  const double half_diagonal = 0.5 * std::hypot(b.width(), b.height());
  // Only a quad within the clearance (+ 20 % for q's variation) of the boundary loses any of its part.
  const double share =
      centre_distance < half_diagonal + 1.2 * kInitBoundaryClearance * q_mid ? kept_share(ctx, b) : 1.0;
  const double target = ctx.state->density * share * b.width() * b.height() * 2.0 / (std::sqrt(3.0) * q_mid * q_mid);
  const double wanted = ctx.state->shortfall + target;
  int count = 1;
  for (const int n : {4, 5, 9})
    if (std::fabs(wanted - n) < std::fabs(wanted - count)) count = n;
  const std::size_t before = ctx.added;
  place_structured(ctx, b, count, true);
  ctx.state->shortfall = wanted - static_cast<double>(ctx.added - before);
}

void fill_quad(FillContext& ctx, const Box& b, const std::vector<int>& segments, bool known_inside, int depth) {
  const double q_mid = ctx.spacing.at(b.centre());
  if (!(q_mid > 0.0) || !std::isfinite(q_mid))
    throw LimitError(fmt::format("initial distribution: spacing q({}, {}) = {} is not a positive finite number",
                                 b.centre().x, b.centre().y, q_mid));
  const double ratio = b.width() * b.height() / (std::numbers::pi * q_mid * q_mid / 4.0);
  if (ratio > kInitSplitRatio && depth < kMaxFillDepth) {
    const auto& segs = ctx.tree.geometry().segments;
    const Vec2 c = b.centre();
    const Box children[4] = {Box{b.lo, c}, Box{{c.x, b.lo.y}, {b.hi.x, c.y}}, Box{{b.lo.x, c.y}, {c.x, b.hi.y}},
                             Box{c, b.hi}};
    for (const Box& child : children) {
      if (known_inside) {
        fill_quad(ctx, child, segments, true, depth + 1);
        continue;
      }
      std::vector<int> touching;
      for (int s : segments)
        if (segment_touches_box(segs[s].a, segs[s].b, child)) touching.push_back(s);
      // A sub-quad no segment touches is wholly inside or wholly outside: skip the outside ones.
      bool inside = false;
      if (touching.empty()) {
        if (!ctx.tree.inside(child.centre())) continue;
        inside = true;
      }
      fill_quad(ctx, child, touching, inside, depth + 1);
    }
    return;
  }
  const bool hybrid = ctx.method == InitMethod::Hybrid;
  ctx.centre = b.centre();
  // The centre's distance to the boundary, found once: the hybrid's test reads it, and so does the keep
  // rule's bound when the quad gets more than one candidate.
  const double centre_distance = known_inside && hybrid ? ctx.tree.closest(ctx.centre).distance : -1.0;
  // q's span around the quad, computed at most once: the lattice test and the density's DensityWhere::Flat
  // both ask, and the clearance decides first whether the lattice test needs it.
  std::optional<QSpan> span;
  const auto around = [&]() -> const QSpan& {
    if (!span) span = q_span_around(ctx, b, q_mid);
    return *span;
  };
  // DensityWhere::Flat keeps the factor 1.05 whatever the lattice test's spread: a wider one would give the
  // density's targets to graded pattern quads next to the boundary, whose patterns already hold the graded
  // average (below).
  const auto flat = [&] { return around().within(kHybridSpread); };
  const bool lattice = ctx.method == InitMethod::Hexagonal ||
                       (hybrid && known_inside && hybrid_clear_of_boundary(b, q_mid, centre_distance) &&
                        around().within(ctx.state->hybrid_spread));
  const int count = ctx.method == InitMethod::Random ? random_count(ratio)
                    : lattice                        ? static_cast<int>(std::ceil(ratio))
                                                     : structured_count(ratio);
  ctx.centre_distance = !known_inside || count <= 1 ? -1.0
                        : hybrid                    ? centre_distance
                                                    : ctx.tree.closest(ctx.centre).distance;
  if (lattice) {
    if (hybrid)
      place_hybrid_lattice(ctx, b, ratio, q_mid, span->plateau(q_mid), known_inside);
    else
      place_hexagonal(ctx, b, q_mid, known_inside);
    return;
  }
  // The quads a segment cuts keep the structured patterns: the boundary nodes own the band along the
  // curves, and the keep rule already thins the patterns there. With DensityWhere::Flat so do the quads
  // where q is graded: their area ratios spread over the bands, so their patterns already hold about
  // 1.21 times the estimate on average, and only a flat field (all quads in one band) strays from it.
  if (hybrid && known_inside && ctx.state->density > 0.0 &&
      (ctx.state->density_where == DensityWhere::Inside || flat())) {
    place_hybrid_pattern(ctx, b, q_mid, centre_distance);
    return;
  }
  if (ctx.method != InitMethod::Random) {
    place_structured(ctx, b, count, known_inside);
    return;
  }
  for (int k = 0; k < count; ++k) {
    const double u = ctx.rng.next();
    const double v = ctx.rng.next();
    place(ctx, Vec2{b.lo.x + u * b.width(), b.lo.y + v * b.height()}, known_inside);
  }
}

}  // namespace

int structured_count(double ratio) {
  // The thesis only says the ratio "is used to determine how many points" go into the quad. One
  // node while fewer than two bubbles fit, then the nearest of {4, 5, 9} (thresholds 4.5 and 7).
  // "Two" is 2.05 here: our tree's root is 1% wider than the geometry (InitTree), which makes every
  // leaf's area ratio 2% larger than in a tree on the geometry itself (2 x 1.01^2 = 2.04).
  // Evidence (docs/initialization.md): the thesis' 200 x 200 square (fig. 7.1, leaves of 25, ratio
  // 1.99) got one node per leaf, 64 in all; a threshold of 2.5 would give the circle within a circle,
  // the one thesis case whose geometry is fully given, 2304 nodes against Table 6.1's 2536 (2.05
  // gives 2436), and structured starts on the rod assembly fewer nodes than random ones, where every
  // row of Table 6.1 has more.
  if (!(ratio >= 2.05)) return 1;
  if (ratio < 4.5) return 4;
  if (ratio < 7.0) return 5;
  return 9;
}

int random_count(double ratio) {
  if (!(ratio >= 1.0)) return 1;
  return static_cast<int>(std::clamp(std::round(ratio), 1.0, 9.0));
}

bool keep_interior_candidate(const GeometryTree& tree, const SpacingField& spacing, Vec2 p, bool known_inside,
                             double& q, double distance_lower_bound) {
  if (!known_inside && !tree.inside(p)) return false;
  q = spacing.at(p);
  if (!(q > 0.0) || !std::isfinite(q)) return false;
  const double needed = kInitBoundaryClearance * q;
  // The bound comes from rounded distances: trust it only with a relative margin.
  if (distance_lower_bound >= needed * (1.0 + 1e-9)) return true;
  return tree.closest(p).distance >= needed;
}

std::size_t fill_leaf(const GeometryTree& tree, const SpacingField& spacing, const InitLeaf& leaf, InitMethod method,
                      UnitRandom& rng, NodeSet& nodes, FillState* state) {
  if ((method == InitMethod::Hexagonal || method == InitMethod::Hybrid) && state == nullptr)
    throw Error("fill_leaf: the hexagonal and hybrid fills need the fill's state (lattice points, shortfall)");
  FillContext ctx{tree, spacing, method, rng, nodes, 0, {}, -1.0, state};
  // Kept leaves without segments lie wholly inside (InitTree keeps only those whose centre is inside).
  fill_quad(ctx, leaf.box, leaf.segments, leaf.segments.empty(), 0);
  return ctx.added;
}

}  // namespace pdmesh
