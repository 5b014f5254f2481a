// The device neighbour build (opencl/device_neighbours, kernels/neighbours.cl) on its own: compact rows
// (CSR) whose every row equals the brute-force reference row slot by slot (interior rows ascending,
// boundary rows [prev, next]), whatever capacities the last build left: a first (counting) build, a
// build from the last counts, rows that outgrow their capacities and are gathered again, and one very
// crowded node, which a padded layout would multiply by the node count. The buffers of the test
// context carry canary tails, so a write past any row buffer fails the download.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "opencl/device_neighbours.hpp"
#include "opencl/neighbour_grids.hpp"
#include "sim/reference/reference_backend.hpp"
#include "step_backend_inputs.hpp"

using namespace pdmesh;
using namespace pdmesh::test;

namespace {

struct DeviceRows {
  std::vector<std::int32_t> count, index, level;
  std::vector<std::uint8_t> skin_class;
  double spacing_ratio = 0.0;
  std::vector<std::uint64_t> offset;
  NeighbourFlags flags;
  int attempts = 0;
  bool sampled = false;
  std::uint64_t outgrown_rows = 0;
  std::size_t index_size = 0;
};

// One DeviceNeighbours<double> across builds (its capacities come from the last build).
class DeviceBuilder {
 public:
  DeviceBuilder() : DeviceBuilder(test_program(ocl::Precision::Double)) {}
  explicit DeviceBuilder(ocl::StepProgram& program) : ctx_(test_context()), nb_(ctx_, program) {}

  ocl::DeviceNeighbours<double>& neighbours() { return nb_; }

  DeviceRows build(const SimParticles& p, double cutoff, double pair_skin = 0.0) {
    const std::size_t n = p.size();
    ocl::Buffer<double> xy(ctx_, "xy", 2 * n), q(ctx_, "q", n);
    ocl::Buffer<std::uint8_t> kind(ctx_, "kind", n);
    ocl::Buffer<std::int32_t> prev(ctx_, "prev", n), next(ctx_, "next", n);
    std::vector<double> packed(2 * n);  // the kernels' layout: x, y interleaved
    for (std::size_t i = 0; i < n; ++i) packed[2 * i] = p.x[i], packed[2 * i + 1] = p.y[i];
    xy.upload(ctx_.queue(), packed);
    q.upload(ctx_.queue(), p.q);
    kind.upload(ctx_.queue(), p.kind);
    prev.upload(ctx_.queue(), p.prev);
    next.upload(ctx_.queue(), p.next);
    DeviceRows out;
    out.flags = nb_.build(n, cutoff, xy, q, kind, prev, next, pair_skin);
    out.spacing_ratio = nb_.spacing_ratio;
    nb_.level().download(ctx_.queue(), out.level, n);
    nb_.skin_class().download(ctx_.queue(), out.skin_class, n);
    out.attempts = nb_.attempts;
    out.outgrown_rows = nb_.outgrown_rows;
    out.sampled = nb_.sampled;
    nb_.offset().download(ctx_.queue(), out.offset, n + 1);
    nb_.count().download(ctx_.queue(), out.count, n);
    nb_.index().download(ctx_.queue(), out.index);
    out.index_size = nb_.index().size();
    return out;
  }

 private:
  ocl::Context& ctx_;
  ocl::DeviceNeighbours<double> nb_;
};

// The reference rows, never truncated (a stride above every count).
NeighbourList reference_rows(const Input& in, NeighbourFlags& flags) {
  NeighbourList oracle;
  oracle.stride = static_cast<int>(in.p.size()) + 2;
  reference::build_neighbours_brute_force(in.p, in.cutoff, oracle, flags);
  REQUIRE(flags.overflow == 0U);
  return oracle;
}

void check_rows(const Input& in, const DeviceRows& got) {
  INFO("input " << in.name << ", " << in.p.size() << " nodes");
  const std::size_t n = in.p.size();
  NeighbourFlags oflags;
  const NeighbourList oracle = reference_rows(in, oflags);
  REQUIRE(got.flags.overflow == 0U);
  REQUIRE(got.flags.max_count == oflags.max_count);
  REQUIRE(got.flags.pairs_within == oflags.pairs_within);
  REQUIRE(got.count == oracle.count);
  REQUIRE(got.offset.size() == n + 1);
  // The vector force loop reads whole chunks of 8 past a row's start: they must be inside the buffer.
  CHECK(got.offset[n] + ocl::kRowTail <= got.index_size);
  const auto s = static_cast<std::size_t>(oracle.stride);
  for (std::size_t i = 0; i < n; ++i) {
    INFO("node " << i);
    // A row inside its slot, or moved behind the last row (relocate_rows); the force loop's chunks too.
    REQUIRE((got.offset[i] + static_cast<std::uint64_t>(got.count[i]) <= got.offset[i + 1] ||
             got.offset[i] >= got.offset[n]));
    REQUIRE(got.offset[i] + static_cast<std::uint64_t>(got.count[i]) + ocl::kRowTail <= got.index_size);
    for (std::size_t k = 0; k < static_cast<std::size_t>(got.count[i]); ++k) {
      INFO("slot " << k);
      REQUIRE(got.index[got.offset[i] + k] == oracle.index[i * s + k]);
    }
  }
}

// The reference rows' entries (what exact capacities would hold).
std::uint64_t total_entries(const Input& in) {
  NeighbourFlags flags;
  const NeighbourList oracle = reference_rows(in, flags);
  std::uint64_t total = 0;
  for (auto c : oracle.count) total += static_cast<std::uint64_t>(c);
  return total;
}

}  // namespace

