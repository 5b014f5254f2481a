// The level-synchronous background builder: it evaluates the exact field only through at_many, in a
// few batches per level, and builds the same arrays bit for bit as the recursive per-point builder it
// replaced (kept here, as it was, as the oracle).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include "geometry/curve_reader.hpp"
#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "spacing/background_builder.hpp"
#include "spacing/background_field.hpp"
#include "spacing/spacing_pipeline.hpp"

using namespace pdmesh;

namespace {

// The recursive builder as it was before batching: depth first, one exact at() per new sample.
class RecursiveBuilder {
 public:
  RecursiveBuilder(const SpacingField& exact, const GeometryTree& tree, const BackgroundOptions& options,
                   BackgroundFieldData& data)
      : exact_(exact), tree_(tree), opt_(options), d_(data), resolution_(options.max_depth + 2) {}

  void build() {
    choose_grid();
    const auto g = static_cast<std::size_t>(d_.grid);
    std::vector<std::vector<int>> root_segments(g * g);
    bin_segments(root_segments);
    d_.root_node.resize(g * g);
    for (std::size_t k = 0; k < g * g; ++k) {
      d_.root_node[k] = new_node();
      const Cell cell{static_cast<std::uint32_t>(k % g) << resolution_,
                      static_cast<std::uint32_t>(k / g) << resolution_, 0};
      build_cell(d_.root_node[k], cell, root_segments[k]);
    }
  }

  std::size_t evaluations() const { return samples_.size(); }

