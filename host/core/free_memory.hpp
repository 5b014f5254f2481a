// Giving freed heap pages back to the system in the middle of a run, so that a transient's pages are
// not resident beside the next one (glibc keeps freed blocks below its mmap threshold, which rises to
// 32 MB as large blocks are freed: a million-node run's node arrays are 8-16 MB).
#pragma once
#include <cstddef>

namespace pdmesh {

// Free heap below which give_back_free_memory keeps the pages (the arenas' free bytes, mallinfo2).
inline constexpr std::size_t kKeptFreeBytes = std::size_t{64} << 20;

// malloc_trim(0) where the C library has it (glibc), once the arenas hold at least kKeptFreeBytes
// free: every arena's whole free pages are given back (madvise), the blocks stay the allocator's.
// Nothing elsewhere. A few milliseconds on a million-node run's heap; the pages given back fault in
// again when reused.
void give_back_free_memory();

}  // namespace pdmesh
