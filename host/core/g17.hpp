// append_g17: a double as printf's %.17g (17 significant digits, enough to read it back exactly),
// through std::to_chars. The characters are fmt's {:.17g} (both are printf's correctly rounded %g;
// tests/test_g17.cpp compares them on special values and random bit patterns), in about half the
// time: fmt 9 takes its slow path for a given precision, and the ASCII mesh and node writers are
// mostly such numbers (the 30P30N .vtu holds 170k of them; the 4M-node annulus' .vtu took 38 s).
#pragma once
#include <charconv>

namespace pdmesh {

// Out: std::string or fmt::memory_buffer (anything with append(first, last)).
template <class Out>
void append_g17(Out& out, double v) {
  char buffer[32];  // "-1.2345678901234567e-308" is 24
  const std::to_chars_result r = std::to_chars(buffer, buffer + sizeof buffer, v, std::chars_format::general, 17);
  out.append(buffer, r.ptr);
}

}  // namespace pdmesh
