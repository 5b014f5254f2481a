// The device neighbour build (opencl/device_neighbours, kernels/neighbours.cl) on its own: every
// row, in order, equals the brute-force reference row (ascending, the `stride` smallest on overflow),
// padding is -1, and the index buffer beyond n x stride is left alone (canary tail).
#include <catch2/catch.hpp>

#include <algorithm>
#include <vector>

#include "opencl/device_neighbours.hpp"
#include "sim/reference/reference_backend.hpp"
#include "step_backend_inputs.hpp"

using namespace pdmesh;
using namespace pdmesh::test;

namespace {

constexpr std::int32_t kCanary = 0x5EEDBEEF;

struct DeviceLists {
  std::vector<std::int32_t> count, index;
  NeighbourFlags flags;
  int stride = 0;
};

// Builds on the device (double) with a fixed stride (no growing) after filling the index buffer,
// sized `capacity` rows (>= n), with the canary.
DeviceLists device_build(const SimParticles& p, double cutoff, int stride, std::size_t capacity) {
  ocl::Context& ctx = test_context();
  ocl::StepProgram& program = test_program(ocl::Precision::Double);
  ocl::DeviceNeighbours<double> nb(ctx, program);
  const std::size_t n = p.size();
  ocl::Buffer<double> x(ctx, "x", n), y(ctx, "y", n), q(ctx, "q", n);
  ocl::Buffer<std::uint8_t> kind(ctx, "kind", n);
  ocl::Buffer<std::int32_t> prev(ctx, "prev", n), next(ctx, "next", n);
  x.upload(ctx.queue(), p.x);
  y.upload(ctx.queue(), p.y);
  q.upload(ctx.queue(), p.q);
  kind.upload(ctx.queue(), p.kind);
  prev.upload(ctx.queue(), p.prev);
  next.upload(ctx.queue(), p.next);
  // A first build over `capacity` nodes sizes the index buffer; then the canary fills all of it.
  SimParticles big = p;
  while (big.size() < capacity) pdmesh_test::add(big, 1e6 + static_cast<double>(big.size()), 0.0, 1.0);
  int s = stride;
  {
    ocl::Buffer<double> bx(ctx, "x", capacity), by(ctx, "y", capacity), bq(ctx, "q", capacity);
    ocl::Buffer<std::uint8_t> bk(ctx, "kind", capacity);
    ocl::Buffer<std::int32_t> bp(ctx, "prev", capacity), bn(ctx, "next", capacity);
    bx.upload(ctx.queue(), big.x);
    by.upload(ctx.queue(), big.y);
    bq.upload(ctx.queue(), big.q);
    bk.upload(ctx.queue(), big.kind);
    bp.upload(ctx.queue(), big.prev);
    bn.upload(ctx.queue(), big.next);
    nb.build(big.x.data(), big.y.data(), big.q.data(), big.kind.data(), capacity, cutoff, bx, by, bq, bk, bp, bn, s,
             false);
  }
  const std::size_t slots = std::max<std::size_t>(nb.index().size(), 1);
  nb.index().upload(ctx.queue(), std::vector<std::int32_t>(slots, kCanary));
  DeviceLists out;
  out.stride = stride;
  out.flags = nb.build(p.x.data(), p.y.data(), p.q.data(), p.kind.data(), n, cutoff, x, y, q, kind, prev, next,
                       out.stride, false);
  nb.count().download(ctx.queue(), out.count, n);
  nb.index().download(ctx.queue(), out.index);
  return out;
}

void check_against_reference(const Input& in, int stride, std::size_t capacity) {
  INFO("input " << in.name << ", " << in.p.size() << " nodes, stride " << stride << ", capacity " << capacity);
  const std::size_t n = in.p.size();
  const DeviceLists got = device_build(in.p, in.cutoff, stride, capacity);
  NeighbourList oracle;
  oracle.stride = stride;
  NeighbourFlags oflags;
  reference::build_neighbours_brute_force(in.p, in.cutoff, oracle, oflags);
  REQUIRE(got.stride == stride);
  REQUIRE(got.flags.overflow == oflags.overflow);
  REQUIRE(got.flags.max_count == oflags.max_count);
  REQUIRE(got.flags.pairs_within == oflags.pairs_within);
  REQUIRE(got.count == oracle.count);
  const auto s = static_cast<std::size_t>(stride);
  for (std::size_t i = 0; i < n; ++i) {
    INFO("node " << i);
    const std::size_t listed = std::min<std::size_t>(static_cast<std::size_t>(oracle.count[i]), s);
    for (std::size_t k = 0; k < s; ++k) {
      INFO("slot " << k);
      // The reference row is ascending and truncated; the device's must equal it slot by slot.
      REQUIRE(got.index[i * s + k] == (k < listed ? oracle.index[i * s + k] : -1));
    }
  }
  std::size_t canaries = 0;
  for (std::size_t k = n * s; k < got.index.size(); ++k) canaries += got.index[k] == kCanary ? 1 : 0;
  CHECK(canaries == got.index.size() - std::min(got.index.size(), n * s));
}

}  // namespace

TEST_CASE("device neighbour rows equal the reference rows in order at awkward sizes", "[opencl][neighbour]") {
  const std::size_t wg = ocl::kStepWorkGroup;
  for (std::size_t n : {std::size_t{0}, std::size_t{1}, wg - 1, wg, wg + 1, std::size_t{131}})
    check_against_reference(random_input(n, 77 + n, false), 32, n + 70);
  check_against_reference(graded_input(false), 32, 700);
  check_against_reference(lattice_input(), 16, 100);
}

TEST_CASE("device neighbour rows with coincident nodes equal the reference", "[opencl][neighbour]") {
  Input in = coincident_input(false);
  // And a stack of 5 nodes at one point: each sees the 4 others at distance 0.
  for (int k = 0; k < 5; ++k) pdmesh_test::add(in.p, 0.25, 0.25, 0.1);
  check_against_reference(in, 32, in.p.size() + 9);
}

TEST_CASE("an overflowing device row keeps the stride smallest indices, ascending", "[opencl][neighbour]") {
  const Input in = crowded_input(false);
  for (int stride : {2, 8, 38, 39, 40}) check_against_reference(in, stride, in.p.size() + 3);
}

// The graded input spans 10 grid levels, so rows get entries scattered by coarser nodes; at these
// strides rows overflow with both parts present, the case where the owner's and the scatters' writes
// once met in one row (a data race: oclgrind --data-races, label oclgrind, counts it).
TEST_CASE("graded rows overflowing small strides with scattered entries equal the reference", "[opencl][neighbour]") {
  const Input in = graded_input(false);
  int overflowing = 0;
  for (int stride : {2, 3, 4, 5, 6, 7, 8, 9, 12, 16, 24}) {
    check_against_reference(in, stride, in.p.size() + 70);  // the device's overflow flag is the reference's
    NeighbourList oracle;
    oracle.stride = stride;
    NeighbourFlags oflags;
    reference::build_neighbours_brute_force(in.p, in.cutoff, oracle, oflags);
    overflowing += static_cast<int>(oflags.overflow);
  }
  CHECK(overflowing >= 6);  // strides 2 .. 8 (the largest graded row holds 9)
}
