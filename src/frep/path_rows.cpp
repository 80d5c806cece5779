// nearestSegments for each SIMD target Highway knows (compiled once per target by foreach_target.h),
// and the run-time choice among them.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "frep/path_rows.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "frep/path_rows.h"

HWY_BEFORE_NAMESPACE();
namespace emboss {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// One segment's squared distance to (px + ax, py + ay), in exactly the operations of the scalar
// search (PreparedOp::pathDistance2): no fused multiply-add (the build has -ffp-contract=off and
// Highway's Mul and Add are separate instructions).
template <class D, class V>
HWY_INLINE V SegmentDistance2(D d, V px, V py, const PathSegment& g) {
  if (g.inv == 0.0) return hn::Add(hn::Mul(px, px), hn::Mul(py, py));
  const V ex = hn::Set(d, g.ex), ey = hn::Set(d, g.ey);
  V t = hn::Mul(hn::Add(hn::Mul(px, ex), hn::Mul(py, ey)), hn::Set(d, g.inv));
  t = hn::Min(hn::Max(t, hn::Zero(d)), hn::Set(d, 1.0));
  const V qx = hn::Sub(px, hn::Mul(t, ex)), qy = hn::Sub(py, hn::Mul(t, ey));
  return hn::Add(hn::Mul(qx, qx), hn::Mul(qy, qy));
}

void NearestSegments(const PathSegment* segs, std::uint32_t count, double y, const double* xs, int n,
                     std::uint32_t* best, double* bestV) {
  const hn::ScalableTag<double> d;
  const int lanes = static_cast<int>(hn::Lanes(d));
  HWY_ALIGN double index[64];  // the widest vector: 8 doubles (AVX-512), SVE at most 32
  int k = 0;
  for (; k + lanes <= n; k += lanes) {
    const auto x = hn::LoadU(d, xs + k);
    auto bv = hn::Zero(d), bi = hn::Zero(d);
    for (std::uint32_t i = 0; i < count; ++i) {
      const PathSegment& g = segs[i];
      const auto v = SegmentDistance2(d, hn::Sub(x, hn::Set(d, g.ax)), hn::Set(d, y - g.ay), g);
      if (i == 0) {
        bv = v;
        continue;
      }
      const auto take = hn::Not(hn::Le(bv, v));  // min(a, b) is b only where !(a <= b)
      bv = hn::IfThenElse(take, v, bv);
      bi = hn::IfThenElse(take, hn::Set(d, static_cast<double>(i)), bi);
    }
    hn::StoreU(bv, d, bestV + k);
    hn::Store(bi, d, index);
    for (int l = 0; l < lanes; ++l) best[k + l] = static_cast<std::uint32_t>(index[l]);
  }
  // The last points, fewer than a vector, one lane at a time.
  const hn::CappedTag<double, 1> d1;
  for (; k < n; ++k) {
    const auto x = hn::Set(d1, xs[k]);
    double bv = 0.0;
    std::uint32_t bi = 0;
    for (std::uint32_t i = 0; i < count; ++i) {
      const PathSegment& g = segs[i];
      const double v = hn::GetLane(SegmentDistance2(d1, hn::Sub(x, hn::Set(d1, g.ax)), hn::Set(d1, y - g.ay), g));
      if (i == 0 || !(bv <= v)) bv = v, bi = i;
    }
    best[k] = bi;
    bestV[k] = bv;
  }
}

const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace emboss
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace emboss {

HWY_EXPORT(NearestSegments);
HWY_EXPORT(TargetName);

void nearestSegments(std::span<const PathSegment> segments, double y, const double* xs, int n,
                     std::uint32_t* best, double* bestV) {
  if (segments.empty() || n <= 0) return;
  HWY_DYNAMIC_DISPATCH(NearestSegments)(segments.data(), static_cast<std::uint32_t>(segments.size()), y, xs, n,
                                        best, bestV);
}

const char* simdTargetName() { return HWY_DYNAMIC_DISPATCH(TargetName)(); }

}  // namespace emboss
#endif
