#include "util/heap_release.h"

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

}  // namespace emboss
