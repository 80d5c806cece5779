// leafNetBounds for each SIMD target Highway knows (compiled once per target by foreach_target.h),
// and the run-time choice among them.
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

// Running extremes, one per lane.
template <class V>
struct Extremes {
  V lo, hi, uLo, uHi, vLo, vHi;
};

// The patches p .. p + lanes - 1 of row c: their Bezier nets (each corner's value, plus or minus a
// third of its scaled slopes, and a ninth of its scaled twist; ((d + x) + y) + t in that order, a
// minus for a negated term: the scalar arithmetic exactly) into the extremes.
template <class D, class V>
HWY_INLINE void PatchRow(D d, const LeafSamples& s, int c, int p, Extremes<V>& e) {
  const V d00 = hn::LoadU(d, &s.d[c][p]), x00 = hn::LoadU(d, &s.x[c][p]), y00 = hn::LoadU(d, &s.y[c][p]),
          t00 = hn::LoadU(d, &s.t[c][p]);
  const V d10 = hn::LoadU(d, &s.d[c][p + 1]), x10 = hn::LoadU(d, &s.x[c][p + 1]),
          y10 = hn::LoadU(d, &s.y[c][p + 1]), t10 = hn::LoadU(d, &s.t[c][p + 1]);
  const V d01 = hn::LoadU(d, &s.d[c + 1][p]), x01 = hn::LoadU(d, &s.x[c + 1][p]),
          y01 = hn::LoadU(d, &s.y[c + 1][p]), t01 = hn::LoadU(d, &s.t[c + 1][p]);
  const V d11 = hn::LoadU(d, &s.d[c + 1][p + 1]), x11 = hn::LoadU(d, &s.x[c + 1][p + 1]),
          y11 = hn::LoadU(d, &s.y[c + 1][p + 1]), t11 = hn::LoadU(d, &s.t[c + 1][p + 1]);
  V b[4][4];
  // Corner (0, 0): +x, +y, +t.
  b[0][0] = d00;
  b[1][0] = hn::Add(d00, x00);
  b[0][1] = hn::Add(d00, y00);
  b[1][1] = hn::Add(hn::Add(hn::Add(d00, x00), y00), t00);
  // Corner (1, 0): -x, +y, -t.
  b[3][0] = d10;
  b[2][0] = hn::Sub(d10, x10);
  b[3][1] = hn::Add(d10, y10);
  b[2][1] = hn::Sub(hn::Add(hn::Sub(d10, x10), y10), t10);
  // Corner (0, 1): +x, -y, -t.
  b[0][3] = d01;
  b[1][3] = hn::Add(d01, x01);
  b[0][2] = hn::Sub(d01, y01);
  b[1][2] = hn::Sub(hn::Sub(hn::Add(d01, x01), y01), t01);
  // Corner (1, 1): -x, -y, +t.
  b[3][3] = d11;
  b[2][3] = hn::Sub(d11, x11);
  b[3][2] = hn::Sub(d11, y11);
  b[2][2] = hn::Add(hn::Sub(hn::Sub(d11, x11), y11), t11);
  const V three = hn::Set(d, 3.0);
  for (int u = 0; u < 4; ++u)
    for (int v = 0; v < 4; ++v) {
      e.lo = hn::Min(e.lo, b[u][v]), e.hi = hn::Max(e.hi, b[u][v]);
      if (u < 3) {
        const V du = hn::Mul(three, hn::Sub(b[u + 1][v], b[u][v]));
        e.uLo = hn::Min(e.uLo, du), e.uHi = hn::Max(e.uHi, du);
      }
      if (v < 3) {
        const V dv = hn::Mul(three, hn::Sub(b[u][v + 1], b[u][v]));
        e.vLo = hn::Min(e.vLo, dv), e.vHi = hn::Max(e.vHi, dv);
      }
    }
}

template <class D>
HWY_INLINE void Rows(D d, const LeafSamples& s, int p0, int p1, int patchesV, LeafNetBounds& out) {
  using V = hn::Vec<D>;
  const int lanes = static_cast<int>(hn::Lanes(d));
  const V inf = hn::Set(d, std::numeric_limits<double>::infinity()), ninf = hn::Neg(inf);
  Extremes<V> e{inf, ninf, inf, ninf, inf, ninf};
  int p = p0;
  for (; p + lanes <= p1; p += lanes)
    for (int c = 0; c < patchesV; ++c) PatchRow(d, s, c, p, e);
  out.lo = std::min(out.lo, hn::GetLane(hn::MinOfLanes(d, e.lo)));
  out.hi = std::max(out.hi, hn::GetLane(hn::MaxOfLanes(d, e.hi)));
  out.uLo = std::min(out.uLo, hn::GetLane(hn::MinOfLanes(d, e.uLo)));
  out.uHi = std::max(out.uHi, hn::GetLane(hn::MaxOfLanes(d, e.uHi)));
  out.vLo = std::min(out.vLo, hn::GetLane(hn::MinOfLanes(d, e.vLo)));
  out.vHi = std::max(out.vHi, hn::GetLane(hn::MaxOfLanes(d, e.vHi)));
  // The last patches, fewer than a vector, one lane at a time.
  if (p < p1) {
    const hn::CappedTag<double, 1> d1;
    Rows(d1, s, p, p1, patchesV, out);
  }
}

LeafNetBounds LeafBounds(const LeafSamples& s, int patchesU, int patchesV) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  LeafNetBounds out{inf, -inf, inf, -inf, inf, -inf};
  const hn::CappedTag<double, 8> d;  // loads end within a row's 16 doubles
  Rows(d, s, 0, patchesU, patchesV, out);
  return out;
}

}  // namespace HWY_NAMESPACE
}  // namespace emboss
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace emboss {

HWY_EXPORT(LeafBounds);

LeafNetBounds leafNetBounds(const LeafSamples& s, int patchesU, int patchesV) {
  return HWY_DYNAMIC_DISPATCH(LeafBounds)(s, patchesU, patchesV);
}

}  // namespace emboss
#endif
