#include "util/heap_release.h"

#include <cstdlib>  // brings in the C library's own headers, which define __GLIBC__ on glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace emboss {

void tuneHeapForKiosk() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, kHeapMmapThreshold);
#endif
}

void releaseFreeHeap() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

bool heapReleaseWorks() {
#if defined(__GLIBC__)
  return true;
#else
  return false;
#endif
}

}  // namespace emboss
