// BackgroundBuilder: level-synchronous refinement of the background quadtree (one at_many call for a
// level's corners and one for its test points, so a field backed by an interpreter is called a few
// dozen times with large batches, never per point) and the depth-first flat layout.
#include "spacing/background_builder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "core/parallel.hpp"
#include "core/progress_notes.hpp"
#include "spacing/inverse_square_integral.hpp"

namespace pdmesh {

namespace {
// Cells tested per thread at least (a test is a few lookups and nine interpolations).
constexpr std::size_t kTestsPerThread = 2048;
// New cells set up per thread at least (a few exact segment-box tests, or one inside test, each).
constexpr std::size_t kChildrenPerThread = 1024;
}  // namespace

BackgroundBuilder::BackgroundBuilder(const SpacingField& exact, const GeometryTree& tree,
                                     const BackgroundOptions& options)
    : exact_(&exact),
      tree_(tree),
      opt_(options),
      resolution_(options.max_depth + 2),
      lattice_unit_(std::ldexp(1.0, -resolution_)) {}

// Level R = max_depth + 2 resolves the quarter points of the finest cells, so every sample point has
// integer lattice coordinates and a 64-bit key; samples shared by neighbouring cells are evaluated once.
double BackgroundBuilder::coord(double origin, std::uint32_t lattice) const {
  return origin + root_size_ * (static_cast<double>(lattice) * lattice_unit_);
}

double BackgroundBuilder::side(int level) const {
  // The levels a cell can have come from the table (the same ldexp values, without a libm call per
  // cell in the per-level decisions and budgets).
  if (level >= 0 && static_cast<std::size_t>(level) < sides_.size()) return sides_[static_cast<std::size_t>(level)];
  return std::ldexp(root_size_, -level);
}

void BackgroundBuilder::set_root_size(double root_size) {
  root_size_ = root_size;
  sides_.resize(static_cast<std::size_t>(resolution_) + 1);
  for (std::size_t level = 0; level < sides_.size(); ++level)
    sides_[level] = std::ldexp(root_size_, -static_cast<int>(level));
}

double BackgroundBuilder::sample(std::uint32_t x, std::uint32_t y) const {
  return values_[static_cast<std::size_t>(samples_.at(key(x, y)))];
}

void BackgroundBuilder::sample_all(const std::vector<std::uint64_t>& keys, std::vector<std::int32_t>& ids) {
  // New samples take the next ids in the order of their first key: the values land in values_ by id,
  // with no second lookup, and callers keep the ids instead of looking keys up again.
  const std::size_t first = values_.size();
  std::vector<Vec2> points;
  ids.resize(keys.size());
  // The table outgrows the caches (263k samples on 30P30N's curves: 1M slots, 16 MB), so each key's
  // slot is fetched a few keys ahead of its insertion; room is made first so that no rehash in the loop
  // moves the slots fetched. Neither changes an id or a value.
  samples_.reserve(samples_.size() + keys.size());
  constexpr std::size_t kAhead = 8;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (i + kAhead < keys.size()) samples_.prefetch(keys[i + kAhead]);
    const std::uint64_t k = keys[i];
    const auto [id, fresh] = samples_.try_emplace(k, static_cast<std::int32_t>(first + points.size()));
    ids[i] = *id;
    if (fresh)
      points.push_back(point(static_cast<std::uint32_t>(k >> 32), static_cast<std::uint32_t>(k & 0xffffffffu)));
  }
  if (points.empty()) return;
  std::vector<double> q;
  exact_->at_many(points, q);
  ++batches_;
  values_.insert(values_.end(), q.begin(), q.end());
}

