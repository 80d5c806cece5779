// tapSumsLanes for each SIMD target Highway knows (compiled once per target by foreach_target.h),
// and the run-time choice among them: the cavity filter of a row of samples (field_lanes.h), a
// vector of samples at once. Float products and sums in the taps' order, each rounded as the
// scalar loop rounds it: the same bits on every target and in the scalar tail.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/cavity_lanes.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "render/field_lanes.h"

#include <cstddef>

HWY_BEFORE_NAMESPACE();
namespace emboss {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void TapSumsLanes(const float* const* rows, const float* w, int taps, const float* own, int n, float* out) {
  const hn::ScalableTag<float> d;
  const size_t lanes = hn::Lanes(d);
  const size_t count = static_cast<size_t>(n);
  size_t k = 0;
  for (; k + lanes <= count; k += lanes) {
    auto acc = hn::Zero(d);
    for (int t = 0; t < taps; ++t) acc = hn::Add(acc, hn::Mul(hn::Set(d, w[t]), hn::LoadU(d, rows[t] + k)));
    hn::StoreU(hn::Sub(acc, hn::LoadU(d, own + k)), d, out + k);
  }
  for (; k < count; ++k) {
    float acc = 0.0f;
    for (int t = 0; t < taps; ++t) acc += w[t] * rows[t][k];
    out[k] = acc - own[k];
  }
}

// NOLINTNEXTLINE(google-readability-namespace-comments)
}  // namespace HWY_NAMESPACE
}  // namespace emboss
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace emboss {

HWY_EXPORT(TapSumsLanes);

void tapSumsLanes(const float* const* rows, const float* w, int taps, const float* own, int n, float* out) {
  if (n > 0) HWY_DYNAMIC_DISPATCH(TapSumsLanes)(rows, w, taps, own, n, out);
}

}  // namespace emboss
#endif  // HWY_ONCE
