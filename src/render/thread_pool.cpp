// The fixed thread pool.
#include "render/thread_pool.h"

#include <algorithm>

#include "util/progress_beat.h"

namespace emboss {

ThreadPool::ThreadPool(int threads) {
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  for (int i = 0; i < threads - 1; ++i) workers_.emplace_back([this] { workerLoop(); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (auto& t : workers_) t.join();
}

void ThreadPool::runTiles() {
  for (;;) {
    if (cancel_ && cancel_->load(std::memory_order_relaxed)) return;
    const size_t i = next_.fetch_add(1, std::memory_order_relaxed);
    if (i >= tiles_.size()) return;
    (*func_)(tiles_[i]);
    completed_.fetch_add(1, std::memory_order_relaxed);
    progressBeat();
  }
}

void ThreadPool::workerLoop() {
  std::uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock lock(mutex_);
      // A worker that wakes late, after the job was closed, waits for the next one: it must not
      // read the tiles, the function or the cancel flag of a job that has returned.
      wake_.wait(lock, [&] { return stop_ || (jobOpen_ && generation_ != seen); });
      if (stop_) return;
      seen = generation_;
      ++busy_;
    }
    runTiles();
    {
      std::lock_guard lock(mutex_);
      --busy_;
    }
    done_.notify_all();
  }
}

bool ThreadPool::parallelFor2D(const Rect& extent, int tileSize, const std::function<void(const Rect&)>& func,
                               const std::atomic_bool* cancel) {
  if (extent.empty()) return true;
  std::lock_guard run(runMutex_);
  if (cancel && cancel->load()) return false;
  tileSize = std::max(1, tileSize);
  {
    std::lock_guard lock(mutex_);
    tiles_.clear();
    for (int y = extent.y; y < extent.y + extent.h; y += tileSize)
      for (int x = extent.x; x < extent.x + extent.w; x += tileSize)
        tiles_.push_back({x, y, std::min(tileSize, extent.x + extent.w - x), std::min(tileSize, extent.y + extent.h - y)});
    next_.store(0);
    completed_.store(0);
    func_ = &func;
    cancel_ = cancel;
    jobOpen_ = true;
    ++generation_;
  }
  if (tiles_.size() > 1) wake_.notify_all();
  runTiles();
  {
    // Close the job (no worker may join it any more), then wait for those inside it.
    std::unique_lock lock(mutex_);
    jobOpen_ = false;
    done_.wait(lock, [&] { return busy_ == 0; });
    func_ = nullptr;
    cancel_ = nullptr;
  }
  ++jobsRun_;
  return completed_.load() == tiles_.size();
}

}  // namespace emboss
