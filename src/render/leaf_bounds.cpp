// leafNetBounds, loadLeafSamples and twistRow for each SIMD target Highway knows (compiled once per
// target by foreach_target.h), and the run-time choice among them.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/leaf_bounds.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "render/leaf_bounds.h"

#include <algorithm>
#include <limits>

HWY_BEFORE_NAMESPACE();
namespace emboss {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Running extremes, one per lane, are passed as six vectors (SVE's sizeless vectors can be
// neither members nor array elements).
template <class V>
HWY_INLINE void Extend(V v, V& lo, V& hi) {
  lo = hn::Min(lo, v), hi = hn::Max(hi, v);
}

// 3 (b - a): a difference of the net, into its extremes.
template <class D, class V>
HWY_INLINE void ExtendDiff(D d, V a, V b, V& lo, V& hi) {
  Extend(hn::Mul(hn::Set(d, 3.0), hn::Sub(b, a)), lo, hi);
}

// The patches p .. p + lanes - 1 of row c: their Bezier nets b<u><v> (each corner's value, plus or
// minus a third of its scaled slopes, and a ninth of its scaled twist; ((d + x) + y) + t in that
// order, a minus for a negated term: the scalar arithmetic exactly) into the extremes.
template <class D, class V>
HWY_INLINE void PatchRow(D d, const LeafSamples& s, int c, int p, V& lo, V& hi, V& uLo, V& uHi, V& vLo, V& vHi) {
  // Corner (0, 0): +x, +y, +t.
  const V d00 = hn::LoadU(d, &s.d[c][p]), x00 = hn::LoadU(d, &s.x[c][p]);
  const V b00 = d00, b10 = hn::Add(d00, x00), b01 = hn::Add(d00, hn::LoadU(d, &s.y[c][p]));
  const V b11 = hn::Add(hn::Add(b10, hn::LoadU(d, &s.y[c][p])), hn::LoadU(d, &s.t[c][p]));
  // Corner (1, 0): -x, +y, -t.
  const V d10 = hn::LoadU(d, &s.d[c][p + 1]), x10 = hn::LoadU(d, &s.x[c][p + 1]);
  const V b30 = d10, b20 = hn::Sub(d10, x10), b31 = hn::Add(d10, hn::LoadU(d, &s.y[c][p + 1]));
  const V b21 = hn::Sub(hn::Add(b20, hn::LoadU(d, &s.y[c][p + 1])), hn::LoadU(d, &s.t[c][p + 1]));
  // Corner (0, 1): +x, -y, -t.
  const V d01 = hn::LoadU(d, &s.d[c + 1][p]), x01 = hn::LoadU(d, &s.x[c + 1][p]);
  const V b03 = d01, b13 = hn::Add(d01, x01), b02 = hn::Sub(d01, hn::LoadU(d, &s.y[c + 1][p]));
  const V b12 = hn::Sub(hn::Sub(b13, hn::LoadU(d, &s.y[c + 1][p])), hn::LoadU(d, &s.t[c + 1][p]));
  // Corner (1, 1): -x, -y, +t.
  const V d11 = hn::LoadU(d, &s.d[c + 1][p + 1]), x11 = hn::LoadU(d, &s.x[c + 1][p + 1]);
  const V b33 = d11, b23 = hn::Sub(d11, x11), b32 = hn::Sub(d11, hn::LoadU(d, &s.y[c + 1][p + 1]));
  const V b22 = hn::Add(hn::Sub(b23, hn::LoadU(d, &s.y[c + 1][p + 1])), hn::LoadU(d, &s.t[c + 1][p + 1]));
  Extend(b00, lo, hi), Extend(b10, lo, hi), Extend(b20, lo, hi), Extend(b30, lo, hi);
  Extend(b01, lo, hi), Extend(b11, lo, hi), Extend(b21, lo, hi), Extend(b31, lo, hi);
  Extend(b02, lo, hi), Extend(b12, lo, hi), Extend(b22, lo, hi), Extend(b32, lo, hi);
  Extend(b03, lo, hi), Extend(b13, lo, hi), Extend(b23, lo, hi), Extend(b33, lo, hi);
  // Along u: 3 (b<u+1><v> - b<u><v>).
  ExtendDiff(d, b00, b10, uLo, uHi), ExtendDiff(d, b10, b20, uLo, uHi), ExtendDiff(d, b20, b30, uLo, uHi);
  ExtendDiff(d, b01, b11, uLo, uHi), ExtendDiff(d, b11, b21, uLo, uHi), ExtendDiff(d, b21, b31, uLo, uHi);
  ExtendDiff(d, b02, b12, uLo, uHi), ExtendDiff(d, b12, b22, uLo, uHi), ExtendDiff(d, b22, b32, uLo, uHi);
  ExtendDiff(d, b03, b13, uLo, uHi), ExtendDiff(d, b13, b23, uLo, uHi), ExtendDiff(d, b23, b33, uLo, uHi);
  // Along v: 3 (b<u><v+1> - b<u><v>).
  ExtendDiff(d, b00, b01, vLo, vHi), ExtendDiff(d, b01, b02, vLo, vHi), ExtendDiff(d, b02, b03, vLo, vHi);
  ExtendDiff(d, b10, b11, vLo, vHi), ExtendDiff(d, b11, b12, vLo, vHi), ExtendDiff(d, b12, b13, vLo, vHi);
  ExtendDiff(d, b20, b21, vLo, vHi), ExtendDiff(d, b21, b22, vLo, vHi), ExtendDiff(d, b22, b23, vLo, vHi);
  ExtendDiff(d, b30, b31, vLo, vHi), ExtendDiff(d, b31, b32, vLo, vHi), ExtendDiff(d, b32, b33, vLo, vHi);
}

// The patches p0 .. p1 - 1 of every row, a vector at a time while a whole vector fits, into out;
// returns the first patch not done.
template <class D>
HWY_INLINE int Rows(D d, const LeafSamples& s, int p0, int p1, int patchesV, LeafNetBounds& out) {
  using V = hn::Vec<D>;
  const int lanes = static_cast<int>(hn::Lanes(d));
  const V inf = hn::Set(d, std::numeric_limits<double>::infinity()), ninf = hn::Neg(inf);
  V lo = inf, hi = ninf, uLo = inf, uHi = ninf, vLo = inf, vHi = ninf;
  int p = p0;
  for (; p + lanes <= p1; p += lanes)
    for (int c = 0; c < patchesV; ++c) PatchRow(d, s, c, p, lo, hi, uLo, uHi, vLo, vHi);
  out.lo = std::min(out.lo, hn::GetLane(hn::MinOfLanes(d, lo)));
  out.hi = std::max(out.hi, hn::GetLane(hn::MaxOfLanes(d, hi)));
  out.uLo = std::min(out.uLo, hn::GetLane(hn::MinOfLanes(d, uLo)));
  out.uHi = std::max(out.uHi, hn::GetLane(hn::MaxOfLanes(d, uHi)));
  out.vLo = std::min(out.vLo, hn::GetLane(hn::MinOfLanes(d, vLo)));
  out.vHi = std::max(out.vHi, hn::GetLane(hn::MaxOfLanes(d, vHi)));
  return p;
}

LeafNetBounds LeafBounds(const LeafSamples& s, int patchesU, int patchesV) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  LeafNetBounds out{inf, -inf, inf, -inf, inf, -inf};
  const hn::CappedTag<double, 8> d;  // loads end within a row's 16 doubles
  const int p = Rows(d, s, 0, patchesU, patchesV, out);
  // The last patches, fewer than a vector, one lane at a time.
  if (p < patchesU) Rows(hn::CappedTag<double, 1>(), s, p, patchesU, patchesV, out);
  return out;
}

// Samples a .. a + lanes - 1 of a row, deinterleaved and widened, into row c of s.
template <class DD>
HWY_INLINE void LoadSamples(DD dd, const float* row, int a, double spacing, LeafSamples& s, int c) {
  const hn::Rebind<float, DD> df;
  hn::Vec<decltype(df)> d, dx, dy, dxy;
  hn::LoadInterleaved4(df, row + 4 * a, d, dx, dy, dxy);
  const auto sp = hn::Set(dd, spacing), sp2 = hn::Set(dd, spacing * spacing);
  hn::StoreU(hn::PromoteTo(dd, d), dd, &s.d[c][a]);
  hn::StoreU(hn::Div(hn::Mul(sp, hn::PromoteTo(dd, dx)), hn::Set(dd, 3.0)), dd, &s.x[c][a]);
  hn::StoreU(hn::Div(hn::Mul(sp, hn::PromoteTo(dd, dy)), hn::Set(dd, 3.0)), dd, &s.y[c][a]);
  hn::StoreU(hn::Div(hn::Mul(sp2, hn::PromoteTo(dd, dxy)), hn::Set(dd, 9.0)), dd, &s.t[c][a]);
}

void LoadLeaf(const float* first, long rowFloats, int samplesU, int samplesV, double spacing, LeafSamples& s) {
  const hn::CappedTag<double, 8> dd;  // stores end within a row's 16 doubles
  const int lanes = static_cast<int>(hn::Lanes(dd));
  for (int c = 0; c < samplesV; ++c) {
    const float* row = first + c * rowFloats;
    int a = 0;
    for (; a + lanes <= samplesU; a += lanes) LoadSamples(dd, row, a, spacing, s, c);
    for (; a < samplesU; ++a) LoadSamples(hn::CappedTag<double, 1>(), row, a, spacing, s, c);
  }
}

// The rows above and below may be another thread's, whose twists it is writing: only their dx
// floats are read, one at a time, never the twists beside them. (A gather instruction would do it;
// QEMU 7.2's emulation of AVX2's gathers returns wrong values, and the appliance's boot test runs
// there.) The row's own samples are this thread's.
template <class DD>
HWY_INLINE void Twists(DD dd, const float* below, const float* row, const float* above, int k, double den, float* out) {
  const hn::Rebind<float, DD> df;
  const int lanes = static_cast<int>(hn::Lanes(df));  // at most 8 (CappedTag)
  HWY_ALIGN float belowDx[8], aboveDx[8];
  for (int l = 0; l < lanes; ++l) belowDx[l] = below[4 * (k + l) + 1], aboveDx[l] = above[4 * (k + l) + 1];
  const auto dxBelow = hn::LoadU(df, belowDx), dxAbove = hn::LoadU(df, aboveDx);
  hn::Vec<decltype(df)> d, dyPrev, dyNext, skip;
  hn::LoadInterleaved4(df, row + 4 * (k - 1), d, skip, dyPrev, skip);
  hn::LoadInterleaved4(df, row + 4 * (k + 1), d, skip, dyNext, skip);
  const auto dn = hn::Set(dd, den);
  const auto dxy = hn::Div(hn::Sub(hn::PromoteTo(dd, dxAbove), hn::PromoteTo(dd, dxBelow)), dn);
  const auto dyx = hn::Div(hn::Sub(hn::PromoteTo(dd, dyNext), hn::PromoteTo(dd, dyPrev)), dn);
  hn::StoreU(hn::DemoteTo(df, hn::Mul(hn::Set(dd, 0.5), hn::Add(dxy, dyx))), df, out + k);
}

void TwistRow(const float* below, const float* row, const float* above, int n, double den, float* out) {
  const hn::CappedTag<double, 8> dd;
  const int lanes = static_cast<int>(hn::Lanes(dd));
  int k = 0;
  for (; k + lanes <= n; k += lanes) Twists(dd, below, row, above, k, den, out);
  for (; k < n; ++k) Twists(hn::CappedTag<double, 1>(), below, row, above, k, den, out);
}

}  // namespace HWY_NAMESPACE
}  // namespace emboss
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace emboss {

HWY_EXPORT(LeafBounds);
HWY_EXPORT(LoadLeaf);
HWY_EXPORT(TwistRow);

void twistRow(const float* below, const float* row, const float* above, int n, double den, float* out) {
  HWY_DYNAMIC_DISPATCH(TwistRow)(below, row, above, n, den, out);
}

void loadLeafSamples(const float* first, long rowFloats, int samplesU, int samplesV, double spacing, LeafSamples& s) {
  HWY_DYNAMIC_DISPATCH(LoadLeaf)(first, rowFloats, samplesU, samplesV, spacing, s);
}

LeafNetBounds leafNetBounds(const LeafSamples& s, int patchesU, int patchesV) {
  return HWY_DYNAMIC_DISPATCH(LeafBounds)(s, patchesU, patchesV);
}

}  // namespace emboss
#endif