TEST_CASE("device neighbour rows equal the reference rows in order at awkward sizes", "[opencl][neighbour]") {
  const std::size_t wg = ocl::kStepWorkGroup;
  for (std::size_t n : {std::size_t{0}, std::size_t{1}, wg - 1, wg, wg + 1, std::size_t{131}, 3 * wg + 5}) {
    const Input in = random_input(n, 77 + n, false);
    DeviceBuilder b;
    check_rows(in, b.build(in.p, in.cutoff));
  }
  for (const Input& in : {graded_input(false), lattice_input(), dense_cluster_input(false)}) {
    DeviceBuilder b;
    check_rows(in, b.build(in.p, in.cutoff));
  }
}

// The GPU-shaped program (ForceLoop::Scalar) bins and gathers with floor() and the cell test everywhere
// (kernels/binning.cl, neighbours.cl): the same rows.
TEST_CASE("device neighbour rows of the GPU-shaped program equal the reference", "[opencl][neighbour]") {
  ocl::StepProgram scalar(test_context(), ocl::Precision::Double, ocl::ForceLoop::Scalar);
  for (const Input& in : {random_input(3 * ocl::kStepWorkGroup + 5, 80, false), graded_input(false), lattice_input()}) {
    DeviceBuilder b(scalar);
    check_rows(in, b.build(in.p, in.cutoff));
  }
}

// Grids of 256 buckets and more (the gather skips most cell tests there, kernels/neighbours.cl,
// tags_apart), their 4 x 4 blocks of cells on both sides of both axes: rows equal the reference's.
TEST_CASE("device rows from larger grids around the origin equal the reference", "[opencl][neighbour]") {
  Input in = random_input(600, 31, false);
  in.name = "random 600 around the origin";
  const double side = std::sqrt(601.0) * 0.08;
  for (std::size_t i = 0; i < in.p.size(); ++i) {
    in.p.x[i] -= 0.5 * side;
    in.p.y[i] -= 0.5 * side;
  }
  DeviceBuilder b;
  check_rows(in, b.build(in.p, in.cutoff));
}

// The gather skips the cell test for candidates well inside a search box of at most 5 x 5 cells
// (kernels/neighbours.cl, tags_apart) because two cells of such a box sharing a bucket are (4a, 4b)
// apart, a, b in {-1, 0, 1}, and nb_tag's top bits then always differ: t' = t + 4a M + 4b N, so the top
// 4 bits of 4a M + 4b N must be neither 0 nor 15 (no carry can bring them back). The kernel's
// constants, checked here; and two such cells' tags, sampled.
TEST_CASE("cells of one search box sharing a bucket never share a tag", "[opencl][neighbour]") {
  constexpr std::uint64_t kM = 0xD6E8FEB86659FD93ULL, kN = 0xA0761D6478BD642FULL;  // binning.cl, nb_tag
  auto tag = [&](std::int64_t cx, std::int64_t cy) {
    return (static_cast<std::uint64_t>(cx) * kM + static_cast<std::uint64_t>(cy) * kN) >> (32 + ocl::kGridNodeBits);
  };
  for (std::int64_t a = -1; a <= 1; ++a)
    for (std::int64_t b = -1; b <= 1; ++b) {
      if (a == 0 && b == 0) continue;
      const std::uint64_t k = static_cast<std::uint64_t>(4 * a) * kM + static_cast<std::uint64_t>(4 * b) * kN;
      INFO("offset (" << 4 * a << ", " << 4 * b << ")");
      CHECK((k >> 60) != 0);
      CHECK((k >> 60) != 15);
      for (std::int64_t cx : {std::int64_t{-9}, std::int64_t{0}, std::int64_t{3}, std::int64_t{1} << 40})
        for (std::int64_t cy : {std::int64_t{-5}, std::int64_t{0}, std::int64_t{77}, -(std::int64_t{1} << 33)}) {
          CHECK(ocl::grid_bucket(cx, cy, 15) == ocl::grid_bucket(cx + 4 * a, cy + 4 * b, 15));
          CHECK(tag(cx, cy) != tag(cx + 4 * a, cy + 4 * b));
        }
    }
}

