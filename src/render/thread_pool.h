// A fixed pool of worker threads, created once, that runs a function over the tiles of a region.
#pragma once

#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "render/image.h"

namespace emboss {

// The pool starts `threads` workers at construction and keeps them until destruction: no thread is
// created per frame. parallelFor2D() splits a rectangle into tiles and hands them out to the
// workers and the calling thread; it returns when every tile is done or, once `cancel` is set, as
// soon as the tiles already started finish (the rest are skipped). One parallelFor2D() at a time
// (calls from several threads are serialised).
class ThreadPool {
 public:
  explicit ThreadPool(int threads = 0);  // 0: one worker per core
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int size() const { return static_cast<int>(workers_.size()) + 1; }  // workers plus the caller
  // Returns false when cancelled before every tile ran.
  bool parallelFor2D(const Rect& extent, int tileSize, const std::function<void(const Rect&)>& func,
                     const std::atomic_bool* cancel = nullptr);

 private:
  void workerLoop();
  void runTiles();

  std::vector<std::thread> workers_;
  std::mutex runMutex_;  // serialises parallelFor2D callers
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::uint64_t generation_ = 0;
  int busy_ = 0;
  bool stop_ = false;
  // The job in flight.
  std::vector<Rect> tiles_;
  std::atomic<size_t> next_{0};
  const std::function<void(const Rect&)>* func_ = nullptr;
  const std::atomic_bool* cancel_ = nullptr;
};

}  // namespace emboss
