// Freed heap pages back to the system; see free_memory.hpp.
#include "core/free_memory.hpp"

#include <cstdlib>  // defines __GLIBC__ (features.h), which the test below needs
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace pdmesh {

void give_back_free_memory() {
#if defined(__GLIBC__)
  // The pages given back fault in again when the heap grows into them: below kKeptFreeBytes of free
  // heap that refault costs more than the pages are worth (a 14k-node run calls this ~48 times with
  // 20-36 MB free; trimming every time doubled its page faults), and the resident set is at most that
  // much above the trimmed one.
#if __GLIBC_PREREQ(2, 33)  // mallinfo2; an older glibc trims every time
  if (mallinfo2().fordblks < kKeptFreeBytes) return;
#endif
  malloc_trim(0);
#endif
}

}  // namespace pdmesh
