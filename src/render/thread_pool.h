// A fixed pool of worker threads, created once, that runs a function over the tiles of a region.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "render/image.h"

namespace emboss {

// The pool starts `threads - 1` workers at construction and keeps them until destruction (the
// thread calling parallelFor2D() is the last of the `threads`): no thread is created per frame.
// parallelFor2D() splits a rectangle into tiles, row-major, and hands them out to the workers and
// the calling thread; it returns when every tile is done or, once `cancel` is set (from any
// thread), as soon as the tiles already started finish: the rest are skipped and it returns
// false. A newer frame supersedes one in flight by setting the older frame's flag. One
// parallelFor2D() runs at a time (calls from several threads are serialised); `func` is called
// concurrently for different tiles and must be thread-safe. No worker touches `func` or `cancel`
// after parallelFor2D() has returned.
class ThreadPool {
 public:
  explicit ThreadPool(int threads = 0);  // 0: one thread per core
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int size() const { return static_cast<int>(workers_.size()) + 1; }  // workers plus the caller
  // Returns false when cancelled before every tile ran.
  bool parallelFor2D(const Rect& extent, int tileSize, const std::function<void(const Rect&)>& func,
                     const std::atomic_bool* cancel = nullptr);
  // How many parallelFor2D() jobs have run (for tests: the pool is reused, never rebuilt).
  std::uint64_t jobsRun() const { return jobsRun_.load(); }

 private:
  void workerLoop();
  void runTiles();

  std::vector<std::thread> workers_;
  std::mutex runMutex_;  // serialises parallelFor2D callers
  std::mutex mutex_;     // guards everything below except next_
  std::condition_variable wake_, done_;
  std::uint64_t generation_ = 0;
  bool jobOpen_ = false;  // workers may join the job in flight only while it is open
  int busy_ = 0;          // workers inside runTiles()
  bool stop_ = false;
  // The job in flight.
  std::vector<Rect> tiles_;
  std::atomic<size_t> next_{0};
  std::atomic<size_t> completed_{0};
  const std::function<void(const Rect&)>* func_ = nullptr;
  const std::atomic_bool* cancel_ = nullptr;
  std::atomic<std::uint64_t> jobsRun_{0};
};

}  // namespace emboss
