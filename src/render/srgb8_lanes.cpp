// toSrgb8Channels for each SIMD target Highway knows (compiled once per target by
// foreach_target.h), and the run-time choice among them: toSrgb8Channel()'s lookup (srgb8.cpp),
// a vector of values at once. Only comparisons, integer sums and table reads: the same bytes on
// every target.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/srgb8_lanes.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "render/srgb8.h"

#include <cstddef>
#include <cstdint>

HWY_BEFORE_NAMESPACE();
namespace emboss {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void Srgb8Lanes(const double* x, int n, std::uint8_t* out) {
  const Srgb8Table& t = srgb8Table();
  const hn::CappedTag<double, 8> d;
  const hn::RebindToSigned<decltype(d)> di;
  const hn::RebindToUnsigned<decltype(d)> du;
  const size_t lanes = hn::Lanes(d);
  const auto low = hn::Set(di, Srgb8Table::kLowBits), buckets = hn::Set(di, Srgb8Table::kHighBits - Srgb8Table::kLowBits);
  // (Highway compares integers by Lt and Gt alone.)
  const auto one = hn::Set(di, 1), nearPlus1 = hn::Set(di, Srgb8Table::kNearSteps + 1), minusOne = hn::Set(di, -1);
  HWY_ALIGN std::int64_t bytes[8];
  size_t i = 0;
  for (; i + lanes <= static_cast<size_t>(n); i += lanes) {
    const auto v = hn::LoadU(d, x + i);
    const auto bits = hn::BitCast(di, v);
    // The bucket: a negative value's sign bit, NaN's and infinity's exponent put it past the last.
    const auto b = hn::Sub(hn::BitCast(di, hn::ShiftRight<Srgb8Table::kBucketShift>(hn::BitCast(du, v))), low);
    const auto inside = hn::And(hn::Gt(b, minusOne), hn::Lt(b, buckets));
    const auto start = hn::GatherIndex(di, t.start, hn::IfThenElseZero(inside, b));
    // The steps at or below the value past its bucket's start (the steps are sorted: a count).
    auto count = start;
    for (int k = 1; k <= t.scan; ++k) {
      const auto step = hn::GatherIndex(d, t.steps, hn::Add(start, hn::Set(di, k)));
      count = hn::Add(count, hn::IfThenElseZero(hn::RebindMask(di, hn::Le(step, v)), one));
    }
    // Near the steps on either side toSrgb8() decides (toSrgb8Channel()).
    const auto above = hn::BitCast(di, hn::GatherIndex(d, t.steps, hn::Add(count, one)));
    const auto below = hn::BitCast(di, hn::GatherIndex(d, t.steps, count));
    const auto within = [&](auto ulps) { return hn::And(hn::Gt(ulps, minusOne), hn::Lt(ulps, nearPlus1)); };
    const auto nearStep = hn::Or(within(hn::Sub(above, bits)), within(hn::Sub(bits, below)));
    const auto alone = hn::Or(hn::Not(inside), nearStep);
    hn::Store(count, di, bytes);
    for (size_t k = 0; k < lanes; ++k) out[i + k] = static_cast<std::uint8_t>(bytes[k]);
    if (hn::AllFalse(di, alone)) continue;
    HWY_ALIGN std::int64_t mask[8];
    hn::Store(hn::VecFromMask(di, alone), di, mask);
    for (size_t k = 0; k < lanes; ++k)
      if (mask[k] != 0) out[i + k] = toSrgb8Channel(x[i + k]);
  }
  for (; i < static_cast<size_t>(n); ++i) out[i] = toSrgb8Channel(x[i]);
}

}  // namespace HWY_NAMESPACE
}  // namespace emboss
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace emboss {

HWY_EXPORT(Srgb8Lanes);

void toSrgb8Channels(const double* linear, int n, std::uint8_t* out) {
  if (n > 0) HWY_DYNAMIC_DISPATCH(Srgb8Lanes)(linear, n, out);
}

}  // namespace emboss
#endif  // HWY_ONCE