 private:
  struct Cell {
    std::uint32_t x, y;
    int level;
  };
  std::uint32_t span(int level) const { return std::uint32_t{1} << (resolution_ - level); }
  double coord(double origin, std::uint32_t lattice) const {
    return origin + d_.root_size * std::ldexp(static_cast<double>(lattice), -resolution_);
  }
  Box box(const Cell& c) const {
    Box b;
    b.lo = {coord(d_.origin_x, c.x), coord(d_.origin_y, c.y)};
    b.hi = {coord(d_.origin_x, c.x + span(c.level)), coord(d_.origin_y, c.y + span(c.level))};
    return b;
  }
  static std::uint64_t key(std::uint32_t x, std::uint32_t y) { return (std::uint64_t{x} << 32) | y; }
  double sample(std::uint32_t x, std::uint32_t y) {
    const auto [it, inserted] = samples_.try_emplace(key(x, y), 0.0);
    if (inserted) it->second = exact_.at({coord(d_.origin_x, x), coord(d_.origin_y, y)});
    return it->second;
  }
  std::int32_t corner(std::uint32_t x, std::uint32_t y) {
    const auto [it, inserted] = corners_.try_emplace(key(x, y), static_cast<std::int32_t>(d_.corner_q.size()));
    if (inserted) d_.corner_q.push_back(sample(x, y));
    return it->second;
  }
  int new_node() {
    d_.node_child.push_back(-1);
    return static_cast<int>(d_.node_child.size()) - 1;
  }
  void choose_grid() {
    const Box& e = tree_.geometry().extents;
    const Vec2 centre = e.centre();
    double side = std::max(e.width(), e.height());
    side *= 1.0 + 1.0 / 64.0;
    double q_max = 0.0;
    for (int i = 0; i <= 8; ++i)
      for (int j = 0; j <= 8; ++j)
        q_max = std::max(q_max, exact_.at({centre.x + side * (i / 8.0 - 0.5), centre.y + side * (j / 8.0 - 0.5)}));
    const double cells = std::ceil(side / (opt_.size_factor * q_max));
    d_.grid = cells >= opt_.max_grid ? opt_.max_grid : std::max(1, static_cast<int>(cells));
    d_.root_size = side / d_.grid;
    d_.inv_root_size = 1.0 / d_.root_size;
    d_.origin_x = centre.x - 0.5 * side;
    d_.origin_y = centre.y - 0.5 * side;
  }
  void bin_segments(std::vector<std::vector<int>>& root_segments) const {
    const auto& segs = tree_.geometry().segments;
    const int g = d_.grid;
    auto cell_of = [&](double c, double origin) {
      const double f = std::floor((c - origin) * d_.inv_root_size);
      return f < 0.0 ? 0 : f > g - 1 ? g - 1 : static_cast<int>(f);
    };
    for (std::size_t s = 0; s < segs.size(); ++s) {
      const Segment& seg = segs[s];
      const int x0 = std::max(0, cell_of(std::min(seg.a.x, seg.b.x), d_.origin_x) - 1);
      const int x1 = std::min(g - 1, cell_of(std::max(seg.a.x, seg.b.x), d_.origin_x) + 1);
      const int y0 = std::max(0, cell_of(std::min(seg.a.y, seg.b.y), d_.origin_y) - 1);
      const int y1 = std::min(g - 1, cell_of(std::max(seg.a.y, seg.b.y), d_.origin_y) + 1);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const Cell root{static_cast<std::uint32_t>(x) << resolution_, static_cast<std::uint32_t>(y) << resolution_,
                          0};
          if (segment_touches_box(seg.a, seg.b, box(root)))
            root_segments[static_cast<std::size_t>(y) * static_cast<std::size_t>(g) + static_cast<std::size_t>(x)]
                .push_back(static_cast<int>(s));
        }
    }
  }
  bool needs_split(const Cell& c, const double q[4], int tag) {
    if (c.level >= opt_.max_depth || tag == kTagOutside) return false;
    const double q_min = std::min(std::min(q[0], q[1]), std::min(q[2], q[3]));
    const double side = std::ldexp(d_.root_size, -c.level);
    if (side > opt_.size_factor * q_min) return true;
    if (side < (tag == kTagBoundary ? opt_.boundary_min_side_fraction : opt_.min_side_fraction) * q_min) return false;
    static constexpr int kTests[9][2] = {{2, 2}, {2, 0}, {2, 4}, {0, 2}, {4, 2}, {1, 1}, {3, 1}, {1, 3}, {3, 3}};
    const std::uint32_t quarter = span(c.level) / 4;
    for (const auto& t : kTests) {
      const double exact =
          sample(c.x + quarter * static_cast<std::uint32_t>(t[0]), c.y + quarter * static_cast<std::uint32_t>(t[1]));
      const double u = t[0] / 4.0, v = t[1] / 4.0;
      const double bilinear = (1.0 - v) * ((1.0 - u) * q[0] + u * q[1]) + v * ((1.0 - u) * q[2] + u * q[3]);
      if (std::fabs(bilinear - exact) > 0.5 * opt_.tolerance * exact) return true;
    }
    return false;
  }
  void build_cell(int node, const Cell& c, const std::vector<int>& segments) {
    const std::uint32_t s = span(c.level);
    const double q[4] = {sample(c.x, c.y), sample(c.x + s, c.y), sample(c.x, c.y + s), sample(c.x + s, c.y + s)};
    const Box b = box(c);
    int tag = kTagBoundary;
    if (segments.empty()) tag = tree_.inside(b.centre()) ? kTagInside : kTagOutside;
    d_.max_depth = std::max(d_.max_depth, c.level);
    if (!needs_split(c, q, tag)) {
      d_.node_child[static_cast<std::size_t>(node)] = -1 - static_cast<std::int32_t>(d_.leaf_tag.size());
      d_.leaf_tag.push_back(tag);
      const std::uint32_t below_root = (std::uint32_t{1} << resolution_) - 1;
      d_.leaf_cell.push_back(
          static_cast<std::int32_t>((c.y >> resolution_) * static_cast<std::uint32_t>(d_.grid) + (c.x >> resolution_)));
      d_.leaf_cell.push_back(c.level);
      d_.leaf_cell.push_back(static_cast<std::int32_t>((c.x & below_root) >> (resolution_ - c.level)));
      d_.leaf_cell.push_back(static_cast<std::int32_t>((c.y & below_root) >> (resolution_ - c.level)));
      for (const auto& [dx, dy] : {std::pair{0u, 0u}, {s, 0u}, {0u, s}, {s, s}})
        d_.leaf_corner.push_back(corner(c.x + dx, c.y + dy));
      return;
    }
    const int first = new_node();
    for (int k = 1; k < 4; ++k) new_node();
    d_.node_child[static_cast<std::size_t>(node)] = first;
    const std::uint32_t h = s / 2;
    const auto& segs = tree_.geometry().segments;
    std::vector<int> child_segments;
    for (int k = 0; k < 4; ++k) {
      const Cell child{c.x + (k & 1 ? h : 0u), c.y + (k & 2 ? h : 0u), c.level + 1};
      const Box cb = box(child);
      child_segments.clear();
      for (const int i : segments)
        if (segment_touches_box(segs[static_cast<std::size_t>(i)].a, segs[static_cast<std::size_t>(i)].b, cb))
          child_segments.push_back(i);
      build_cell(first + k, child, child_segments);
    }
  }

