// The set operations' bins (set_op_bins.h).
#include "render/set_op_bins.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace emboss {

void SetOpBins::build(std::vector<Box2> supportsIn) {
  supports_ = std::move(supportsIn);
  area_ = Box2{};
  for (const Box2& s : supports_) area_.extend(s);
  bits_.clear();
  words_ = 0;
  if (supports_.size() < kFewest || area_.empty()) return;
  // Square bins about as many as the operations, at most kMaxSide a side.
  const double w = area_.x1 - area_.x0, h = area_.y1 - area_.y0;
  const double side = std::sqrt(std::max(w * h, 1e-12) / static_cast<double>(supports_.size()));
  nx_ = std::clamp(static_cast<int>(std::ceil(w / side)), 1, kMaxSide);
  ny_ = std::clamp(static_cast<int>(std::ceil(h / side)), 1, kMaxSide);
  x0_ = area_.x0, y0_ = area_.y0;
  invX_ = w > 0.0 ? nx_ / w : 0.0, invY_ = h > 0.0 ? ny_ / h : 0.0;
  words_ = static_cast<int>((supports_.size() + 63) / 64);
  bits_.assign(static_cast<size_t>(nx_) * ny_ * words_, 0);
  for (size_t k = 0; k < supports_.size(); ++k) {
    const Box2& s = supports_[k];
    if (s.empty()) continue;  // (meets nothing)
    const int i0 = column(s.x0), i1 = column(s.x1), j0 = row(s.y0), j1 = row(s.y1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i)
        bits_[(static_cast<size_t>(j) * nx_ + i) * words_ + k / 64] |= std::uint64_t{1} << (k % 64);
  }
}

int SetOpBins::column(double x) const {
  const double u = (x - x0_) * invX_;
  return !(u > 0.0) ? 0 : u >= nx_ - 1 ? nx_ - 1 : static_cast<int>(u);  // (NaN: the first)
}

int SetOpBins::row(double y) const {
  const double v = (y - y0_) * invY_;
  return !(v > 0.0) ? 0 : v >= ny_ - 1 ? ny_ - 1 : static_cast<int>(v);
}

}  // namespace emboss
