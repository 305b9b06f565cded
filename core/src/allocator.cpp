#include "navaid/core/allocator.hpp"

#include <cstdlib>  // defines __GLIBC__ on glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace navaid {

bool keep_freed_memory() {
#if defined(__GLIBC__)
  // Both are needed: a fixed mmap threshold alone moves the blocks onto the heap, whose top the
  // default trim threshold then hands back; a trim threshold alone leaves them mmapped.
  constexpr int kMmapThreshold = 32 << 20;  // glibc's ceiling for this setting on 64-bit
  constexpr int kTrimThreshold = 512 << 20;
  return mallopt(M_MMAP_THRESHOLD, kMmapThreshold) == 1 && mallopt(M_TRIM_THRESHOLD, kTrimThreshold) == 1;
#else
  return false;
#endif
}

}  // namespace navaid
