// Tests for the fault guard of the KMS dumb-buffer path: a write into a mapping that stops being
// memory (here a file truncated under its map, which faults with SIGBUS as a removed card's buffer
// does) ends the guarded body with false, and the process, and later guards, carry on.
#include <gtest/gtest.h>

#include <sys/mman.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

#include "display/kms_scanout.h"

namespace emboss {
namespace {

struct Target {
  std::uint8_t* map;
  std::size_t size;
  int reached = 0;  // pages written before the fault
};

void fill(void* context) {
  auto* t = static_cast<Target*>(context);
  const long page = sysconf(_SC_PAGESIZE);
  for (std::size_t off = 0; off < t->size; off += static_cast<std::size_t>(page)) {
    std::memset(t->map + off, 0x5A, static_cast<std::size_t>(page));
    ++t->reached;
  }
}

// A shared map of a temporary file of `pages` pages.
struct MappedFile {
  explicit MappedFile(int pages) {
    char name[] = "/tmp/emboss-guard-XXXXXX";
    fd = mkstemp(name);
    unlink(name);
    size = static_cast<std::size_t>(pages) * static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
    if (fd >= 0 && ftruncate(fd, static_cast<off_t>(size)) == 0) {
      void* m = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
      if (m != MAP_FAILED) map = static_cast<std::uint8_t*>(m);
    }
  }
  ~MappedFile() {
    if (map != nullptr) munmap(map, size);
    if (fd >= 0) close(fd);
  }
  int fd = -1;
  std::size_t size = 0;
  std::uint8_t* map = nullptr;
};

TEST(KmsScanout, AGuardedWriteIntoLiveMemoryRunsToItsEnd) {
  MappedFile f(4);
  ASSERT_NE(f.map, nullptr);
  Target t{f.map, f.size};
  EXPECT_TRUE(runGuarded(fill, &t));
  EXPECT_EQ(t.reached, 4);
  EXPECT_EQ(f.map[f.size - 1], 0x5A);
}

TEST(KmsScanout, AWriteIntoAMappingThatWentAwayEndsWithFalseAndTheProcessCarriesOn) {
  for (int round = 0; round < 20; ++round) {  // the guard re-arms, and the signal mask is restored each time
    MappedFile f(4);
    ASSERT_NE(f.map, nullptr);
    ASSERT_EQ(ftruncate(f.fd, 0), 0);  // the pages behind the map are gone: touching them is SIGBUS
    Target t{f.map, f.size};
    EXPECT_FALSE(runGuarded(fill, &t)) << "round " << round;
    EXPECT_EQ(t.reached, 0);
    MappedFile live(2);
    Target ok{live.map, live.size};
    EXPECT_TRUE(runGuarded(fill, &ok)) << "round " << round;
  }
}

TEST(KmsScanout, EachThreadHasItsOwnGuard) {
  MappedFile gone(2);
  ASSERT_NE(gone.map, nullptr);
  ASSERT_EQ(ftruncate(gone.fd, 0), 0);
  bool results[2] = {true, false};
  std::thread a([&] {
    Target t{gone.map, gone.size};
    results[0] = runGuarded(fill, &t);
  });
  std::thread b([&] {
    MappedFile live(8);
    Target t{live.map, live.size};
    results[1] = runGuarded(fill, &t);
  });
  a.join();
  b.join();
  EXPECT_FALSE(results[0]);
  EXPECT_TRUE(results[1]);
}

void faultOutsideAGuard() {
  MappedFile f(1);
  Target t{f.map, f.size};
  runGuarded(fill, &t);  // installs the handler
  if (ftruncate(f.fd, 0) != 0) std::exit(3);
  std::memset(f.map, 1, f.size);  // unguarded: SIGBUS, the default action
  std::exit(0);
}

TEST(KmsScanout, AFaultOutsideAGuardStillEndsTheProcess) {
  // The handler must not swallow the faults of the rest of the program.
  EXPECT_EXIT(faultOutsideAGuard(), ::testing::KilledBySignal(SIGBUS), "");
}

TEST(KmsScanout, SoftwareRenderersAreRecognised) {
  EXPECT_TRUE(isSoftwareRenderer("llvmpipe (LLVM 15.0.6, 256 bits)"));
  EXPECT_TRUE(isSoftwareRenderer("softpipe"));
  EXPECT_FALSE(isSoftwareRenderer("V3D 4.2"));
  EXPECT_FALSE(isSoftwareRenderer("Mesa Intel(R) UHD Graphics 620 (KBL GT2)"));
}

}  // namespace
}  // namespace emboss
