#include "dloam/run/process_memory.hpp"

#include <cstdlib>  // defines __GLIBC__ with glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace dloam::run {

void reuse_freed_memory() {
#if defined(__GLIBC__)
  constexpr int kMB = 1 << 20;
  mallopt(M_MMAP_THRESHOLD, 32 * kMB);
  mallopt(M_TRIM_THRESHOLD, 256 * kMB);
#endif
}

}  // namespace dloam::run
