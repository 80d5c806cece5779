// The field's Hermite patch in SIMD lanes, shared by the targets' code of field_lanes.cpp and
// walk_lanes.cpp (Highway's per-target header: included once for each target, after highway.h,
// by a file that foreach_target.h compiles once per target). Each helper mirrors the one-point
// code of HeightField in the same operations and order, so the same bits.
#if defined(EMBOSS_RENDER_HERMITE_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef EMBOSS_RENDER_HERMITE_INL_H_
#undef EMBOSS_RENDER_HERMITE_INL_H_
#else
#define EMBOSS_RENDER_HERMITE_INL_H_
#endif

#include <cstddef>
#include <cstdint>

#include "hwy/highway.h"
#include "render/field_lanes.h"

HWY_BEFORE_NAMESPACE();
namespace emboss {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The cells of the lanes' points (fx, fy in cells from the lattice's origin): i = clamp(int(fx), 0,
// nx - 2) (the conversion truncates, as the cast does) and u = fx - i, likewise j and w; and each
// lane's first sample, j nx + i, stored for the reads lane by lane (a gather by another name).
template <class D, class V = hn::Vec<D>>
HWY_INLINE void Cells(D d, V fx, V fy, int nx, int ny, V& u, V& w, int32_t* first) {
  const hn::Rebind<int32_t, D> di;
  const auto zero = hn::Zero(di);
  const auto i = hn::Min(hn::Max(hn::DemoteTo(di, fx), zero), hn::Set(di, nx - 2));
  const auto j = hn::Min(hn::Max(hn::DemoteTo(di, fy), zero), hn::Set(di, ny - 2));
  u = hn::Sub(fx, hn::PromoteTo(d, i)), w = hn::Sub(fy, hn::PromoteTo(d, j));
  hn::StoreU(hn::Add(hn::Mul(j, hn::Set(di, nx)), i), di, first);
}

// The four corners' samples (00, 10, 01, 11) of each lane's cell, four floats each (d, dD/dx,
// dD/dy, twist), read lane by lane into c[0..15][lane] (first[lane]: the cell's first sample).
template <class T, size_t kLanes>
HWY_INLINE void ReadCorners(const SampleLattice& l, const int32_t* first, size_t lanes, T (*c)[kLanes]) {
  for (size_t k = 0; k < lanes; ++k) {
    const float* r0 = l.samples + static_cast<size_t>(static_cast<uint32_t>(first[k])) * 4;
    const float* r1 = r0 + static_cast<size_t>(l.nx) * 4;
    for (int m = 0; m < 4; ++m) {
      c[m][k] = r0[m], c[4 + m][k] = r0[4 + m];
      c[8 + m][k] = r1[m], c[12 + m][k] = r1[4 + m];
    }
  }
}

// The bicubic Hermite basis at u, and its derivative (height_field.cpp's basis() and
// basisDerivative(), the same operations in the same order).
template <class V>
HWY_INLINE void Basis(V u, V& h0, V& h1, V& g0, V& g1) {
  const hn::DFromV<V> d;
  const V one = hn::Set(d, 1.0), two = hn::Set(d, 2.0), three = hn::Set(d, 3.0);
  const V u2 = hn::Mul(u, u);
  h0 = hn::Add(hn::Mul(hn::Sub(hn::Mul(two, u), three), u2), one);
  h1 = hn::Mul(hn::Sub(three, hn::Mul(two, u)), u2);
  g0 = hn::Mul(hn::Add(hn::Mul(hn::Sub(u, two), u), one), u);
  g1 = hn::Mul(hn::Sub(u, one), u2);
}
template <class V>
HWY_INLINE void BasisDerivative(V u, V& h0, V& h1, V& g0, V& g1) {
  const hn::DFromV<V> d;
  const V one = hn::Set(d, 1.0);
  const V d0 = hn::Mul(hn::Mul(hn::Set(d, 6.0), u), hn::Sub(u, one));
  h0 = d0, h1 = hn::Neg(d0);
  g0 = hn::Add(hn::Mul(hn::Sub(hn::Mul(hn::Set(d, 3.0), u), hn::Set(d, 4.0)), u), one);
  g1 = hn::Mul(hn::Sub(hn::Mul(hn::Set(d, 3.0), u), hn::Set(d, 2.0)), u);
}

// h0 p + h1 q + s (g0 r + g1 t): a row of the patch (valueAndGradient's rowD and rowY).
template <class V>
HWY_INLINE V Row(V h0, V h1, V g0, V g1, V s, V p, V q, V r, V t) {
  return hn::Add(hn::Add(hn::Mul(h0, p), hn::Mul(h1, q)), hn::Mul(s, hn::Add(hn::Mul(g0, r), hn::Mul(g1, t))));
}

// NOLINTNEXTLINE(google-readability-namespace-comments)
}  // namespace HWY_NAMESPACE
}  // namespace emboss
HWY_AFTER_NAMESPACE();

#endif  // EMBOSS_RENDER_HERMITE_INL_H_
