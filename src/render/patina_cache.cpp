// The patina's lattice (patina_cache.h): its blocks made and forgotten.
#include "render/patina_cache.h"

#include <algorithm>

namespace emboss {

bool PatinaCache::configure(const Box2& domain) {
  if (blocks_ && domain.x0 == domain_.x0 && domain.y0 == domain_.y0 && domain.x1 == domain_.x1 &&
      domain.y1 == domain_.y1)
    return true;
  clear();
  domain_ = domain;
  nx_ = std::max(1, static_cast<int>(std::ceil((domain.x1 - domain.x0) * kInv)));
  ny_ = std::max(1, static_cast<int>(std::ceil((domain.y1 - domain.y0) * kInv)));
  xMax_ = nodeX(nx_), yMax_ = nodeY(ny_);
  bx_ = (nx_ + kBlockCells - 1) / kBlockCells;
  by_ = (ny_ + kBlockCells - 1) / kBlockCells;
  blocks_ = std::make_unique<std::atomic<float*>[]>(static_cast<size_t>(bx_) * by_);
  for (size_t k = 0; k < static_cast<size_t>(bx_) * by_; ++k) blocks_[k].store(nullptr, std::memory_order_relaxed);
  return false;
}

void PatinaCache::clear() {
  if (!blocks_) return;
  for (size_t k = 0; k < static_cast<size_t>(bx_) * by_; ++k)
    if (float* b = blocks_[k].exchange(nullptr)) release(b);
  allocated_ = 0;
}

void PatinaCache::invalidate(const Box2& region) {
  if (!blocks_) return;
  // The blocks whose nodes' span meets the region (a block's last nodes are its neighbour's first).
  const double span = kBlockCells * kSpacing;
  const int i0 = std::clamp(static_cast<int>(std::floor((region.x0 - domain_.x0) / span)) - 1, 0, bx_ - 1);
  const int i1 = std::clamp(static_cast<int>(std::floor((region.x1 - domain_.x0) / span)) + 1, 0, bx_ - 1);
  const int j0 = std::clamp(static_cast<int>(std::floor((region.y0 - domain_.y0) / span)) - 1, 0, by_ - 1);
  const int j1 = std::clamp(static_cast<int>(std::floor((region.y1 - domain_.y0) / span)) + 1, 0, by_ - 1);
  if (region.x1 < domain_.x0 || region.y1 < domain_.y0 || region.x0 > xMax_ || region.y0 > yMax_) return;
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i)
      if (float* b = blocks_[static_cast<size_t>(j) * bx_ + i].exchange(nullptr); b && b != zeroBlock()) {
        delete[] b;
        --allocated_;
      }
}

}  // namespace emboss
