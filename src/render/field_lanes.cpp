// bilinearLanes and hermiteLanes for each SIMD target Highway knows (compiled once per target by
// foreach_target.h), and the run-time choice among them. The lanes mirror HeightField::bilinear
// and HeightField::valueAndGradient line by line.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/field_lanes.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "render/field_lanes.h"
#include "render/hermite-inl.h"

#include <cstddef>
#include <cstdint>

HWY_BEFORE_NAMESPACE();
namespace emboss {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

constexpr size_t kMaxLanes = 32;  // doubles in the widest vector (SVE, 2048 bits)

int BilinearLanes(const FloatLattice& l, const double* xs, const double* ys, int n, double* out) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const int lanes = static_cast<int>(hn::Lanes(d));
  HWY_ALIGN int32_t first[kMaxLanes];
  HWY_ALIGN double t[4][kMaxLanes];
  const V x0 = hn::Set(d, l.x0), y0 = hn::Set(d, l.y0), invS = hn::Set(d, l.invS), zero = hn::Zero(d);
  const V xMax = hn::Set(d, l.nx - 1.0), yMax = hn::Set(d, l.ny - 1.0);
  int k = 0;
  for (; k + lanes <= n; k += lanes) {
    // std::clamp((x - x0) invS, 0, nx - 1), and the cell below it (at most the last one: the
    // point is not below the first, so min(int(fx), nx - 2) is the clamp).
    const V fx = hn::Min(hn::Max(hn::Mul(hn::Sub(hn::LoadU(d, xs + k), x0), invS), zero), xMax);
    const V fy = hn::Min(hn::Max(hn::Mul(hn::Sub(hn::LoadU(d, ys + k), y0), invS), zero), yMax);
    V u, v;
    Cells(d, fx, fy, l.nx, l.ny, u, v, first);
    for (int q = 0; q < lanes; ++q) {
      const float* r0 = l.values + static_cast<size_t>(static_cast<uint32_t>(first[q]));
      const float* r1 = r0 + l.nx;
      // The differences of neighbours in float, as the one-point read's floats subtract.
      t[0][q] = r0[0], t[1][q] = r0[1] - r0[0], t[2][q] = r1[0], t[3][q] = r1[1] - r1[0];
    }
    // a = g(k0) + u (g(k0 + 1) - g(k0)), b likewise a row on, a + v (b - a).
    const V a = hn::Add(hn::LoadU(d, t[0]), hn::Mul(u, hn::LoadU(d, t[1])));
    const V b = hn::Add(hn::LoadU(d, t[2]), hn::Mul(u, hn::LoadU(d, t[3])));
    hn::StoreU(hn::Add(a, hn::Mul(v, hn::Sub(b, a))), d, out + k);
  }
  return k;
}

int HermiteLanes(const SampleLattice& l, const double* xs, const double* ys, int n, double* outV, double* outGx,
                 double* outGy) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const int lanes = static_cast<int>(hn::Lanes(d));
  HWY_ALIGN int32_t first[kMaxLanes];
  // The four corners' samples (00, 10, 01, 11), four floats each, lane by lane.
  HWY_ALIGN double t[16][kMaxLanes];
  const V x0 = hn::Set(d, l.x0), y0 = hn::Set(d, l.y0), invS = hn::Set(d, l.invS), s = hn::Set(d, l.s);
  int k = 0;
  for (; k + lanes <= n; k += lanes) {
    const V fx = hn::Mul(hn::Sub(hn::LoadU(d, xs + k), x0), invS), fy = hn::Mul(hn::Sub(hn::LoadU(d, ys + k), y0), invS);
    V u, w;
    Cells(d, fx, fy, l.nx, l.ny, u, w, first);
    ReadCorners(l, first, static_cast<size_t>(lanes), t);
    // (Fields named one by one: SVE's sizeless vectors cannot be array elements.)
    const V d00 = hn::LoadU(d, t[0]), x00 = hn::LoadU(d, t[1]), y00 = hn::LoadU(d, t[2]), t00 = hn::LoadU(d, t[3]);
    const V d10 = hn::LoadU(d, t[4]), x10 = hn::LoadU(d, t[5]), y10 = hn::LoadU(d, t[6]), t10 = hn::LoadU(d, t[7]);
    const V d01 = hn::LoadU(d, t[8]), x01 = hn::LoadU(d, t[9]), y01 = hn::LoadU(d, t[10]), t01 = hn::LoadU(d, t[11]);
    const V d11 = hn::LoadU(d, t[12]), x11 = hn::LoadU(d, t[13]), y11 = hn::LoadU(d, t[14]), t11 = hn::LoadU(d, t[15]);
    V buH0, buH1, buG0, buG1, bvH0, bvH1, bvG0, bvG1, duH0, duH1, duG0, duG1, dvH0, dvH1, dvG0, dvG1;
    Basis(u, buH0, buH1, buG0, buG1), Basis(w, bvH0, bvH1, bvG0, bvG1);
    BasisDerivative(u, duH0, duH1, duG0, duG1), BasisDerivative(w, dvH0, dvH1, dvG0, dvG1);
    const V a0 = Row(buH0, buH1, buG0, buG1, s, d00, d10, x00, x10), a1 = Row(buH0, buH1, buG0, buG1, s, d01, d11, x01, x11);
    const V b0 = Row(buH0, buH1, buG0, buG1, s, y00, y10, t00, t10), b1 = Row(buH0, buH1, buG0, buG1, s, y01, y11, t01, t11);
    hn::StoreU(Row(bvH0, bvH1, bvG0, bvG1, s, a0, a1, b0, b1), d, outV + k);
    hn::StoreU(hn::Mul(Row(dvH0, dvH1, dvG0, dvG1, s, a0, a1, b0, b1), invS), d, outGy + k);
    const V c0 = Row(duH0, duH1, duG0, duG1, s, d00, d10, x00, x10), c1 = Row(duH0, duH1, duG0, duG1, s, d01, d11, x01, x11);
    const V e0 = Row(duH0, duH1, duG0, duG1, s, y00, y10, t00, t10), e1 = Row(duH0, duH1, duG0, duG1, s, y01, y11, t01, t11);
    hn::StoreU(hn::Mul(Row(bvH0, bvH1, bvG0, bvG1, s, c0, c1, e0, e1), invS), d, outGx + k);
  }
  return k;
}

// NOLINTNEXTLINE(google-readability-namespace-comments)
}  // namespace HWY_NAMESPACE
}  // namespace emboss
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace emboss {

HWY_EXPORT(BilinearLanes);
HWY_EXPORT(HermiteLanes);

int hermiteLanes(const SampleLattice& lattice, const double* x, const double* y, int n, double* v, double* gx,
                 double* gy) {
  return HWY_DYNAMIC_DISPATCH(HermiteLanes)(lattice, x, y, n, v, gx, gy);
}

int bilinearLanes(const FloatLattice& lattice, const double* x, const double* y, int n, double* out) {
  return HWY_DYNAMIC_DISPATCH(BilinearLanes)(lattice, x, y, n, out);
}

}  // namespace emboss
#endif  // HWY_ONCE
