#include "core/allocator.h"

#include <cstdlib>  // defines __GLIBC__ where the C library is glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace plslam {

bool keepFreedMemoryForReuse() {
#if defined(__GLIBC__)
  // Setting either value also turns off glibc's own adaptation of the two, which raises
  // them only for the main thread's arena and only after a large block was freed.
  constexpr int kMmapThreshold = 16 << 20;  // blocks below this come from the arenas (max 32 MB)
  constexpr int kTrimThreshold = 64 << 20;  // an arena keeps up to this much free memory at its top
  return mallopt(M_MMAP_THRESHOLD, kMmapThreshold) == 1 && mallopt(M_TRIM_THRESHOLD, kTrimThreshold) == 1;
#else
  return false;
#endif
}

}  // namespace plslam
