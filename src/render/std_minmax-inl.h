// std::min and std::max of two lanes' values as <algorithm> defines them (b < a ? b : a and
// a < b ? b : a): the same value as the scalar code's, down to which of two equal zeros (Highway's
// Min and Max may pick the other). Shared by the targets' code of walk_lanes.cpp and ray_lanes.cpp
// (Highway's per-target header: included once for each target, after highway.h).
#if defined(EMBOSS_RENDER_STD_MINMAX_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef EMBOSS_RENDER_STD_MINMAX_INL_H_
#undef EMBOSS_RENDER_STD_MINMAX_INL_H_
#else
#define EMBOSS_RENDER_STD_MINMAX_INL_H_
#endif

#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace emboss {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

template <class V>
HWY_INLINE V MinOf(V a, V b) {
  return hn::IfThenElse(hn::Lt(b, a), b, a);
}
template <class V>
HWY_INLINE V MaxOf(V a, V b) {
  return hn::IfThenElse(hn::Lt(a, b), b, a);
}

// NOLINTNEXTLINE(google-readability-namespace-comments)
}  // namespace HWY_NAMESPACE
}  // namespace emboss
HWY_AFTER_NAMESPACE();

#endif  // EMBOSS_RENDER_STD_MINMAX_INL_H_
