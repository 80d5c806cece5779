// The fixed thread pool.
#include "render/thread_pool.h"

#include <algorithm>

namespace emboss {

ThreadPool::ThreadPool(int threads) {
  if (threads <= 0) threads = std::max(1u, std::thread::hardware_concurrency());
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
  }
}

void ThreadPool::workerLoop() {
  std::uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
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
  tileSize = std::max(1, tileSize);
  {
    // No worker may still be reading the previous job's tiles while they are replaced.
    std::unique_lock lock(mutex_);
    done_.wait(lock, [&] { return busy_ == 0; });
    tiles_.clear();
    for (int y = extent.y; y < extent.y + extent.h; y += tileSize)
      for (int x = extent.x; x < extent.x + extent.w; x += tileSize)
        tiles_.push_back({x, y, std::min(tileSize, extent.x + extent.w - x), std::min(tileSize, extent.y + extent.h - y)});
    next_.store(0);
    func_ = &func;
    cancel_ = cancel;
    ++generation_;
  }
  wake_.notify_all();
  runTiles();
  {
    // Wait until every worker that picked up this generation has left runTiles().
    std::unique_lock lock(mutex_);
    done_.wait(lock, [&] { return busy_ == 0; });
    func_ = nullptr;
  }
  return !(cancel && cancel->load());
}

}  // namespace emboss