  const SpacingField& exact_;
  const GeometryTree& tree_;
  const BackgroundOptions& opt_;
  BackgroundFieldData& d_;
  const int resolution_;
  std::unordered_map<std::uint64_t, double> samples_;
  std::unordered_map<std::uint64_t, std::int32_t> corners_;
};

// Counts how the builder calls a field: per point (at) or in batches (at_many).
class CountingField final : public SpacingField {
 public:
  explicit CountingField(const SpacingField& inner) : inner_(inner) {}
  double at(Vec2 p) const override {
    ++at_calls;
    return inner_.at(p);
  }
  void at_many(const std::vector<Vec2>& p, std::vector<double>& q) const override {
    ++batches;
    points += p.size();
    largest = std::max(largest, p.size());
    inner_.at_many(p, q);
  }
  mutable std::size_t at_calls = 0, batches = 0, points = 0, largest = 0;

 private:
  const SpacingField& inner_;
};

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void check_identical(const BackgroundFieldData& a, const BackgroundFieldData& b) {
  CHECK(std::memcmp(&a.origin_x, &b.origin_x, sizeof(double)) == 0);
  CHECK(std::memcmp(&a.origin_y, &b.origin_y, sizeof(double)) == 0);
  CHECK(std::memcmp(&a.root_size, &b.root_size, sizeof(double)) == 0);
  CHECK(std::memcmp(&a.inv_root_size, &b.inv_root_size, sizeof(double)) == 0);
  CHECK(a.grid == b.grid);
  CHECK(a.max_depth == b.max_depth);
  CHECK(same_bits(a.root_node, b.root_node));
  CHECK(same_bits(a.node_child, b.node_child));
  CHECK(same_bits(a.leaf_corner, b.leaf_corner));
  CHECK(same_bits(a.leaf_tag, b.leaf_tag));
  CHECK(same_bits(a.leaf_cell, b.leaf_cell));
  CHECK(same_bits(a.corner_q, b.corner_q));
}

// The 30P30N airfoil of cases/30p30n in its own far field (the case's geometry files).
Geometry p30n() {
  auto raw = read_curve_file(PDMESH_SOURCE_DIR "/cases/30p30n/airfoil.crv");
  auto far = read_curve_file(PDMESH_SOURCE_DIR "/cases/30p30n/farfield.crv");
  raw.insert(raw.end(), far.begin(), far.end());
  return build_geometry(std::move(raw));
}

Geometry naca0012() {
  auto raw = read_curve_file(PDMESH_SOURCE_DIR "/cases/naca0012/airfoil.crv");
  auto far = read_curve_file(PDMESH_SOURCE_DIR "/cases/naca0012/farfield.crv");
  raw.insert(raw.end(), far.begin(), far.end());
  return build_geometry(std::move(raw));
}

// A field evaluated point by point on the calling thread: SpacingField's own at_many loop.
class SerialField final : public SpacingField {
 public:
  explicit SerialField(const SpacingField& inner) : inner_(inner) {}
  double at(Vec2 p) const override { return inner_.at(p); }

 private:
  const SpacingField& inner_;
};

Geometry circle_circle() {
  return build_geometry(read_curve_file(PDMESH_SOURCE_DIR "/cases/circle_circle/circles.crv"));
}

}  // namespace

TEST_CASE("background builder: batched build equals the recursive build bit for bit", "[spacing]") {
  const bool p30 = GENERATE(false, true);
  const Geometry g = p30 ? p30n() : circle_circle();
  const GeometryTree tree(g);
  const BoundarySpacing exact(tree);
  BackgroundOptions options;
  if (!p30) options.tolerance = 1e-3;  // deeper trees on the small case
  INFO((p30 ? "30p30n" : "circle_circle") << ", tolerance " << options.tolerance);

  BackgroundFieldData reference;
  RecursiveBuilder recursive(exact, tree, options, reference);
  recursive.build();

  const CountingField counting(exact);
  const BackgroundSpacing batched(counting, tree, options);
  check_identical(batched.data(), reference);

  // The exact field is only ever called in batches: the 81 grid samples, then at most three per level
  // (corners, the 5 test points that are the children's corners, the 4 quarter points) and never per point.
  const BackgroundStats& s = batched.stats();
  INFO("batches " << counting.batches << ", points " << counting.points << ", largest " << counting.largest
                  << ", depth " << s.max_depth);
  CHECK(counting.at_calls == 0);
  CHECK(counting.batches == s.exact_batches);
  CHECK(counting.batches <= 1 + 3 * static_cast<std::size_t>(s.max_depth + 1));
  // Every sample is evaluated once (81 grid samples are not cached), and batching evaluates hardly
  // more points than the per-point builder, whose tests stop at the first failing point.
  CHECK(counting.points == s.exact_evaluations + 81);
  CHECK(s.exact_evaluations >= recursive.evaluations());
  CHECK(static_cast<double>(s.exact_evaluations) <= 1.01 * static_cast<double>(recursive.evaluations()));
}