// The device's grids as the gather reads them: each node's level, and per grid its hash mask, bucket
// offset and inverse cell size; the buckets' ends and their entries.
void download_grids(ocl::DeviceNeighbours<double>& nb, std::size_t n, std::vector<std::int32_t>& level,
                    std::vector<std::int32_t>& mask, std::vector<std::uint32_t>& bucket_offset,
                    std::vector<double>& inv_cell, std::vector<std::uint32_t>& bucket,
                    std::vector<std::int32_t>& nodes) {
  ocl::Context& ctx = test_context();
  nb.level().download(ctx.queue(), level, n);
  nb.grid_mask().download(ctx.queue(), mask);
  nb.grid_bucket_offset().download(ctx.queue(), bucket_offset);
  nb.grid_inv_cell().download(ctx.queue(), inv_cell);
  nb.bucket().download(ctx.queue(), bucket);
  nb.grid_nodes().download(ctx.queue(), nodes);
}

// What the gather's scan meets (kernels/neighbours.cl, gather_node), computed on the host from the
// device's grids: `examined`, the candidates of a scan per probed cell (entries of the cell's bucket with
// the cell's tag, other than the node), which both program shapes must count; and, for the CPU shape's
// scan by ranges (the probed cells of one row of a box inside one 4 x 4 block, consecutive buckets),
// how often a test input meets its cases: ranges of several cells, box rows split into two ranges at a
// block's edge, entries of another cell in a range's bucket (hash collisions), and among them those
// carrying the tag of another cell of the same range (a test against any of the range's tags would take
// them).
struct ScanCounts {
  std::uint64_t examined = 0, multi_cell_ranges = 0, split_rows = 0, collisions = 0, foreign_tags = 0;
};

ScanCounts host_scan(const Input& in, ocl::DeviceNeighbours<double>& nb, double radius_factor) {
  const std::size_t n = in.p.size();
  std::vector<std::int32_t> level, mask, nodes;
  std::vector<std::uint32_t> bucket_offset, bucket;
  std::vector<double> inv_cell;
  download_grids(nb, n, level, mask, bucket_offset, inv_cell, bucket, nodes);
  auto tag = [](std::int64_t cx, std::int64_t cy) {  // binning.cl, nb_tag
    return static_cast<std::uint32_t>((static_cast<std::uint64_t>(cx) * 0xD6E8FEB86659FD93ULL +
                                       static_cast<std::uint64_t>(cy) * 0xA0761D6478BD642FULL) >>
                                      (32 + ocl::kGridNodeBits));
  };
  const std::uint32_t node_mask = (1U << ocl::kGridNodeBits) - 1U;
  ScanCounts counts;
  for (std::size_t i = 0; i < n; ++i) {
    const auto own = static_cast<std::size_t>(level[i]);
    const double ic = inv_cell[own], cell = 1.0 / ic, xi = in.p.x[i], yi = in.p.y[i];
    const double r = radius_factor * in.p.q[i], r2 = r * r;
    const double slack = (std::fabs(xi) + std::fabs(yi) + r + cell) * 1e-12;  // the kernel's, in double
    auto coord = [&](double v) { return static_cast<std::int64_t>(std::floor(v * ic)); };
    const std::int64_t x0 = coord(xi - r), x1 = coord(xi + r), y0 = coord(yi - r), y1 = coord(yi + r);
    const auto m = static_cast<std::uint64_t>(static_cast<std::uint32_t>(mask[own]));
    const bool ranged = x1 - x0 <= 4 && y1 - y0 <= 4 && m >= 15;
    auto bucket_of = [&](std::int64_t cx, std::int64_t cy) {
      return bucket_offset[own] + static_cast<std::uint32_t>(ocl::grid_bucket(cx, cy, m));
    };
    for (std::int64_t cy = y0; cy <= y1; ++cy) {
      const double gy =
          std::max(std::max(static_cast<double>(cy) * cell - yi, yi - static_cast<double>(cy + 1) * cell) - slack, 0.0);
      std::vector<std::vector<std::int64_t>> ranges;  // the row's probed cells, by range
      for (std::int64_t cx = x0; cx <= x1; ++cx) {
        const double gx = std::max(
            std::max(static_cast<double>(cx) * cell - xi, xi - static_cast<double>(cx + 1) * cell) - slack, 0.0);
        if (gx * gx + gy * gy > r2) continue;
        const std::uint32_t b = bucket_of(cx, cy);
        for (std::uint32_t k = b > 0 ? bucket[b - 1] : 0; k < bucket[b]; ++k) {
          const auto e = static_cast<std::uint32_t>(nodes[k]);
          if ((e >> ocl::kGridNodeBits) == tag(cx, cy) && (e & node_mask) != i) ++counts.examined;
        }
        const bool joins = ranged && !ranges.empty() && ranges.back().back() == cx - 1 && (cx & 3) != 0;
        if (joins)
          ranges.back().push_back(cx);
        else
          ranges.push_back({cx});
      }
      if (ranged && ranges.size() > 1) ++counts.split_rows;
      for (const auto& cells : ranges) {
        if (cells.size() < 2) continue;
        ++counts.multi_cell_ranges;
        for (std::int64_t cx : cells) {
          const std::uint32_t b = bucket_of(cx, cy);
          for (std::uint32_t k = b > 0 ? bucket[b - 1] : 0; k < bucket[b]; ++k) {
            const auto j = static_cast<std::size_t>(static_cast<std::uint32_t>(nodes[k]) & node_mask);
            const std::int64_t jx = coord(in.p.x[j]), jy = coord(in.p.y[j]);
            if (jx == cx && jy == cy) continue;
            ++counts.collisions;
            for (std::int64_t other : cells)
              if (other != cx && tag(jx, jy) == tag(other, cy)) ++counts.foreign_tags;
          }
        }
      }
    }
  }
  return counts;
}

