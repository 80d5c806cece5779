// The kiosk's heap settings must take effect: big buffers mapped on their own, and the free pages
// of the heap given back when a visitor leaves. An earlier version compiled both to nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "util/heap_release.h"

namespace emboss {
namespace {

long residentKib() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::strtol(line.c_str() + 6, nullptr, 10);
  return -1;
}

TEST(HeapRelease, WorksOnGlibc) {
#if defined(__GLIBC__)
  EXPECT_TRUE(heapReleaseWorks());
#else
  EXPECT_FALSE(heapReleaseWorks());
#endif
}

#if defined(__GLIBC__)
TEST(HeapRelease, BigBuffersAreMappedOnTheirOwn) {
  tuneHeapForKiosk();
  const size_t before = mallinfo2().hblkhd;
  // Below the threshold: from the heap (glibc's own starting threshold, 128 KiB, would map it).
  void* small = std::malloc(kHeapMmapThreshold / 2);
  EXPECT_EQ(mallinfo2().hblkhd, before);
  std::free(small);
  // Above it: mapped on its own, and unmapped when freed. glibc serves any request from a free
  // chunk big enough before it thinks of mapping, and the tests run before this one (in one
  // process) may have left such chunks; so the block is bigger than all the heap's free bytes.
  const size_t size = std::max<size_t>(2u << 20, mallinfo2().fordblks + (1u << 20));
  void* big = std::malloc(size);
  ASSERT_NE(big, nullptr);
  std::memset(big, 1, size);
  EXPECT_GE(mallinfo2().hblkhd, before + size);
  std::free(big);
  EXPECT_EQ(mallinfo2().hblkhd, before);
}

TEST(HeapRelease, TheFreePagesGoBackWhenAVisitorLeaves) {
  if (residentKib() < 0) GTEST_SKIP() << "no /proc/self/status";
  tuneHeapForKiosk();
  // 48 MB in blocks below the mmap threshold (a piece's operations and their fields), then a small
  // block after them that stays, so that the heap's top cannot simply shrink.
  std::vector<void*> blocks;
  for (int i = 0; i < 480; ++i) {
    blocks.push_back(std::malloc(100 * 1024));
    ASSERT_NE(blocks.back(), nullptr);
    std::memset(blocks.back(), 1, 100 * 1024);
  }
  void* pin = std::malloc(64);
  for (void* b : blocks) std::free(b);
  const long held = residentKib();
  releaseFreeHeap();
  const long after = residentKib();
  std::free(pin);
  EXPECT_LT(after, held - 20 * 1024) << "resident " << held << " kB before malloc_trim, " << after << " kB after";
}
#endif

}  // namespace
}  // namespace emboss