TEST_CASE("background builder: sample ids name the lattice points of the cells' corners", "[spacing]") {
  // Every cell keeps the sample ids of its corners (children take theirs from the parent's corners
  // and tested points), callers index their own arrays by them: each must be the sample at its point.
  const Geometry g = circle_circle();
  const GeometryTree tree(g);
  const BoundarySpacing boundary(tree);
  // Counts the points the builder evaluates.
  struct Counting : SpacingField {
    explicit Counting(const SpacingField& f) : f(f) {}
    double at(Vec2 p) const override {
      ++points;
      return f.at(p);
    }
    void at_many(const std::vector<Vec2>& p, std::vector<double>& q) const override {
      points += p.size();
      f.at_many(p, q);
    }
    const SpacingField& f;
    mutable std::size_t points = 0;
  } exact(boundary);
  BackgroundOptions options;
  options.tolerance = 1e-3;
  BackgroundBuilder b(exact, tree, options);
  b.build();
  // Mismatches are counted, not asserted one by one: hundreds of thousands of corners.
  auto bad_cells = [&] {
    std::size_t bad = 0;
    const auto& cells = b.cells();
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const BackgroundBuilder::Cell& c = cells[i];
      const std::uint32_t s = b.span(c.level);
      for (int k = 0; k < 4; ++k) {
        if (c.corner[k] < 0 || static_cast<std::size_t>(c.corner[k]) >= b.samples()) {
          ++bad;
          continue;
        }
        if (b.sample_value(c.corner[k]) != b.sample(c.x + (k & 1 ? s : 0u), c.y + (k & 2 ? s : 0u))) ++bad;
      }
      if (c.level == 0) {
        if (c.parent != -1) ++bad;
      } else if (c.parent < 0) {
        ++bad;
      } else {
        const auto first = static_cast<std::size_t>(cells[static_cast<std::size_t>(c.parent)].first_child);
        if (i < first || i >= first + 4) ++bad;
      }
    }
    return bad;
  };
  CHECK(bad_cells() == 0);
  // Every sample is one evaluation, none twice; besides them only choose_grid's 9 x 9 probe.
  CHECK(exact.points == b.samples() + 81);
  // A caller's refinement (every leaf split once more, the new cells not): the ids it is handed name
  // the keys' points.
  const std::size_t before = b.samples();
  const std::size_t old_cells = b.cells().size();
  std::size_t checked = 0, bad_ids = 0;
  const std::size_t splits = b.refine(
      b.leaves(),
      [&](const BackgroundBuilder::Cell& c, const double*) {
        const auto index = static_cast<std::size_t>(&c - b.cells().data());
        return index < old_cells && c.level < options.max_depth ? BackgroundBuilder::Decision::Split
                                                                : BackgroundBuilder::Decision::Leaf;
      },
      [](const BackgroundBuilder::Cell&, const double*, const double*, const std::int32_t*, int) { return false; },
      [&](const BackgroundBuilder::Cell&, std::uint32_t x, std::uint32_t y, std::int32_t id) {
        if (b.sample_value(id) != b.sample(x, y)) ++bad_ids;
        return b.sample_value(id);
      },
      [&](const std::vector<std::uint64_t>& keys, const std::vector<std::int32_t>& ids) {
        REQUIRE(keys.size() == ids.size());
        for (std::size_t i = 0; i < keys.size(); ++i) {
          if (b.sample_value(ids[i]) !=
              b.sample(static_cast<std::uint32_t>(keys[i] >> 32), static_cast<std::uint32_t>(keys[i] & 0xffffffffu)))
            ++bad_ids;
          ++checked;
        }
      });
  CHECK(splits > 0);
  CHECK(b.samples() > before);
  CHECK(checked > 0);
  CHECK(bad_ids == 0);
  CHECK(bad_cells() == 0);
}