// One grid level of 16 buckets (every 4 x 4 block's cells share them, so every bucket holds other
// blocks' cells) over ~12 x 12 cells, and larger grids: the rows of both program shapes equal the
// reference, both count the candidates of a scan per probed cell, and the inputs meet the CPU shape's
// scan by ranges in every case above.
TEST_CASE("device rows scanned by ranges of cells equal the reference and examine the candidates of each cell",
          "[opencl][neighbour]") {
  std::vector<Input> inputs;
  for (std::uint64_t seed : {3U, 4U, 5U}) {
    Input in{"one level of 16 buckets, seed " + std::to_string(seed), {}, 1.5};
    std::mt19937_64 rng(seed);
    for (int k = 0; k < 30; ++k)  // q 0.06 .. 0.119: one level, cells of 0.09, boxes of 3 to 5 cells
      pdmesh_test::add(in.p, 1.1 * uniform(rng) - 0.3, 1.1 * uniform(rng) - 0.3, 0.06 + 0.059 * uniform(rng));
    inputs.push_back(in);
  }
  inputs.push_back(random_input(600, 31, false));
  inputs.push_back(graded_input(false));
  inputs.push_back(lattice_input());  // nodes on cell edges, pairs on the cut-off: the cell test decides
  ocl::StepProgram scalar(test_context(), ocl::Precision::Double, ocl::ForceLoop::Scalar);
  ScanCounts seen;
  for (const Input& in : inputs) {
    for (ocl::StepProgram* program : {&test_program(ocl::Precision::Double), &scalar}) {
      INFO("input " << in.name << ", force loop " << (program == &scalar ? "scalar" : "vector"));
      DeviceBuilder b(*program);
      b.build(in.p, in.cutoff);
      const DeviceRows got = b.build(in.p, in.cutoff);  // from the first build's counts: one gather
      check_rows(in, got);
      const ScanCounts counts = host_scan(in, b.neighbours(), in.cutoff);
      CHECK(got.flags.pairs_examined == counts.examined);
      if (program == &scalar) continue;
      seen.multi_cell_ranges += counts.multi_cell_ranges;
      seen.split_rows += counts.split_rows;
      seen.collisions += counts.collisions;
      seen.foreign_tags += counts.foreign_tags;
    }
  }
  INFO("ranges of 2-4 cells " << seen.multi_cell_ranges << ", rows split at a block's edge " << seen.split_rows
                              << ", other cells' entries in ranges " << seen.collisions << ", of them with another "
                              << "cell's tag of the range " << seen.foreign_tags);
  CHECK(seen.multi_cell_ranges > 0);
  CHECK(seen.split_rows > 0);
  CHECK(seen.collisions > 0);
  CHECK(seen.foreign_tags > 0);
}

TEST_CASE("device neighbour rows with coincident nodes equal the reference", "[opencl][neighbour]") {
  Input in = coincident_input(false);
  // And a stack of 5 nodes at one point: each sees the 4 others at distance 0.
  for (int k = 0; k < 5; ++k) pdmesh_test::add(in.p, 0.25, 0.25, 0.1);
  DeviceBuilder b;
  check_rows(in, b.build(in.p, in.cutoff));
}

