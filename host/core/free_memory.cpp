// Freed heap pages back to the system; see free_memory.hpp.
#include "core/free_memory.hpp"

#include <cstdlib>  // defines __GLIBC__ (features.h), which the test below needs
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace pdmesh {

void give_back_free_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace pdmesh
