// The patina strokes' amounts at the nodes of a lattice over the sheet, kept block by block: a hit
// reads its cell's four nodes instead of the distance to every stroke over it (docs/rendering.md,
// "The patina's lattice").
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <memory>

#include "frep/box.h"
#include "frep/operation.h"

namespace emboss {

class PatinaCache {
 public:
  // mm between nodes: a brush's amount, strength (1 - (d/r)^4)^2, is smooth, and bilinear between
  // nodes this far apart it is within 3.6 % of the strength of the exact one for the narrowest
  // brush kept (kMinReach), 0.8 % for one of 5 mm (docs/rendering.md).
  static constexpr double kSpacing = 0.25;
  static constexpr int kBlockCells = 16;                  // a block's cells along x and along y
  static constexpr int kBlockNodes = kBlockCells + 1;     // its nodes along each (the edges' twice)
  static constexpr int kTinges = 4;                       // black, brown, green, golden (Operation::tinge 1..4)
  static constexpr size_t kBlockFloats = static_cast<size_t>(kBlockNodes) * kBlockNodes * kTinges;
  // Brushes narrower than this are not kept on the lattice: each hit works theirs out exactly.
  static constexpr double kMinReach = 8.0 * kSpacing;

  // Whether `op`'s amounts are the lattice's.
  static bool kept(const Operation& op) { return op.isPatina() && op.a >= kMinReach; }

  PatinaCache() = default;
  ~PatinaCache() { clear(); }
  PatinaCache(const PatinaCache&) = delete;
  PatinaCache& operator=(const PatinaCache&) = delete;

  // The lattice over `domain` (its nodes from its low corner, kSpacing apart, over it). Returns
  // false and forgets every block if the domain differs from the last one.
  bool configure(const Box2& domain);
  // Forgets every block (none is worked out until read again).
  void clear();
  // Forgets the blocks with a node within `region` (call with no read under way).
  void invalidate(const Box2& region);
  // Whether (x, y) lies in the lattice's cells.
  bool covers(double x, double y) const {
    return nx_ > 0 && x >= domain_.x0 && y >= domain_.y0 && x <= xMax_ && y <= yMax_;
  }
  // A node's coordinates (by its indices from the low corner: the same bits from every block).
  double nodeX(int i) const { return domain_.x0 + static_cast<double>(i) * kSpacing; }
  double nodeY(int j) const { return domain_.y0 + static_cast<double>(j) * kSpacing; }

  // The amounts of the kept strokes at (x, y), which covers() holds, by tinge (out[0] black ..
  // out[3] golden): the bilinear interpolation of its cell's nodes. A block not yet worked out is
  // worked out by `fill(i0, j0, values)` (its first node's indices; kBlockFloats values, node by
  // node along x then y, kTinges each; false, without writing them: no kept stroke reaches the
  // block, whose amounts are all 0 and take no memory), which may run on several threads at once
  // for one block: the first to finish keeps its values (each gives the same).
  template <class Fill>
  void at(double x, double y, const Fill& fill, double out[kTinges]) const {
    const double u = (x - domain_.x0) * kInv, v = (y - domain_.y0) * kInv;
    const int i = std::min(static_cast<int>(u), nx_ - 1), j = std::min(static_cast<int>(v), ny_ - 1);
    const double fx = u - i, fy = v - j;
    const int bi = i / kBlockCells, bj = j / kBlockCells;
    std::atomic<float*>& slot = blocks_[static_cast<size_t>(bj) * bx_ + bi];
    float* block = slot.load(std::memory_order_acquire);
    if (!block) block = workOut(slot, bi, bj, fill);
    const int li = i - bi * kBlockCells, lj = j - bj * kBlockCells;
    const float* a = block + (static_cast<size_t>(lj) * kBlockNodes + li) * kTinges;
    const float* b = a + kTinges;
    const float* c = a + static_cast<size_t>(kBlockNodes) * kTinges;
    const float* d = c + kTinges;
    for (int t = 0; t < kTinges; ++t) {
      const double lo = a[t] + fx * (static_cast<double>(b[t]) - a[t]);
      const double hi = c[t] + fx * (static_cast<double>(d[t]) - c[t]);
      out[t] = lo + fy * (hi - lo);
    }
  }

  size_t memoryBytes() const { return allocated_.load() * kBlockFloats * sizeof(float); }
  // The blocks worked out that hold a stroke's amounts (the others share one block of zeros).
  size_t blocksWorkedOut() const { return allocated_.load(); }

 private:
  static constexpr double kInv = 1.0 / kSpacing;
  // The block of a region no kept stroke reaches (shared, never written).
  static float* zeroBlock() {
    alignas(64) static float zeros[kBlockFloats] = {};
    return zeros;
  }
  template <class Fill>
  float* workOut(std::atomic<float*>& slot, int bi, int bj, const Fill& fill) const {
    thread_local std::unique_ptr<float[]> scratch;
    if (!scratch) scratch = std::make_unique<float[]>(kBlockFloats);
    float* expected = nullptr;
    if (!fill(bi * kBlockCells, bj * kBlockCells, scratch.get())) {
      if (slot.compare_exchange_strong(expected, zeroBlock(), std::memory_order_acq_rel)) return zeroBlock();
      return expected;
    }
    auto values = std::make_unique<float[]>(kBlockFloats);
    std::copy(scratch.get(), scratch.get() + kBlockFloats, values.get());
    if (slot.compare_exchange_strong(expected, values.get(), std::memory_order_acq_rel)) {
      ++allocated_;
      return values.release();
    }
    return expected;  // another thread's, the same values
  }
  static void release(float* block) {
    if (block != zeroBlock()) delete[] block;
  }

  Box2 domain_{};
  double xMax_ = 0.0, yMax_ = 0.0;  // the last nodes
  int nx_ = 0, ny_ = 0;             // cells along x and y
  int bx_ = 0, by_ = 0;             // blocks along x and y
  std::unique_ptr<std::atomic<float*>[]> blocks_;
  mutable std::atomic<size_t> allocated_{0};
};

}  // namespace emboss
