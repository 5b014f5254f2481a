// libFuzzer target: pdmesh::fuzz::mesh_reader_medit (see fuzz_entries.hpp; run with tools/check/fuzz.sh).
#include <cstddef>
#include <cstdint>

#include "fuzz_entries.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  pdmesh::fuzz::mesh_reader_medit(data, size);
  return 0;
}