// The square: the extents' bounding square grown by 1/64 so that points off the grid are outside the
// domain; the top grid makes root cells about size_factor * (largest of 81 samples).
void BackgroundBuilder::choose_grid() {
  const Box& e = tree_.geometry().extents;
  Vec2 centre{0.0, 0.0};
  double side = 1.0;
  if (e.lo.x <= e.hi.x && e.lo.y <= e.hi.y) {
    centre = e.centre();
    side = std::max(e.width(), e.height());
    if (!(side > 0.0)) side = 1.0;
  }
  side *= 1.0 + 1.0 / 64.0;
  std::vector<Vec2> points;
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j)
      points.push_back({centre.x + side * (i / 8.0 - 0.5), centre.y + side * (j / 8.0 - 0.5)});
  std::vector<double> q;
  exact_->at_many(points, q);
  ++batches_;
  double q_max = 0.0;
  for (const double v : q) q_max = std::max(q_max, v);
  const double cells = std::ceil(side / (opt_.size_factor * q_max));
  grid_ = cells >= opt_.max_grid ? opt_.max_grid : std::max(1, static_cast<int>(cells));
  set_root_size(side / grid_);
  origin_x_ = centre.x - 0.5 * side;
  origin_y_ = centre.y - 0.5 * side;
}

void BackgroundBuilder::set_tag(Cell& c, std::vector<int> segments) {
  const std::uint32_t half = span(c.level) / 2;
  const bool inside = segments.empty() && tree_.inside(point(c.x + half, c.y + half));
  set_tag(c, std::move(segments), inside);
}

void BackgroundBuilder::set_tag(Cell& c, std::vector<int> segments, bool inside) {
  if (segments.empty()) {
    c.tag = static_cast<std::int8_t>(inside ? kTagInside : kTagOutside);
    return;
  }
  c.tag = kTagBoundary;
  c.segments = static_cast<std::int32_t>(segment_lists_.size());
  segment_lists_.push_back(std::move(segments));
}