// A first build knows no counts: a counting pass (every row outgrows its capacity of kSpareMin), then the
// gather with the exact counts (before that, grids larger than the first guess run the binning again); a second
// build of the same nodes fits the first's capacities; rows that outgrow them (nodes moved together)
// move behind the others in the same pass, or, when too many spill, are gathered again. Every
// build's rows equal the reference.
TEST_CASE("device rows that outgrow their capacities are gathered again and equal the reference",
          "[opencl][neighbour]") {
  for (const Input& in : {crowded_input(false), graded_input(false)}) {
    DeviceBuilder b;
    const DeviceRows first = b.build(in.p, in.cutoff);
    check_rows(in, first);
    CHECK(first.outgrown_rows > 0);  // capacities of kSpareMin: the counting pass, then the gather
    CHECK(first.attempts >= 2);
    const DeviceRows again = b.build(in.p, in.cutoff);
    check_rows(in, again);
    CHECK(again.attempts == 1);
    CHECK(again.outgrown_rows == 0);
    CHECK(b.build(in.p, in.cutoff).offset == again.offset);  // capacities from the same counts
    // Shrink the cloud 100-fold towards node 0: rows grow past count + count/8 + kSpareMin.
    Input moved = in;
    for (std::size_t i = 0; i < moved.p.size(); ++i) {
      moved.p.x[i] = in.p.x[0] + 0.01 * (moved.p.x[i] - in.p.x[0]);
      moved.p.y[i] = in.p.y[0] + 0.01 * (moved.p.y[i] - in.p.y[0]);
    }
    const DeviceRows grown = b.build(moved.p, moved.cutoff);
    check_rows(moved, grown);
    CHECK(grown.outgrown_rows > 0);
    // crowded: a few rows spill a few entries: they move behind the others in the same pass; graded:
    // every row outgrows, the spill list overflows, and the build runs again.
    CHECK(grown.attempts == (in.name == "crowded" ? 1 : 2));
    const DeviceRows settled = b.build(moved.p, moved.cutoff);
    check_rows(moved, settled);
    CHECK(settled.outgrown_rows == 0);
    // And a node set of another size starts from zero counts again.
    Input fewer = in;
    for (auto* v : {&fewer.p.x, &fewer.p.y, &fewer.p.q, &fewer.p.tx, &fewer.p.ty}) v->resize(v->size() - 3);
    for (auto* v : {&fewer.p.prev, &fewer.p.next}) v->resize(v->size() - 3);
    fewer.p.kind.resize(fewer.p.kind.size() - 3);
    check_rows(fewer, b.build(fewer.p, fewer.cutoff));
  }
}

// A device run frees what only a build reads between its builds (release_build_scratch): the rows
// the step reads stay whole, and the next build bins again into grids made at the capacities the
// last one found, with the same rows and layout.
TEST_CASE("device rows built after the build's scratch was freed equal the reference", "[opencl][neighbour]") {
  for (const Input& in : {crowded_input(false), graded_input(false)}) {
    DeviceBuilder b;
    const DeviceRows first = b.build(in.p, in.cutoff);
    check_rows(in, first);
    const DeviceRows settled = b.build(in.p, in.cutoff);
    ocl::DeviceNeighbours<double>& nb = b.neighbours();
    nb.release_build_scratch();
    CHECK(nb.grid_nodes().size() == 0);
    CHECK(nb.bucket().size() == 0);
    CHECK(nb.level().size() == 0);
    // The rows stay: what the step reads after the build.
    CHECK(nb.index().size() == settled.index_size);
    CHECK(nb.count().size() >= in.p.size());
    const DeviceRows again = b.build(in.p, in.cutoff);
    check_rows(in, again);
    CHECK(again.offset == settled.offset);
    CHECK(again.level == settled.level);
    CHECK(again.attempts == 1);
    CHECK(nb.grid_nodes().size() > 0);
    // Moved nodes after another release: the grids are made again for their positions.
    Input moved = in;
    for (std::size_t i = 0; i < moved.p.size(); ++i) {
      moved.p.x[i] = in.p.x[0] + 0.5 * (moved.p.x[i] - in.p.x[0]);
      moved.p.y[i] = in.p.y[0] + 0.5 * (moved.p.y[i] - in.p.y[0]);
    }
    nb.release_build_scratch();
    check_rows(moved, b.build(moved.p, moved.cutoff));
  }
}

