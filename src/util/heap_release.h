// The heap at the kiosk's quiet moments. glibc keeps what short-lived large buffers freed (a piece's
// field, a picture being saved) in the arena of the thread that freed them, and raises its mmap
// threshold after each such free: the resident size then steps up with the largest piece ever
// shown and never comes down (docs/performance.md, the soak). Elsewhere both calls do nothing.
#pragma once

namespace emboss {

// At start: buffers of kHeapMmapThreshold and more are mapped on their own and unmapped when freed
// (a fixed threshold turns off glibc's dynamic one).
void tuneHeapForKiosk();
// When a visitor has left: the free pages of every arena go back to the system (malloc_trim).
void releaseFreeHeap();
// True where the two calls above do something (glibc).
bool heapReleaseWorks();

inline constexpr int kHeapMmapThreshold = 1 << 20;

}  // namespace emboss
