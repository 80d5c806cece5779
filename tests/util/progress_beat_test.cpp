// The watchdog feeder: a ping only while work is done, at most every interval.
#include <gtest/gtest.h>

#include "render/thread_pool.h"
#include "util/progress_beat.h"

namespace emboss {
namespace {

TEST(WatchdogFeeder, PingsWhileWorkIsDoneAtMostEveryInterval) {
  WatchdogFeeder f(5.0);
  EXPECT_TRUE(f.due(1, 0.0));    // work seen: the first ping
  EXPECT_FALSE(f.due(2, 1.0));   // work, but within the interval
  EXPECT_TRUE(f.due(2, 5.0));    // the work seen at 1.0 counts once the interval has passed
  EXPECT_FALSE(f.due(3, 6.0));
  EXPECT_TRUE(f.due(4, 10.5));
}

TEST(WatchdogFeeder, NoPingWhenNothingMoves) {
  WatchdogFeeder f(5.0);
  EXPECT_TRUE(f.due(7, 0.0));
  // A hang: the count stands still, so the watchdog is never fed again however long we look.
  for (double t = 1; t < 100; t += 1) EXPECT_FALSE(f.due(7, t)) << t;
  EXPECT_TRUE(f.due(8, 100.0));  // work again: fed again
}

TEST(WatchdogFeeder, TheThreadPoolsTilesAreWork) {
  ThreadPool pool(2);
  const std::uint64_t before = progressBeats().load();
  pool.parallelFor2D(Rect{0, 0, 64, 64}, 16, [](const Rect&) {});
  EXPECT_GE(progressBeats().load() - before, 16u);  // one beat per tile, 4 x 4 tiles
}

}  // namespace
}  // namespace emboss
