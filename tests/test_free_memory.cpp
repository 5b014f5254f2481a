// give_back_free_memory (core/free_memory): the free heap's pages go back to the system once the
// arenas hold at least kKeptFreeBytes free, and stay below that (their refault would cost more).
// The test needs glibc's own allocator: under AddressSanitizer malloc is ASan's, mallinfo2 reports
// nothing and malloc_trim has no heap to trim, so the test is left out there.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <vector>

#include "core/free_memory.hpp"

#if defined(__GLIBC__) && __GLIBC_PREREQ(2, 33) && !defined(__SANITIZE_ADDRESS__)
#include <malloc.h>
#include <unistd.h>

namespace {

// This process's resident bytes (/proc/self/statm's second field, in pages).
std::size_t resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t size = 0, resident = 0;
  statm >> size >> resident;
  return resident * static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
}

// `bytes` of free, resident heap in the middle of the main arena: small blocks (below the mmap
// threshold) written, then freed with a live block after them, so that free() cannot give their
// pages back by shrinking the heap's top. Returns the live block.
void* free_resident_heap(std::size_t bytes) {
  constexpr std::size_t kBlock = 1024;
  std::vector<void*> blocks(bytes / kBlock);
  for (void*& b : blocks) {
    b = std::malloc(kBlock);
    std::memset(b, 1, kBlock);
  }
  void* pin = std::malloc(kBlock);
  for (void* b : blocks) std::free(b);
  return pin;
}

}  // namespace

TEST_CASE("give_back_free_memory: pages kept below the threshold, given back above it", "[memory]") {
  SECTION("below: kept") {
    malloc_trim(0);
    void* pin = free_resident_heap(pdmesh::kKeptFreeBytes / 4);
    REQUIRE(mallinfo2().fordblks < pdmesh::kKeptFreeBytes);
    const std::size_t before = resident_bytes();
    pdmesh::give_back_free_memory();
    CHECK(resident_bytes() + pdmesh::kKeptFreeBytes / 16 > before);  // at most a little less
    std::free(pin);
  }
  SECTION("above: given back") {
    malloc_trim(0);
    void* pin = free_resident_heap(2 * pdmesh::kKeptFreeBytes);
    REQUIRE(mallinfo2().fordblks >= pdmesh::kKeptFreeBytes);
    const std::size_t before = resident_bytes();
    pdmesh::give_back_free_memory();
    CHECK(resident_bytes() + pdmesh::kKeptFreeBytes < before);  // most of the 2 x threshold went
    std::free(pin);
  }
}
#endif
