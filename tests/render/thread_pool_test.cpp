// The fixed thread pool: every tile once (one job, many back to back), workers reused, cancellation.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <functional>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

#include "bench/piece_generator.h"
#include "render/renderer.h"
#include "render/thread_pool.h"
#include "tools/metal.h"

namespace emboss {
namespace {

TEST(ThreadPool, RunsEveryTileOnce) {
  ThreadPool pool(3);
  EXPECT_EQ(pool.size(), 3);
  const Rect extent{5, 7, 101, 53};
  std::vector<std::atomic<int>> hits(static_cast<size_t>(extent.w) * extent.h);
  const bool done = pool.parallelFor2D(extent, 16, [&](const Rect& t) {
    for (int y = t.y; y < t.y + t.h; ++y)
      for (int x = t.x; x < t.x + t.w; ++x) ++hits[static_cast<size_t>(y - extent.y) * extent.w + (x - extent.x)];
  });
  EXPECT_TRUE(done);
  for (const auto& h : hits) ASSERT_EQ(h.load(), 1);
}

TEST(ThreadPool, KeepsItsThreadsAcrossJobs) {
  ThreadPool pool(2);
  std::mutex m;
  std::set<std::thread::id> seen;
  for (int job = 0; job < 50; ++job)
    pool.parallelFor2D(Rect{0, 0, 64, 64}, 8, [&](const Rect&) {
      std::this_thread::sleep_for(std::chrono::microseconds(50));
      std::lock_guard lock(m);
      seen.insert(std::this_thread::get_id());
    });
  // The caller and one worker, never a new thread per job.
  EXPECT_LE(seen.size(), 2u);
  EXPECT_EQ(pool.jobsRun(), 50u);
}

// Jobs one right after another, as a render's passes and a pen's steps come, of one tile to
// more than the threads: every tile of every job runs once, none after its job returned (a
// worker that wakes late must find the job closed).
TEST(ThreadPool, JobsBackToBackRunEveryTileOnceNoneAfterItsJobReturned) {
  ThreadPool pool(3);
  constexpr int kJobs = 4000, kMaxTiles = 9;
  // Job j's tiles are the columns j * kMaxTiles + [0, tiles): each counted where it ran.
  std::vector<std::atomic<int>> runs(static_cast<size_t>(kJobs) * kMaxTiles);
  std::atomic<int> returned{-1};  // the last job returned
  std::atomic<int> lateTiles{0};
  const std::function<void(const Rect&)> tile = [&](const Rect& t) {
    if (t.x / kMaxTiles <= returned.load()) ++lateTiles;
    ++runs[static_cast<size_t>(t.x)];
    const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(20);
    while (std::chrono::steady_clock::now() < until) {
    }
  };
  const auto tilesOf = [](int j) { return 1 + j % kMaxTiles; };
  for (int j = 0; j < kJobs; ++j) {
    ASSERT_TRUE(pool.parallelFor2D(Rect{j * kMaxTiles, 0, tilesOf(j), 1}, 1, tile));
    returned = j;
  }
  for (int j = 0; j < kJobs; ++j)
    for (int k = 0; k < kMaxTiles; ++k)
      ASSERT_EQ(runs[static_cast<size_t>(j) * kMaxTiles + k].load(), k < tilesOf(j) ? 1 : 0) << "job " << j << " tile " << k;
  EXPECT_EQ(lateTiles.load(), 0);
  EXPECT_EQ(pool.jobsRun(), static_cast<std::uint64_t>(kJobs));
}

TEST(ThreadPool, CancelledBeforeStartRunsNothing) {
  ThreadPool pool(2);
  std::atomic_bool cancel{true};
  std::atomic<int> tiles{0};
  EXPECT_FALSE(pool.parallelFor2D(Rect{0, 0, 100, 100}, 10, [&](const Rect&) { ++tiles; }, &cancel));
  EXPECT_EQ(tiles.load(), 0);
}

TEST(ThreadPool, CancelStopsAJobInFlightAndThePoolGoesOn) {
  ThreadPool pool(2);
  std::atomic_bool cancel{false};
  std::atomic<int> tiles{0};
  std::thread canceller([&] {
    while (tiles.load() < 4) std::this_thread::yield();
    cancel = true;
  });
  const bool done = pool.parallelFor2D(Rect{0, 0, 400, 400}, 10, [&](const Rect&) {
    ++tiles;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }, &cancel);
  canceller.join();
  EXPECT_FALSE(done);
  EXPECT_LT(tiles.load(), 1600);  // far from all of them
  // The next job runs to the end with the same workers.
  std::atomic<int> again{0};
  EXPECT_TRUE(pool.parallelFor2D(Rect{0, 0, 100, 100}, 10, [&](const Rect&) { ++again; }));
  EXPECT_EQ(again.load(), 100);
}

// A newer frame supersedes the one in flight: the kiosk's render thread is told to stop by the
// older frame's flag, and the next frame is exactly a fresh one.
TEST(ThreadPool, RendererFrameSupersededByANewerOne) {
  PieceOptions opt;
  opt.width = 60, opt.height = 40;
  opt.deformation = Deformation::Offset;  // the slow exact tracer: the frame is long enough to stop
  const GeneratedPiece piece = generatePiece(30, 3, opt);
  auto model = piece.makeModel();
  ASSERT_TRUE(model.ok());
  ThreadPool pool(2);
  Renderer renderer(pool);
  renderer.setCamera(Camera(piece.camera, 240, 160));
  ShadingParams shading;
  shading.metal = *metalByName("silver");
  renderer.setShading(shading);
  RenderOptions o;
  o.tileSize = 8;
  renderer.setOptions(o);
  renderer.sync(*model);

  Image image;
  std::atomic_bool older{false};
  std::atomic_bool started{false};
  bool olderDone = true;
  std::thread frame([&] {
    started = true;
    olderDone = renderer.render(image, Rect{0, 0, 240, 160}, nullptr, &older);
  });
  while (!started) std::this_thread::yield();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  older = true;  // superseded
  frame.join();
  EXPECT_FALSE(olderDone);

  std::atomic_bool newer{false};
  EXPECT_TRUE(renderer.render(image, Rect{0, 0, 240, 160}, nullptr, &newer));
  Renderer fresh(pool);
  fresh.setCamera(Camera(piece.camera, 240, 160));
  fresh.setShading(shading);
  fresh.sync(*model);
  Image reference;
  fresh.renderFull(reference);
  EXPECT_EQ(0, std::memcmp(image.rgba.data(), reference.rgba.data(), image.rgba.size()));
}

}  // namespace
}  // namespace emboss
