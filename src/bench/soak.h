// The kiosk's soak: the whole kiosk logic, headless and on a fake clock, through many visitors'
// strokes with undo, redo, resets, restores from the journal and attract cycles, watching the
// process's resident memory and open file descriptors (docs/performance.md, "Soak").
#pragma once

#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <string>

namespace emboss {

struct SoakOptions {
  size_t strokes = 200000;
  size_t reportEvery = 0;   // a table row every this many strokes (0: strokes / 20)
  size_t warmup = 0;        // strokes before the baseline (0: strokes / 10)
  int width = 96, height = 60;  // the screen in memory, pixels
  int threads = 1;          // render threads
  std::filesystem::path dir;  // the sessions folder's parent (empty: a new temporary folder, removed at the end)
  size_t restartEvery = 7;     // the kiosk is killed and restarted mid-session every this many
                               // visitors (0: never: one kiosk lives through the whole soak)
  unsigned seed = 1;
  double attractSeconds = 12;  // attract mode's play after a visitor leaves (fake clock, 0.2 s steps)
  size_t attractEvery = 10;    // attract plays after every this many visitors; the others are
                               // followed at once by the next visitor (a busy day)
  size_t leakKibPerVisitor = 0;  // a leak put in on purpose, to show that the verdict catches one:
                                 // this many KiB allocated, touched and held after every visitor
};

struct SoakResult {
  bool pass = false;
  // Resident memory read when a visitor has left (the session ended, the sheet blank, the heap
  // trimmed, before attract mode plays): the median, and the lowest, of the readings in the last
  // report window minus those of the first window after the warm-up. The verdict is on the median.
  double settledGrowthMb = 0, settledLowestGrowthMb = 0;
  long fdGrowth = 0;  // open file descriptors at the end minus after the warm-up
};

// The limits the soak holds the kiosk to: resident memory growth after warm-up, fd growth.
inline constexpr double kSoakMaxRssGrowthMb = 2.0;
inline constexpr long kSoakMaxFdGrowth = 0;

// Runs the soak, printing the table and the verdict to `out` as it goes.
SoakResult runSoak(const SoakOptions& options, std::FILE* out);

// The process's resident set now and at its peak so far (VmRSS, VmHWM of /proc/self/status) in KiB,
// and its open file descriptors (entries of /proc/self/fd, the one used to count them excluded).
// -1 when they cannot be read.
long residentKib();
long peakResidentKib();
long openFds();

}  // namespace emboss
