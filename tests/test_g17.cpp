// append_g17 writes a double exactly as fmt's {:.17g} (printf's %.17g) did before it: the mesh and
// node files must keep their bytes.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include <fmt/format.h>

#include "core/g17.hpp"

namespace {

std::string g17(double v) {
  std::string out;
  pdmesh::append_g17(out, v);
  return out;
}

}  // namespace

TEST_CASE("append_g17 writes what fmt's {:.17g} writes", "[g17]") {
  const double special[] = {0.0,
                            -0.0,
                            1.0,
                            -1.0,
                            0.1,
                            1e-5,
                            1e-4,
                            1e16,
                            1e17,
                            123456789012345678.0,
                            5e-324,
                            2.2250738585072014e-308,
                            std::numeric_limits<double>::max(),
                            std::numeric_limits<double>::infinity(),
                            -std::numeric_limits<double>::infinity(),
                            std::numeric_limits<double>::quiet_NaN(),
                            1e300,
                            -1e300,
                            0.35,
                            399.924};
  for (const double v : special) {
    INFO(fmt::format("{:.17g}", v));
    CHECK(g17(v) == fmt::format("{:.17g}", v));
  }
  CHECK(g17(0.1) == "0.10000000000000001");
  CHECK(g17(1e17) == "1e+17");
  // Random bit patterns (every exponent and sign) and coordinates of a unit-size geometry.
  std::mt19937_64 random(14);
  std::uniform_real_distribution<double> coordinate(-20.0, 20.0);
  int differ = 0;
  for (int i = 0; i < 100000; ++i) {
    std::uint64_t bits = random();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    if (std::isnan(v)) v = coordinate(random);
    differ += g17(v) != fmt::format("{:.17g}", v);
    const double c = coordinate(random);
    differ += g17(c) != fmt::format("{:.17g}", c);
  }
  CHECK(differ == 0);
}

TEST_CASE("append_g17 appends to an fmt::memory_buffer too", "[g17]") {
  fmt::memory_buffer out;
  pdmesh::append_g17(out, -2.5);
  out.push_back(' ');
  pdmesh::append_g17(out, 1.0 / 3.0);
  CHECK(fmt::to_string(out) == "-2.5 0.33333333333333331");
}