// A build without counts from kSampleFrom nodes on lays its rows out from a sample (every stride-th
// node's scan counted, one capacity per grid level); forced here on small inputs. The rows above
// their level's estimate move behind the others in the same pass (random inputs: counts spread
// around the mean), or, where the estimate is far off (crowded: a row of 39 in a level of rows of
// 0), when the move list or the spare region overflows, the build runs again with the exact counts.
// Either way the rows equal the reference slot by slot, and the next build uses the counts.
TEST_CASE("device rows laid out from a sampled estimate move the outgrown rows and equal the reference",
          "[opencl][neighbour]") {
  REQUIRE(ocl::DeviceNeighbours<double>::kSampleStride > 1);
  for (const int stride : {4, 16}) {
    for (const Input& in : {random_input(600, 41, false), random_input(3 * ocl::kStepWorkGroup + 5, 43, false),
                            graded_input(false), crowded_input(false), dense_cluster_input(false), lattice_input()}) {
      INFO("stride " << stride << ", input " << in.name);
      DeviceBuilder b;
      b.neighbours().sample_stride = stride;
      const DeviceRows first = b.build(in.p, in.cutoff);
      check_rows(in, first);
      CHECK(first.sampled);
      CHECK(first.attempts <= 2);
      if (in.name.rfind("random", 0) == 0) {
        CHECK(first.outgrown_rows > 0);  // rows above their level's mean: moved in the same pass
        CHECK(first.attempts == 1);
      }
      const DeviceRows again = b.build(in.p, in.cutoff);  // from the counts: nothing outgrows
      check_rows(in, again);
      CHECK_FALSE(again.sampled);
      CHECK(again.attempts == 1);
      CHECK(again.outgrown_rows == 0);
    }
  }
  // Stride 1: the exact counting pass (no estimate), then the rows at their counts.
  const Input in = random_input(600, 41, false);
  DeviceBuilder b;
  b.neighbours().sample_stride = 1;
  const DeviceRows exact = b.build(in.p, in.cutoff);
  check_rows(in, exact);
  CHECK_FALSE(exact.sampled);
  CHECK(exact.attempts == 2);
}

// A build from the last counts whose grids no longer fit (two nodes' spacing raised tenfold: new
// coarse levels, each a cumulative grid of every node) bins again at the grids' size and gathers
// once more with those counts, not from zero counts: only the two grown rows outgrow and move. From
// zero counts every row would outgrow, the spill list overflow, and a third gather follow (annulus_1m
// after a population event: 1,045,372 rows outgrown, 32 million entries spilled).
TEST_CASE("a build whose grids no longer fit keeps the last counts", "[opencl][neighbour]") {
  Input in = random_input(2000, 53, false);
  DeviceBuilder b;
  b.build(in.p, in.cutoff);
  REQUIRE(b.build(in.p, in.cutoff).attempts == 1);
  for (const std::size_t i : {100u, 1500u}) {
    in.p.kind[i] = kSimInterior;
    in.p.q[i] *= 10.0;
  }
  const DeviceRows grown = b.build(in.p, in.cutoff);
  check_rows(in, grown);
  CHECK(grown.outgrown_rows == 2);
  CHECK(grown.attempts == 2);  // the pass whose grids were too small, then the gather
}

// One node whose radius covers every other node: its row holds them all, every other row a few. Rows
// of one stride would take n x (n - 1) entries; the compact rows take about the total.
TEST_CASE("one very crowded row costs its own entries, not a stride for every node", "[opencl][neighbour]") {
  Input in = random_input(600, 31, false);
  in.p.q[17] = 100.0;  // radius 150 around a ~2 x 2 cloud
  DeviceBuilder b;
  b.build(in.p, in.cutoff);
  const DeviceRows rows = b.build(in.p, in.cutoff);
  check_rows(in, rows);
  REQUIRE(rows.count[17] == 599);
  const std::uint64_t total = total_entries(in);
  // The rows with their slack, and the spare region for moved rows (2 max(4096, total / 64)).
  const std::uint64_t bound = total + (total >> ocl::DeviceNeighbours<double>::kSpareShift) +
                              static_cast<std::uint64_t>(ocl::DeviceNeighbours<double>::kSpareMin) * in.p.size() +
                              2 * std::max<std::uint64_t>(4096, total / 64) + ocl::kRowTail;
  CHECK(rows.offset.back() <= bound);
  CHECK(rows.index_size <= bound);
  CHECK(rows.index_size < in.p.size() * 599 / 10);
}

