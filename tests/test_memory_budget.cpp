// The memory and node budgets checked before allocation (core/memory_budget, the background builder's
// level checks, the node estimate's arithmetic): sizes as users write them, the default limit, and
// refusals that carry the numbers, all on small inputs.
#include <catch2/catch.hpp>

#include "error_message.hpp"

#include <sys/resource.h>

#include <cmath>
#include <limits>
#include <string>

#include "core/errors.hpp"
#include "core/memory_budget.hpp"
#include "geometry/geometry_tree.hpp"
#include "geometry_fixtures.hpp"
#include "init/node_estimate.hpp"
#include "spacing/background_builder.hpp"
#include "spacing/background_field.hpp"
#include "spacing/spacing_field.hpp"
#include "spacing/spacing_pipeline.hpp"

using namespace pdmesh;

namespace {

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("memory limit: sizes with suffixes in powers of 1024", "[memory]") {
  CHECK(parse_memory_limit("4G").bytes == 4ull << 30);
  CHECK(parse_memory_limit("512M").bytes == 512ull << 20);
  CHECK(parse_memory_limit("1.5GiB").bytes == 3ull << 29);
  CHECK(parse_memory_limit("2t").bytes == 2ull << 40);
  CHECK(parse_memory_limit("64KB").bytes == 64ull << 10);
  CHECK(parse_memory_limit("4096").bytes == 4096);
  CHECK(parse_memory_limit("4G").described == "--max-memory 4.00 GiB");
}

TEST_CASE("memory limit: anything but a positive size is refused, naming the option and the text", "[memory]") {
  for (const char* bad : {"-1", "0", "abc", "4X", "4GG", "", "nan", "inf", "1e30T", "0.1"}) {
    INFO(bad);
    try {
      (void)parse_memory_limit(bad);
      FAIL("accepted");
    } catch (const InputError& e) {
      CHECK(contains(e.what(), std::string("--max-memory ") + bad + ":"));
    }
  }
}

TEST_CASE("memory limit: the default is 3/4 of the address-space limit when that is the least", "[memory]") {
  rlimit saved{};
  REQUIRE(getrlimit(RLIMIT_AS, &saved) == 0);
  rlimit set = saved;
  set.rlim_cur = std::min<rlim_t>(saved.rlim_cur, rlim_t{1} << 30);  // 1 GiB, below any RAM
  REQUIRE(setrlimit(RLIMIT_AS, &set) == 0);
  const MemoryLimit m = default_memory_limit();
  REQUIRE(setrlimit(RLIMIT_AS, &saved) == 0);
  CHECK(m.bytes == static_cast<std::uint64_t>(kDefaultMemoryShare * static_cast<double>(set.rlim_cur)));
  CHECK(contains(m.described, "ulimit -v"));
  CHECK(contains(m.described, "default --max-memory"));
}

TEST_CASE("memory limit: check_memory refuses with what, how much and the limit", "[memory]") {
  const MemoryLimit limit = parse_memory_limit("1M");
  CHECK_NOTHROW(check_memory(limit, 1024.0 * 1024.0, "x", "y"));
  const std::string m =
      pdmesh_test::error_message<LimitError>([&] { check_memory(limit, 3.5 * 1024 * 1024, "the thing", "raise it"); });
  CHECK(m == "the thing needs about 3.50 MiB of memory, more than --max-memory 1.00 MiB; raise it");
  CHECK_FALSE(pdmesh_test::error_message<LimitError>([&] {
                check_memory(limit, std::numeric_limits<double>::infinity(), "t", "r");
              }).empty());
  CHECK_NOTHROW(check_memory(MemoryLimit{}, 1e30, "no limit", "r"));
}

TEST_CASE("node estimate: spacings beyond 1e154 give a finite count, not NaN", "[memory]") {
  // q^2 overflows above ~1.34e154: the closed form took inf - inf.
  for (const double q : {2e154, 1e200, 1e300}) {
    INFO(q);
    const double v = inverse_square_integral(q, q, q, q);
    CHECK(std::isfinite(v));
    CHECK(v == Approx(1.0 / (q * (q / 1e100)) / 1e100).epsilon(1e-12));
    const double w = inverse_square_integral(q, 2 * q, 1.5 * q, q);
    CHECK(std::isfinite(w));
    CHECK(w >= 0.0);  // 1e-400 underflows to 0
  }
  // Tiny spacings: the count grows without NaN.
  CHECK(std::isinf(inverse_square_integral(1e-160, 1e-160, 1e-160, 1e-160)));  // 1e320
  CHECK_FALSE(std::isnan(inverse_square_integral(1e-200, 1.0, 1.0, 1e200)));
  // The usual range is the formula as it was, bit for bit.
  CHECK(inverse_square_integral(0.5, 0.5, 0.5, 0.5) == 4.0);
}

TEST_CASE("background quadtree: a field that asks for far more nodes than max_nodes is refused on a coarse level",
          "[memory]") {
  const Geometry g = fixtures::square(1.0, 4);
  const GeometryTree tree(g);
  // q = 1e-4 on the unit square asks for about 1.15e8 nodes; its tree at that resolution would hold
  // ~3e7 leaves. The root level (512 x 512 cells) already shows the count.
  const fixtures::ConstantSpacing q(1e-4);
  BackgroundOptions options;
  options.max_nodes = 1000.0;
  BackgroundBuilder builder(q, tree, options);
  const std::string m = pdmesh_test::error_message<LimitError>([&] { builder.build(); });
  INFO(m);
  CHECK(contains(m, "asks for about 1.1"));
  CHECK(contains(m, "e+08 nodes already on level 0"));
  CHECK(contains(m, "--max-nodes 1000"));
  CHECK(builder.cells().size() == 512u * 512u);  // nothing below the roots was made
}

TEST_CASE("background quadtree: a tree that would outgrow the memory limit is refused before its level is made",
          "[memory]") {
  const Geometry g = fixtures::square(1.0, 4);
  const GeometryTree tree(g);
  // q from 0.005 at x = 0 to 0.105 at x = 1 (about 2200 nodes): 5 x 5 root cells, refined toward x = 0.
  const ExpressionSpacing q("0.005 + 0.1 * x");
  BackgroundOptions options;
  options.max_nodes = 1e6;  // not the limit that refuses
  options.memory = parse_memory_limit("256K");
  BackgroundBuilder builder(q, tree, options);
  const std::string m = pdmesh_test::error_message<LimitError>([&] { builder.build(); });
  INFO(m);
  CHECK(contains(m, "the spacing field's background quadtree of"));
  CHECK(contains(m, "cells (level "));
  CHECK(contains(m, "more than --max-memory 256 KiB"));
  CHECK(builder.cells().size() * BackgroundBuilder::kBytesPerCell <= 256.0 * 1024.0);
  // With room, the same tree is built, larger than the limit above.
  options.memory = parse_memory_limit("64M");
  BackgroundBuilder roomy(q, tree, options);
  CHECK_NOTHROW(roomy.build());
  CHECK(roomy.cells().size() * BackgroundBuilder::kBytesPerCell > 256.0 * 1024.0);
}

TEST_CASE("background quadtree: the coarse count leaves a field within max_nodes alone", "[memory]") {
  // The exact estimate is what --max-nodes compares; the level check only refuses beyond a margin.
  const Geometry g = fixtures::square(1.0, 4);
  const GeometryTree tree(g);
  const fixtures::ConstantSpacing q(2e-2);
  BackgroundOptions options;
  BackgroundSpacing exact_tree(q, tree, options);
  const double estimate = estimate_node_count(tree, exact_tree);
  options.max_nodes = estimate;  // exactly at the limit
  BackgroundBuilder builder(q, tree, options);
  CHECK_NOTHROW(builder.build());
  options.max_nodes = estimate / (2.0 * BackgroundBuilder::kEarlyNodeMargin);
  BackgroundBuilder refused(q, tree, options);
  CHECK_THROWS_AS(refused.build(), LimitError);
}

TEST_CASE("spacing pipeline: limits that ask for far more nodes than max_nodes are refused before refinement",
          "[memory]") {
  const Geometry g = fixtures::square(1.0, 4);
  const GeometryTree tree(g);
  // A point size of 1e-4 spreading by a gradation of 0.001 asks for millions of nodes.
  SpacingOptions options;
  options.gradation = 0.001;
  options.points.push_back({{0.5, 0.5}, 1e-4});
  options.background.max_nodes = 1000.0;
  SECTION("a base field fine enough for inside leaves: refused on the base tree's leaves") {
    const fixtures::ConstantSpacing base(0.05);
    const std::string m =
        pdmesh_test::error_message<LimitError>([&] { SpacingPipeline pipeline(base, tree, options); });
    INFO(m);
    CHECK(contains(m, "the spacing field with its limits"));
    CHECK(contains(m, "before they are refined for it, more than --max-nodes 1000"));
  }
  SECTION("a base field whose leaves all cross the boundary: refused on a coarse level of the refinement") {
    // One node per unit area: no base leaf lies inside the square, so only the refinement's own count
    // sees the limit's nodes; it refuses on level 2 (cells of side ~0.25), long before the ~1e-4 cells.
    const fixtures::ConstantSpacing base(1.0);
    const std::string m =
        pdmesh_test::error_message<LimitError>([&] { SpacingPipeline pipeline(base, tree, options); });
    INFO(m);
    CHECK(contains(m, "nodes already on level 2 of its quadtree"));
    CHECK(contains(m, "more than --max-nodes 1000"));
  }
  SECTION("within the budget it builds") {
    const fixtures::ConstantSpacing base(1.0);
    options.background.max_nodes = 1e9;
    options.points.front().q = 0.05;
    CHECK_NOTHROW(SpacingPipeline(base, tree, options));
  }
}