TEST_CASE("background builder: an expression field is built in batches too", "[spacing]") {
  const Geometry g = build_geometry(read_curve_file(PDMESH_SOURCE_DIR "/cases/shock/square.crv"));
  const GeometryTree tree(g);
  const ExpressionSpacing exact("0.5 + 19.5*tanh(x/16)^2");
  BackgroundFieldData reference;
  BackgroundOptions options;
  RecursiveBuilder(exact, tree, options, reference).build();
  const CountingField counting(exact);
  const BackgroundSpacing batched(counting, tree, options);
  check_identical(batched.data(), reference);
  CHECK(counting.at_calls == 0);
  CHECK(counting.batches <= 1 + 3 * static_cast<std::size_t>(batched.stats().max_depth + 1));
}

TEST_CASE("BoundarySpacing::at_many equals at() point by point on large batches", "[spacing]") {
  const Geometry g = p30n();
  const GeometryTree tree(g);
  const BoundarySpacing exact(tree);
  // Sizes around the blocks of 64 points, the per-thread chunk and an odd prime; every 37th point on a
  // segment's end (distance 0: the boundary's limit of eq. 3.6).
  for (const std::size_t n :
       {std::size_t{1}, std::size_t{63}, std::size_t{65}, std::size_t{4095}, std::size_t{4097}, std::size_t{20011}}) {
    std::vector<Vec2> p(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double t = static_cast<double>(i) / static_cast<double>(n);
      p[i] = {-2.0 + 5.0 * t, -1.0 + 2.0 * std::sin(97.0 * t)};
      if (i % 37 == 5) p[i] = g.segments[(7 * i) % g.segments.size()].a;
    }
    std::vector<double> q;
    exact.at_many(p, q);
    REQUIRE(q.size() == n);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double one = exact.at(p[i]);
      if (std::memcmp(&q[i], &one, sizeof(double)) != 0) ++differ;
    }
    INFO("n = " << n);
    CHECK(differ == 0);
  }
}

TEST_CASE("spacing pipeline: threaded batches build the same field bit for bit as one thread", "[spacing]") {
  // The best preset's pipeline (feature size, curvature, gradation, the sources' floor) and the
  // thesis' (the base tree alone) on NACA 0012: BoundarySpacing::at_many splits its large batches
  // among threads and the sources run in parallel_for; the result must be the serial build's.
  const bool best = GENERATE(false, true);
  const Geometry g = naca0012();
  const GeometryTree tree(g);
  const BoundarySpacing threaded(tree);
  const SerialField serial(threaded);
  SpacingOptions options;
  if (best) {
    options.gradation = 0.2;
    options.rows_in_gap = 2.0;
    options.curvature_angle = 10.0;
    options.input_boundary_floor = kInputBoundaryFloor;
    options.final_floor = false;
  }
  INFO((best ? "best" : "thesis") << " preset's pipeline");
  const CountingField counting(threaded);
  const SpacingPipeline a(counting, tree, options);
  const SpacingPipeline b(serial, tree, options);
  check_identical(a.background().data(), b.background().data());
  // At least one batch was large enough to be split among two threads (where the machine has them).
  CHECK(counting.largest >= 2 * kPointsPerThread);
}

TEST_CASE("spacing pipeline: the builder's and the limited field's loops on one thread build the same field",
          "[spacing]") {
  // The best preset's pipeline on the 30P30N curves (large enough that every loop of the builder and
  // of the limited field splits its range among threads where the machine has two): the base field
  // evaluated serially and every loop capped at one thread (BackgroundOptions::threads), against the
  // default. The decisions of the base tree, the corner registration, the limit-refine rounds'
  // candidates and the node counts must not depend on the thread count.
  const Geometry g = p30n();
  const GeometryTree tree(g);
  const BoundarySpacing threaded(tree);
  const SerialField serial(threaded);
  SpacingOptions options;
  options.gradation = 0.2;
  options.rows_in_gap = 2.0;
  options.curvature_angle = 10.0;
  options.input_boundary_floor = kInputBoundaryFloor;
  options.final_floor = false;
  options.background.max_nodes = 1e7;  // the node counts of every level and round are taken
  SpacingOptions one = options;
  one.background.threads = 1;
  const SpacingPipeline a(threaded, tree, options);
  const SpacingPipeline b(serial, tree, one);
  check_identical(a.background().data(), b.background().data());
  CHECK(a.stats().rounds == b.stats().rounds);
  CHECK(a.stats().reduced_corners == b.stats().reduced_corners);
  CHECK(a.stats().rounds >= 2);  // the later rounds' path (corners known, relimit) is taken
}