// The device's binning (kernels/binning.cl) against the host's (neighbour_grids.cpp, the reference's
// grids in flat arrays): the same level per node and cell size per level, and every cumulative grid
// holds the same nodes, each in the bucket of its own cell (order within a bucket is free).
TEST_CASE("device binning puts every node in the cells the host binning does", "[opencl][neighbour]") {
  for (const Input& in : {graded_input(false), random_input(3 * ocl::kStepWorkGroup + 5, 9, false), lattice_input()}) {
    INFO("input " << in.name);
    DeviceBuilder b;
    b.build(in.p, in.cutoff);
    const std::size_t n = in.p.size();
    ocl::NeighbourGrids host;
    ocl::build_neighbour_grids(in.p.x.data(), in.p.y.data(), in.p.q.data(), n, in.cutoff, host);
    ocl::DeviceNeighbours<double>& nb = b.neighbours();
    std::vector<std::int32_t> level, mask, nodes;
    std::vector<std::uint32_t> bucket_offset, bucket;
    std::vector<double> inv_cell;
    download_grids(nb, n, level, mask, bucket_offset, inv_cell, bucket, nodes);
    REQUIRE(level == host.level);
    int grids = 0;
    for (int L = 0; L < host.levels; ++L) {
      INFO("level " << L);
      const auto g = static_cast<std::size_t>(2 * L);  // the host's cumulative grid C_L
      const bool has_nodes = std::count(host.level.begin(), host.level.end(), L) > 0;
      REQUIRE((mask[static_cast<std::size_t>(L)] >= 0) == has_nodes);
      if (!has_nodes) continue;
      ++grids;
      CHECK(inv_cell[static_cast<std::size_t>(L)] == host.inv_cell[g]);
      // Host: every cell's nodes, by cell coordinates.
      std::map<std::pair<std::int64_t, std::int64_t>, std::vector<std::int32_t>> host_cells, device_cells;
      const auto start = static_cast<std::size_t>(host.start_offset[g]);
      const auto base = static_cast<std::size_t>(host.nodes_offset[g]);
      const auto cap = static_cast<std::size_t>(host.table_mask[g]) + 1;
      for (std::size_t s = 0; s < cap; ++s) {
        const std::int32_t id = host.table_id[static_cast<std::size_t>(host.table_offset[g]) + s];
        if (id < 0) continue;
        const auto cell = std::pair{host.table_cx[static_cast<std::size_t>(host.table_offset[g]) + s],
                                    host.table_cy[static_cast<std::size_t>(host.table_offset[g]) + s]};
        for (auto k = host.cell_start[start + static_cast<std::size_t>(id)];
             k < host.cell_start[start + static_cast<std::size_t>(id) + 1]; ++k)
          host_cells[cell].push_back(host.cell_nodes[base + static_cast<std::size_t>(k)]);
      }
      // Device: every bucket of grid L; each node must sit in the bucket of its cell (its block's hash).
      const std::uint32_t first = bucket_offset[static_cast<std::size_t>(L)];
      const auto buckets = static_cast<std::uint32_t>(mask[static_cast<std::size_t>(L)]) + 1;
      for (std::uint32_t k = 0; k < buckets; ++k) {
        const std::uint32_t bi = first + k;
        for (std::uint32_t e = bi > 0 ? bucket[bi - 1] : 0; e < bucket[bi]; ++e) {
          const auto j =
              static_cast<std::int32_t>(static_cast<std::uint32_t>(nodes[e]) & ((1U << ocl::kGridNodeBits) - 1U));
          const double ic = inv_cell[static_cast<std::size_t>(L)];
          const auto cell = std::pair{static_cast<std::int64_t>(std::floor(in.p.x[static_cast<std::size_t>(j)] * ic)),
                                      static_cast<std::int64_t>(std::floor(in.p.y[static_cast<std::size_t>(j)] * ic))};
          CHECK(ocl::grid_bucket(cell.first, cell.second, buckets - 1) == k);
          // The entry's tag (kernels/binning.cl, nb_tag): the top bits of a second hash of its cell.
          const std::uint64_t t = static_cast<std::uint64_t>(cell.first) * 0xD6E8FEB86659FD93ULL +
                                  static_cast<std::uint64_t>(cell.second) * 0xA0761D6478BD642FULL;
          CHECK((static_cast<std::uint32_t>(nodes[e]) >> ocl::kGridNodeBits) == (t >> (32 + ocl::kGridNodeBits)));
          device_cells[cell].push_back(j);
        }
      }
      for (auto& [cell, v] : device_cells) std::sort(v.begin(), v.end());
      CHECK(device_cells == host_cells);
    }
    CHECK(grids > 0);
  }
}

// Both program shapes (bin_bounds has a CPU shape of its own): the first invalid node within a
// work-group and across work-groups (kStepWorkGroup = 64: nodes 150 and 170 share one, 40 another).
TEST_CASE("a device build names the first invalid node and builds no rows", "[opencl][neighbour]") {
  ocl::StepProgram scalar(test_context(), ocl::Precision::Double, ocl::ForceLoop::Scalar);
  for (ocl::StepProgram* program : {&test_program(ocl::Precision::Double), &scalar}) {
    INFO("force loop " << (program == &scalar ? "scalar" : "default"));
    Input in = random_input(200, 3, false);
    in.p.q[150] = -1.0;
    in.p.x[170] = std::numeric_limits<double>::quiet_NaN();
    DeviceBuilder b(*program);
    CHECK(b.build(in.p, in.cutoff).flags.first_invalid == 150);
    in.p.q[150] = 0.1;
    CHECK(b.build(in.p, in.cutoff).flags.first_invalid == 170);
    in.p.y[40] = std::numeric_limits<double>::infinity();
    CHECK(b.build(in.p, in.cutoff).flags.first_invalid == 40);
    in.p.y[40] = 0.5;
    in.p.x[170] = 0.5;
    check_rows(in, b.build(in.p, in.cutoff));
  }
}

