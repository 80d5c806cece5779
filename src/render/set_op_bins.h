// The set operations' supports, and which of them meet a place: a grid of bins over the box of
// them all, each with a bit for every operation whose support meets it. A ray's set-up and a hit's
// normal read the bins under them, not every support (the sheet a visitor leaves holds 93 set
// operations, and a ray over it meets about a dozen; docs/performance.md, "Stop 60").
#pragma once

#include <bit>
#include <cstdint>
#include <vector>

#include "frep/box.h"

namespace emboss {

class SetOpBins {
 public:
  // Below this many operations there are no bins: every support is read.
  static constexpr size_t kFewest = 16;
  static constexpr int kMaxSide = 32;

  // The supports, in the set operations' order.
  void build(std::vector<Box2> supports);
  size_t size() const { return supports_.size(); }

  // Calls f(k) for each k whose support meets `box`, ascending.
  template <class F>
  void meeting(const Box2& box, F&& f) const {
    if (area_.overlaps(box))
      under(box, [&](std::uint32_t k) {
        if (supports_[k].overlaps(box)) f(k);
      });
  }
  // Calls f(k) for each k whose support holds (x, y), ascending.
  template <class F>
  void holding(double x, double y, F&& f) const {
    if (area_.contains(x, y))
      under(Box2{x, y, x, y}, [&](std::uint32_t k) {
        if (supports_[k].contains(x, y)) f(k);
      });
  }

  // Calls f(k) for the k the bins under `box` name: every k whose support meets it and maybe
  // others, ascending. Without bins: every k.
  template <class F>
  void under(const Box2& box, F&& f) const {
    if (words_ == 0) {
      for (std::uint32_t k = 0; k < supports_.size(); ++k) f(k);
      return;
    }
    const int i0 = column(box.x0), i1 = column(box.x1), j0 = row(box.y0), j1 = row(box.y1);
    for (int w = 0; w < words_; ++w) {
      std::uint64_t m = 0;
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) m |= bits_[(static_cast<size_t>(j) * nx_ + i) * words_ + w];
      for (; m != 0; m &= m - 1) f(static_cast<std::uint32_t>(w * 64 + std::countr_zero(m)));
    }
  }

 private:
  // A coordinate's bin, clamped to the grid: monotone, so a point in both a support and a box lies
  // in a bin of both.
  int column(double x) const;
  int row(double y) const;

  std::vector<Box2> supports_;  // side by side: a SetOp is two cache lines
  Box2 area_;  // the box of them all
  int nx_ = 0, ny_ = 0, words_ = 0;
  double x0_ = 0, y0_ = 0, invX_ = 0, invY_ = 0;
  std::vector<std::uint64_t> bits_;  // bin (i, j)'s words at (j nx + i) words
};

}  // namespace emboss