// Each segment goes to the root cells its bounding box overlaps that it really touches (exact test).
void BackgroundBuilder::make_roots() {
  const auto& segs = tree_.geometry().segments;
  const int g = grid_;
  const double inv = 1.0 / root_size_;
  auto cell_of = [&](double c, double origin) {
    const double f = std::floor((c - origin) * inv);
    return f < 0.0 ? 0 : f > g - 1 ? g - 1 : static_cast<int>(f);
  };
  auto root_box = [&](int x, int y) {
    Box b;
    b.lo = point(static_cast<std::uint32_t>(x) << resolution_, static_cast<std::uint32_t>(y) << resolution_);
    b.hi = point(static_cast<std::uint32_t>(x + 1) << resolution_, static_cast<std::uint32_t>(y + 1) << resolution_);
    return b;
  };
  const auto cells = static_cast<std::size_t>(g) * static_cast<std::size_t>(g);
  std::vector<std::vector<int>> root_segments(cells);
  for (std::size_t s = 0; s < segs.size(); ++s) {
    const Segment& seg = segs[s];
    // One cell of slack each way: the floor above may round either way at a cell edge.
    const int x0 = std::max(0, cell_of(std::min(seg.a.x, seg.b.x), origin_x_) - 1);
    const int x1 = std::min(g - 1, cell_of(std::max(seg.a.x, seg.b.x), origin_x_) + 1);
    const int y0 = std::max(0, cell_of(std::min(seg.a.y, seg.b.y), origin_y_) - 1);
    const int y1 = std::min(g - 1, cell_of(std::max(seg.a.y, seg.b.y), origin_y_) + 1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        if (segment_touches_box(seg.a, seg.b, root_box(x, y)))
          root_segments[static_cast<std::size_t>(y) * static_cast<std::size_t>(g) + static_cast<std::size_t>(x)]
              .push_back(static_cast<int>(s));
  }
  cells_.resize(cells);
  for (std::size_t k = 0; k < cells; ++k) {
    Cell& c = cells_[k];
    c.x = static_cast<std::uint32_t>(k % static_cast<std::size_t>(g)) << resolution_;
    c.y = static_cast<std::uint32_t>(k / static_cast<std::size_t>(g)) << resolution_;
    set_tag(c, std::move(root_segments[k]));
  }
}

void BackgroundBuilder::build() {
  choose_grid();
  // The root cells are the first allocation in proportion to the field (up to 512 x 512).
  check_memory(opt_.memory, kBytesPerCell * static_cast<double>(grid_) * static_cast<double>(grid_),
               fmt::format("the spacing field's background quadtree of {} x {} root cells", grid_, grid_),
               "raise --max-memory");
  make_roots();
  std::vector<int> roots(cells_.size());
  for (std::size_t k = 0; k < roots.size(); ++k) roots[k] = static_cast<int>(k);
  // The default rules only read the cell and the samples: their decisions are made on all cores.
  decide_in_parallel_ = true;
  try {
    refine(
        std::move(roots), [this](const Cell& c, const double q[4]) { return default_decide(c, q); },
        [this](const Cell&, const double q[4], const double exact[9], const std::int32_t*, int count) {
          return default_test(q, exact, count);
        },
        [this](const Cell&, std::uint32_t, std::uint32_t, std::int32_t id) { return sample_value(id); });
  } catch (...) {
    decide_in_parallel_ = false;
    throw;
  }
  decide_in_parallel_ = false;
}

BackgroundBuilder::Decision BackgroundBuilder::default_decide(const Cell& c, const double q[4]) const {
  if (c.level >= opt_.max_depth || c.tag == kTagOutside) return Decision::Leaf;
  const double q_min = std::min(std::min(q[0], q[1]), std::min(q[2], q[3]));
  const double s = side(c.level);
  if (s > opt_.size_factor * q_min) return Decision::Split;
  if (c.tag == kTagBoundary) return s < opt_.boundary_min_side_fraction * q_min ? Decision::Leaf : Decision::Test;
  if (s < std::min(opt_.min_side_fraction, opt_.jump_min_side_fraction) * q_min) return Decision::Leaf;
  if (s >= opt_.min_side_fraction * q_min) return Decision::Test;
  // The band below the cap: only a cell whose corners differ by a factor, which may straddle a large jump
  // (a refinement region's edge), is tested; any other stops here, without test samples.
  const double q_max = std::max(std::max(q[0], q[1]), std::max(q[2], q[3]));
  return q_max > (1.0 + opt_.jump_tolerance) * q_min ? Decision::Test : Decision::Leaf;
}

bool BackgroundBuilder::default_test(const double q[4], const double exact[9], int count) const {
  for (int t = 0; t < count; ++t) {
    const double u = kTests[t][0] / 4.0, v = kTests[t][1] / 4.0;
    const double bilinear = (1.0 - v) * ((1.0 - u) * q[0] + u * q[1]) + v * ((1.0 - u) * q[2] + u * q[3]);
    // Half the tolerance: the 9 test points see most, but not all, of the worst error in the cell.
    if (std::fabs(bilinear - exact[t]) > 0.5 * opt_.tolerance * exact[t]) return true;
  }
  return false;
}

void BackgroundBuilder::check_budget(const std::vector<int>& level_cells, const std::vector<Decision>& decision,
                                     const std::vector<double>& corners) {
  std::size_t splits = 0;
  for (const Decision d : decision) splits += d == Decision::Split ? 1 : 0;
  if (opt_.max_nodes > 0.0) {
    // The hexagonal-packing count of the inside cells, on their bilinear q: exact for the leaves' final
    // field and converging to it level by level for the cells that split. Boundary cells are left
    // out (the part of them inside the domain is not known here; counting them whole would refuse a
    // thin domain on its coarse levels).
    const double hex = 2.0 / std::sqrt(3.0);
    // Each cell's count on all cores (a logarithm each), then the sums in the cells' order: the same
    // sums as one loop.
    std::vector<double> cell_nodes(level_cells.size(), 0.0);
    parallel_for(
        level_cells.size(),
        [&](std::size_t n) {
          const Cell& c = cells_[static_cast<std::size_t>(level_cells[n])];
          if (c.tag != kTagInside) return;
          const double* q = &corners[4 * n];
          if (!(q[0] > 0.0 && q[1] > 0.0 && q[2] > 0.0 && q[3] > 0.0)) return;
          const double s = side(c.level);
          cell_nodes[n] = hex * s * s * inverse_square_integral(q[0], q[1], q[2], q[3]);
        },
        kTestsPerThread, opt_.loop_threads());
    double splitting = 0.0;
    for (std::size_t n = 0; n < level_cells.size(); ++n) {
      const Cell& c = cells_[static_cast<std::size_t>(level_cells[n])];
      if (c.tag != kTagInside) continue;
      const double* q = &corners[4 * n];
      if (!(q[0] > 0.0 && q[1] > 0.0 && q[2] > 0.0 && q[3] > 0.0)) continue;
      (decision[n] == Decision::Split ? splitting : finished_nodes_) += cell_nodes[n];
    }
    const double estimate = finished_nodes_ + splitting;
    if (!(estimate <= kEarlyNodeMargin * opt_.max_nodes)) {
      const Cell& c = cells_[static_cast<std::size_t>(level_cells.front())];
      throw LimitError(fmt::format(
          "the spacing field asks for about {} nodes already on level {} of its quadtree (cells of side {:.3g}; "
          "hexagonal-packing estimate over the cells inside the domain), more than --max-nodes {:.0f}; coarsen "
          "the spacing or raise --max-nodes",
          std::isfinite(estimate) ? fmt::format("{:.3g}", estimate) : std::string("infinitely many"), c.level,
          side(c.level), opt_.max_nodes));
    }
  }
  if (splits == 0) return;
  const double cells = static_cast<double>(cells_.size()) + 4.0 * static_cast<double>(splits);
  check_memory(opt_.memory, kBytesPerCell * cells,
               fmt::format("the spacing field's background quadtree of {:.3g} cells (level {})", cells,
                           cells_[static_cast<std::size_t>(level_cells.front())].level + 1),
               "raise --max-memory, or coarsen the spacing");
}

// The work arrays of one level of refine(): its cells with, per cell, the four corner values and the
// decision; the cells tested (indices into `cells`) with the exact values and sample ids at their
// test points; and the batch buffers (a batch's lattice keys and their sample ids).
struct BackgroundBuilder::Level {
  std::vector<int> cells;
  std::vector<double> corners;     // 4 per cell
  std::vector<Decision> decision;  // per cell
  std::vector<int> tested;
  std::vector<double> exact;           // 9 per tested cell
  std::vector<std::int32_t> test_ids;  // 9 per tested cell
  std::vector<std::uint64_t> keys;
  std::vector<std::int32_t> ids;
};

// Step 1: the corners of every cell of the level, in one batch. Most are known already: a child's
// corners are its parent's corners and test points (step 3), and a leaf refined again keeps its own.
// Only the others are looked up (or sampled): the same new samples in the same order.
void BackgroundBuilder::sample_corners(Level& level, const SampledFn& sampled) {
  level.keys.clear();
  std::vector<std::size_t> unknown;  // 4 n + k: corner k of level.cells[n]
  for (std::size_t n = 0; n < level.cells.size(); ++n) {
    const Cell& c = cells_[static_cast<std::size_t>(level.cells[n])];
    const std::uint32_t s = span(c.level);
    for (int k = 0; k < 4; ++k) {
      if (c.corner[k] >= 0) continue;
      level.keys.push_back(key(c.x + (k & 1 ? s : 0u), c.y + (k & 2 ? s : 0u)));
      unknown.push_back(4 * n + static_cast<std::size_t>(k));
    }
  }
  sample_all(level.keys, level.ids);
  for (std::size_t i = 0; i < unknown.size(); ++i)
    cells_[static_cast<std::size_t>(level.cells[unknown[i] / 4])].corner[unknown[i] % 4] = level.ids[i];
  if (sampled) sampled(level.keys, level.ids);
}

// The corner values and the decision of every cell of the level; the cells to test, with the keys of
// their first test points (the centre and edge midpoints) as the next batch.
void BackgroundBuilder::decide_level(Level& level, const DecideFn& decide, const CornerFn& corner_value) {
  level.corners.resize(4 * level.cells.size());
  level.decision.assign(level.cells.size(), Decision::Leaf);
  level.keys.clear();
  level.tested.clear();
  auto corners_and_decision = [&](std::size_t n) {
    const Cell& c = cells_[static_cast<std::size_t>(level.cells[n])];
    const std::uint32_t s = span(c.level);
    double* q = &level.corners[4 * n];
    q[0] = corner_value(c, c.x, c.y, c.corner[0]);
    q[1] = corner_value(c, c.x + s, c.y, c.corner[1]);
    q[2] = corner_value(c, c.x, c.y + s, c.corner[2]);
    q[3] = corner_value(c, c.x + s, c.y + s, c.corner[3]);
    level.decision[n] = decide(c, q);
  };
  // Each cell writes only its own corners and decision; with rules that only read (build()), on all
  // cores, else on this thread in the cells' order, as the caller's rules may keep state.
  if (decide_in_parallel_) parallel_for(level.cells.size(), corners_and_decision, kTestsPerThread, opt_.loop_threads());
  for (std::size_t n = 0; n < level.cells.size(); ++n) {
    if (!decide_in_parallel_) corners_and_decision(n);
    if (level.decision[n] != Decision::Test) continue;
    const Cell& c = cells_[static_cast<std::size_t>(level.cells[n])];
    const std::uint32_t s = span(c.level);
    level.tested.push_back(static_cast<int>(n));
    const std::uint32_t quarter = s / 4;
    for (int t = 0; t < kFirstQuarterTest; ++t)
      level.keys.push_back(key(c.x + quarter * static_cast<std::uint32_t>(kTests[t][0]),
                               c.y + quarter * static_cast<std::uint32_t>(kTests[t][1])));
  }
}

// The keys of the quarter points of the tested cells the first round did not split, as the next
// batch; first_key[m] is where tested cell m's keys start in it.
void BackgroundBuilder::quarter_point_keys(Level& level, std::vector<std::size_t>& first_key) const {
  level.keys.clear();
  for (std::size_t m = 0; m < level.tested.size(); ++m) {
    const auto n = static_cast<std::size_t>(level.tested[m]);
    if (level.decision[n] == Decision::Split) continue;
    first_key[m] = level.keys.size();
    const Cell& c = cells_[static_cast<std::size_t>(level.cells[n])];
    const std::uint32_t quarter = span(c.level) / 4;
    for (int t = kFirstQuarterTest; t < 9; ++t)
      level.keys.push_back(key(c.x + quarter * static_cast<std::uint32_t>(kTests[t][0]),
                               c.y + quarter * static_cast<std::uint32_t>(kTests[t][1])));
  }
}

// Step 2: the test points of the cells whose corners did not decide, in two batches: first the centre
// and edge midpoints (the corners of the children, needed anyway if the cell splits), then, for the
// cells these did not already split, the quarter points. Evaluating all 9 at once costs a third more
// samples on 30P30N than the per-point builder, whose tests stop at the first failure.
void BackgroundBuilder::test_level(Level& level, const TestFn& test, const SampledFn& sampled) {
  const std::vector<int>& tested = level.tested;
  level.exact.assign(9 * tested.size(), 0.0);
  level.test_ids.assign(9 * tested.size(), 0);
  std::vector<std::size_t> first_key(tested.size());  // where tested cell m's keys start in this round's batch
  for (std::size_t m = 0; m < tested.size(); ++m) first_key[m] = kFirstQuarterTest * m;
  for (const int round : {0, 1}) {
    if (round == 1) quarter_point_keys(level, first_key);
    sample_all(level.keys, level.ids);
    if (sampled) sampled(level.keys, level.ids);
    // The tests only read (the samples, the caller's state), and each writes its own cell's decision:
    // on all cores, with the decisions of one loop.
    parallel_for(
        tested.size(),
        [&](std::size_t m) {
          const auto n = static_cast<std::size_t>(tested[m]);
          if (round == 1 && level.decision[n] == Decision::Split) return;
          const Cell& c = cells_[static_cast<std::size_t>(level.cells[n])];
          const int from = round == 0 ? 0 : kFirstQuarterTest;
          const int count = round == 0 ? kFirstQuarterTest : 9;
          for (int t = from; t < count; ++t) {
            const std::int32_t id = level.ids[first_key[m] + static_cast<std::size_t>(t - from)];
            level.test_ids[9 * m + static_cast<std::size_t>(t)] = id;
            level.exact[9 * m + static_cast<std::size_t>(t)] = values_[static_cast<std::size_t>(id)];
          }
          const bool split = test(c, &level.corners[4 * n], &level.exact[9 * m], &level.test_ids[9 * m], count);
          level.decision[n] = split ? Decision::Split : round == 0 ? Decision::Test : Decision::Leaf;
        },
        kTestsPerThread, opt_.loop_threads());
  }
}

// The four children of the level's cell n, which splits, appended to cells_ and to `next`; m is its
// index among the tested cells (-1: not tested). Returns the parent's segment list, moved out of it.
std::vector<int> BackgroundBuilder::split_cell(const Level& level, std::size_t n, std::int32_t m,
                                               std::vector<int>& next) {
  // The sample ids at the parent's points in quarters (0, 2, 4 each way): its corners, and its centre
  // and edge midpoints when it was tested (else -1: step 1 looks them up).
  std::int32_t at[3][3];
  for (auto& row : at) std::fill(row, row + 3, -1);
  {
    const Cell& c = cells_[static_cast<std::size_t>(level.cells[n])];
    for (int k = 0; k < 4; ++k) at[k & 2 ? 2 : 0][k & 1 ? 2 : 0] = c.corner[k];
    if (m >= 0)
      for (int t = 0; t < kFirstQuarterTest; ++t)
        at[kTests[t][1] / 2][kTests[t][0] / 2] =
            level.test_ids[9 * static_cast<std::size_t>(m) + static_cast<std::size_t>(t)];
  }
  const auto parent = static_cast<std::size_t>(level.cells[n]);
  const auto first = static_cast<std::int32_t>(cells_.size());
  cells_[parent].first_child = first;
  const Cell p = cells_[parent];
  std::vector<int> parent_list;
  if (p.segments >= 0) {
    parent_list = std::move(segment_lists_[static_cast<std::size_t>(p.segments)]);
    cells_[parent].segments = -1;  // an inner cell needs no list (the vector was moved out)
  }
  const std::uint32_t h = span(p.level) / 2;
  for (int k = 0; k < 4; ++k) {
    Cell child;
    child.x = p.x + (k & 1 ? h : 0u);
    child.y = p.y + (k & 2 ? h : 0u);
    child.level = static_cast<std::int8_t>(p.level + 1);
    child.parent = static_cast<std::int32_t>(parent);
    for (int j = 0; j < 4; ++j)
      child.corner[j] = at[(k & 2 ? 1 : 0) + (j & 2 ? 1 : 0)][(k & 1 ? 1 : 0) + (j & 1 ? 1 : 0)];
    cells_.push_back(child);
    next.push_back(first + k);
  }
  return parent_list;
}

// Step 3: the children of the level's split cells, in the cells' order, as `next`; parent_lists gets
// each split cell's segment list. Returns the number of cells split.
std::size_t BackgroundBuilder::split_level(const Level& level, std::vector<int>& next,
                                           std::vector<std::vector<int>>& parent_lists) {
  next.clear();
  std::vector<std::int32_t> tested_as(level.cells.size(), -1);  // n -> m
  for (std::size_t m = 0; m < level.tested.size(); ++m)
    tested_as[static_cast<std::size_t>(level.tested[m])] = static_cast<std::int32_t>(m);
  std::size_t splits = 0;
  for (std::size_t n = 0; n < level.cells.size(); ++n) {
    if (level.decision[n] != Decision::Split) continue;
    ++splits;
    parent_lists.push_back(split_cell(level, n, tested_as[n], next));
  }
  return splits;
}

// The children's segment lists (exact segment-box tests) and, for those without segments, the inside
// test of their centre: on all cores, each child writing its own entries; then the tags in the
// children's order, as set_tag always numbered the lists. The children of a cell without segments
// take its tag without a test: its closed box touches no segment, so every point of it (the
// children's centres among them, point() being monotonic) lies on the same side of the boundary as
// its centre, and the exact even-odd test would give each of them the parent's answer.
void BackgroundBuilder::tag_children(const std::vector<int>& next, const std::vector<std::vector<int>>& parent_lists) {
  const auto& segs = tree_.geometry().segments;
  std::vector<std::vector<int>> child_segments(next.size());
  std::vector<std::uint8_t> inside(next.size(), 0);
  parallel_for(
      next.size(),
      [&](std::size_t i) {
        const Cell& child = cells_[static_cast<std::size_t>(next[i])];
        const std::int8_t parent_tag = cells_[static_cast<std::size_t>(child.parent)].tag;
        if (parent_tag != kTagBoundary) {
          inside[i] = parent_tag == kTagInside ? 1 : 0;
          return;
        }
        const std::uint32_t h = span(child.level);
        Box b;
        b.lo = point(child.x, child.y);
        b.hi = point(child.x + h, child.y + h);
        for (const int s : parent_lists[i / 4])
          if (segment_touches_box(segs[static_cast<std::size_t>(s)].a, segs[static_cast<std::size_t>(s)].b, b))
            child_segments[i].push_back(s);
        if (child_segments[i].empty()) inside[i] = tree_.inside(point(child.x + h / 2, child.y + h / 2)) ? 1 : 0;
      },
      kChildrenPerThread, opt_.loop_threads());
  for (std::size_t i = 0; i < next.size(); ++i)
    set_tag(cells_[static_cast<std::size_t>(next[i])], std::move(child_segments[i]), inside[i] != 0);
}

std::size_t BackgroundBuilder::refine(std::vector<int> level_cells, const DecideFn& decide, const TestFn& test,
                                      const CornerFn& corner_value, const SampledFn& sampled) {
  PhaseProgress progress("spacing field");
  finished_nodes_ = 0.0;
  std::size_t splits = 0;
  Level level;
  level.cells = std::move(level_cells);
  std::vector<int> next;
  while (!level.cells.empty()) {
    check_interrupt();
    sample_corners(level, sampled);
    decide_level(level, decide, corner_value);
    test_level(level, test, sampled);
    // The next level, once the budgets allow it.
    check_budget(level.cells, level.decision, level.corners);
    progress.note([&] {
      return fmt::format("quadtree level {}: {} cells, {} samples",
                         cells_[static_cast<std::size_t>(level.cells.front())].level, cells_.size(), values_.size());
    });
    std::vector<std::vector<int>> parent_lists;  // per split cell, in order: its segments
    splits += split_level(level, next, parent_lists);
    tag_children(next, parent_lists);
    level.cells.swap(next);
  }
  return splits;
}

const std::vector<int>& BackgroundBuilder::segments(const Cell& c) const {
  static const std::vector<int> none;
  return c.segments >= 0 ? segment_lists_[static_cast<std::size_t>(c.segments)] : none;
}

std::vector<int> BackgroundBuilder::leaves() const {
  std::vector<int> out;
  for (std::size_t i = 0; i < cells_.size(); ++i)
    if (cells_[i].first_child < 0) out.push_back(static_cast<int>(i));
  return out;
}

int BackgroundBuilder::locate(Vec2 p) const {
  // The lattice coordinates of p, clamped onto the grid; then the descent by the children's midlines.
  const double scale = std::ldexp(1.0 / root_size_, resolution_);
  const double top = std::ldexp(static_cast<double>(grid_), resolution_) - 1.0;
  const double fx = std::clamp(std::floor((p.x - origin_x_) * scale), 0.0, top);
  const double fy = std::clamp(std::floor((p.y - origin_y_) * scale), 0.0, top);
  const auto x = static_cast<std::uint32_t>(fx), y = static_cast<std::uint32_t>(fy);
  int cell = static_cast<int>((y >> resolution_) * static_cast<std::uint32_t>(grid_) + (x >> resolution_));
  while (cells_[static_cast<std::size_t>(cell)].first_child >= 0) {
    const Cell& c = cells_[static_cast<std::size_t>(cell)];
    const std::uint32_t h = span(c.level) / 2;
    cell = c.first_child + (x >= c.x + h ? 1 : 0) + (y >= c.y + h ? 2 : 0);
  }
  return cell;
}

BackgroundFieldData BackgroundBuilder::emit(const ValueFn& corner_value) const {
  BackgroundFieldData d;
  d.origin_x = origin_x_;
  d.origin_y = origin_y_;
  d.root_size = root_size_;
  d.inv_root_size = 1.0 / root_size_;
  d.grid = grid_;
  // Distinct corners numbered in the order first reached, by sample id (every leaf corner is a sample).
  std::vector<std::int32_t> corner_ids(values_.size(), -1);
  const std::uint32_t below_root = (std::uint32_t{1} << resolution_) - 1;
  auto corner = [&](std::int32_t sample_id) {
    std::int32_t& id = corner_ids[static_cast<std::size_t>(sample_id)];
    if (id < 0) {
      id = static_cast<std::int32_t>(d.corner_q.size());
      d.corner_q.push_back(corner_value ? corner_value(sample_id) : values_[static_cast<std::size_t>(sample_id)]);
    }
    return id;
  };
  // Every cell is a node; the leaves' arrays are sized once.
  std::size_t leaves = 0;
  for (const Cell& c : cells_) leaves += c.first_child < 0 ? 1 : 0;
  d.node_child.reserve(cells_.size());
  d.leaf_tag.reserve(leaves);
  d.leaf_cell.reserve(4 * leaves);
  d.leaf_corner.reserve(4 * leaves);
  auto new_node = [&] {
    d.node_child.push_back(-1);
    return static_cast<int>(d.node_child.size()) - 1;
  };
  // Depth first, children numbered when their parent is reached: the numbering of the recursive
  // builder this one replaced, so the arrays are the same bit for bit. The walk keeps its own stack of
  // (cell, node), the children pushed last to first so that the first is visited first.
  std::vector<std::pair<int, int>> stack;
  auto visit = [&](int root, int root_node) {
    stack.assign(1, {root, root_node});
    while (!stack.empty()) {
      const auto [cell, node] = stack.back();
      stack.pop_back();
      const Cell& c = cells_[static_cast<std::size_t>(cell)];
      d.max_depth = std::max(d.max_depth, static_cast<std::int32_t>(c.level));
      if (c.first_child < 0) {
        d.node_child[static_cast<std::size_t>(node)] = -1 - static_cast<std::int32_t>(d.leaf_tag.size());
        d.leaf_tag.push_back(c.tag);
        d.leaf_cell.push_back(
            static_cast<std::int32_t>((c.y >> resolution_) * static_cast<std::uint32_t>(grid_) + (c.x >> resolution_)));
        d.leaf_cell.push_back(c.level);
        d.leaf_cell.push_back(static_cast<std::int32_t>((c.x & below_root) >> (resolution_ - c.level)));
        d.leaf_cell.push_back(static_cast<std::int32_t>((c.y & below_root) >> (resolution_ - c.level)));
        for (const std::int32_t id : c.corner) d.leaf_corner.push_back(corner(id));
        continue;
      }
      const int first = new_node();
      for (int k = 1; k < 4; ++k) new_node();
      d.node_child[static_cast<std::size_t>(node)] = first;
      for (int k = 3; k >= 0; --k) stack.emplace_back(c.first_child + k, first + k);
    }
  };
  const auto roots = static_cast<std::size_t>(grid_) * static_cast<std::size_t>(grid_);
  d.root_node.resize(roots);
  for (std::size_t k = 0; k < roots; ++k) {
    d.root_node[k] = new_node();
    visit(static_cast<int>(k), d.root_node[k]);
  }
  return d;
}

}  // namespace pdmesh