// Radii spanning more than 2^kBinLevels need more grid levels than the binning has: the build says so
// (bin_levels' flag, both shapes) instead of binning into a wrong level.
TEST_CASE("a device build whose radii span more than its grid levels throws", "[opencl][neighbour]") {
  ocl::StepProgram scalar(test_context(), ocl::Precision::Double, ocl::ForceLoop::Scalar);
  for (ocl::StepProgram* program : {&test_program(ocl::Precision::Double), &scalar}) {
    INFO("force loop " << (program == &scalar ? "scalar" : "default"));
    Input in = random_input(200, 5, false);
    in.p.q[130] = std::ldexp(in.p.q[130], -(ocl::kBinLevels + 2));
    DeviceBuilder b(*program);
    CHECK_THROWS_AS(b.build(in.p, in.cutoff), SimulationError);
  }
}

// The device run's lists (pair_skin = s c > 0): row i of an interior node holds every j within
// c (1 + s) q_i and, of a coarser grid level, within c q_i + s c q_j (kernels/neighbours.cl); each node's
// skin class is ceil(16 log2 rho) (+1 at most: the kernel's margin) of its largest ratio q_m / q_j over
// the interior j of its own level within c (1 + s) q_m, never below it (host/opencl/device_run.hpp
// rests on it). Brute force over every pair, with the device's grid levels.
TEST_CASE(
    "device rows of the run take coarser neighbours within c q_i + s c q_j, and skin classes bound the "
    "spacing ratios of a level",
    "[opencl][neighbour]") {
  // Both programs: the GPU-shaped one gathers with floor() and the cell test everywhere.
  ocl::StepProgram scalar(test_context(), ocl::Precision::Double, ocl::ForceLoop::Scalar);
  const std::vector<Input> inputs{graded_input(false), random_input(3 * ocl::kStepWorkGroup + 5, 91, false),
                                  dense_cluster_input(false)};
  for (std::size_t run = 0; run < 2 * inputs.size(); ++run) {
    ocl::StepProgram* program = run < inputs.size() ? &test_program(ocl::Precision::Double) : &scalar;
    const Input& in = inputs[run % inputs.size()];
    INFO("input " << in.name << ", force loop " << (program == &scalar ? "scalar" : "vector"));
    const double skin = 0.3, c = in.cutoff, radius = c * (1.0 + skin), pair_skin = skin * c;
    DeviceBuilder b(*program);
    const DeviceRows got = b.build(in.p, radius, pair_skin);
    const SimParticles& p = in.p;
    const std::size_t n = p.size();
    REQUIRE(got.level.size() == n);
    double largest = 0.0;
    std::uint64_t widened = 0;
    for (std::size_t i = 0; i < n; ++i) {
      INFO("node " << i);
      std::vector<std::int32_t> row;
      double rho = 1.0, ratio = 0.0;
      for (std::size_t j = 0; j < n; ++j) {
        if (j == i) continue;
        const double dx = p.x[j] - p.x[i], dy = p.y[j] - p.y[i], d2 = dx * dx + dy * dy;
        const double own = radius * p.q[i];
        // The kernel's expression, from the coarser node's scan.
        const double wide = radius * p.q[i] + (p.q[i] < p.q[j] ? pair_skin * (p.q[j] - p.q[i]) : 0.0);
        const bool coarser = got.level[j] > got.level[i];
        if (d2 <= own * own || (coarser && d2 <= wide * wide)) {
          row.push_back(static_cast<std::int32_t>(j));
          if (!(d2 <= own * own)) ++widened;
        }
        if (p.kind[j] == kSimInterior && got.level[j] == got.level[i] && d2 <= own * own) {
          ratio = std::max(ratio, p.q[i] / p.q[j]);
          rho = std::max(rho, p.q[i] / p.q[j]);
        }
      }
      largest = std::max(largest, ratio);
      const int exact = static_cast<int>(std::ceil(16.0 * std::log2(rho)));
      CHECK(static_cast<int>(got.skin_class[i]) >= exact);
      CHECK(static_cast<int>(got.skin_class[i]) <= exact + 1);
      CHECK(rho < 2.0);  // one level spans a factor 2 of radii
      if (p.kind[i] != kSimInterior) continue;
      REQUIRE(got.count[i] == static_cast<std::int32_t>(row.size()));
      for (std::size_t k = 0; k < row.size(); ++k) REQUIRE(got.index[got.offset[i] + k] == row[k]);
    }
    CHECK(got.spacing_ratio >= largest);
    CHECK(got.spacing_ratio <= largest + 2.0 / ocl::kRowRatioScale);
    if (in.name == graded_input(false).name) CHECK(widened > 0);  // the widened radius is exercised
  }
}
