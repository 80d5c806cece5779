// shadeMetalLanes for each SIMD target Highway knows (compiled once per target by
// foreach_target.h), and the run-time choice among them. Every line mirrors a line of
// shadeMetal() (shading.cpp) and of what it calls, in the same order of operations: the lanes give
// the bits one call gives (no fused multiply-adds; sums, products, divisions and square roots are
// rounded alike on every target).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/shade_lanes.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "render/shade_lanes.h"

#include <cmath>
#include <cstdint>

HWY_BEFORE_NAMESPACE();
namespace emboss {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// glm::dot of two dvec3: (ax bx + ay by) + az bz.
template <class V>
HWY_INLINE V Dot(V ax, V ay, V az, V bx, V by, V bz) {
  return hn::Add(hn::Add(hn::Mul(ax, bx), hn::Mul(ay, by)), hn::Mul(az, bz));
}

// std::clamp(v, lo, hi) for numbers (no NaN reaches it).
template <class V>
HWY_INLINE V ClampTo(V v, V lo, V hi) {
  return hn::Min(hn::Max(v, lo), hi);
}

// glm::mix(x, y, a) = x (1 - a) + y a, given 1 - a.
template <class V>
HWY_INLINE V Mix(V x, V y, V a, V oneMinusA) {
  return hn::Add(hn::Mul(x, oneMinusA), hn::Mul(y, a));
}

// SphereMap::lookup(d): the octahedral map's bilinear texel, three channels.
template <class D, class V = hn::Vec<D>>
HWY_INLINE void Lookup(D d, const SphereTexels& map, V dx, V dy, V dz, V& outR, V& outG, V& outB) {
  const hn::Rebind<int32_t, D> di;
  const V one = hn::Set(d, 1.0), zero = hn::Zero(d);
  const V l1 = hn::Add(hn::Add(hn::Abs(dx), hn::Abs(dy)), hn::Abs(dz));
  V u = hn::Div(dx, l1), v = hn::Div(dy, l1);
  const auto below = hn::Lt(dz, zero);
  const V minusOne = hn::Set(d, -1.0);
  const V fu = hn::Mul(hn::Sub(one, hn::Abs(v)), hn::IfThenElse(hn::Ge(u, zero), one, minusOne));
  const V fv = hn::Mul(hn::Sub(one, hn::Abs(u)), hn::IfThenElse(hn::Ge(v, zero), one, minusOne));
  u = hn::IfThenElse(below, fu, u), v = hn::IfThenElse(below, fv, v);
  const V size = hn::Set(d, static_cast<double>(map.size)), half = hn::Set(d, 0.5);
  const V top = hn::Set(d, map.size - 1.0);
  const V fx = ClampTo(hn::Sub(hn::Mul(hn::Mul(hn::Add(u, one), half), size), half), zero, top);
  const V fy = ClampTo(hn::Sub(hn::Mul(hn::Mul(hn::Add(v, one), half), size), half), zero, top);
  const auto lastCell = hn::Set(di, map.size - 2);
  const auto x0 = hn::Min(hn::DemoteTo(di, fx), lastCell), y0 = hn::Min(hn::DemoteTo(di, fy), lastCell);
  const V ax = hn::Sub(fx, hn::PromoteTo(d, x0)), ay = hn::Sub(fy, hn::PromoteTo(d, y0));
  // The four texels of each lane, read one lane at a time (a gather by another name).
  constexpr size_t kMax = 32;  // doubles in the widest vector (SVE, 2048 bits)
  HWY_ALIGN int32_t first[kMax];
  hn::StoreU(hn::Add(hn::Mul(y0, hn::Set(di, map.size)), x0), di, first);
  HWY_ALIGN double t[12][kMax];
  const size_t lanes = hn::Lanes(d);
  for (size_t k = 0; k < lanes; ++k) {
    const float* row0 = map.rgb + static_cast<size_t>(first[k]) * 3;
    const float* row1 = row0 + static_cast<size_t>(map.size) * 3;
    for (int c = 0; c < 3; ++c) {
      t[c][k] = row0[c], t[3 + c][k] = row0[3 + c];
      t[6 + c][k] = row1[c], t[9 + c][k] = row1[3 + c];
    }
  }
  const V oneMinusAx = hn::Sub(one, ax), oneMinusAy = hn::Sub(one, ay);
  const auto channel = [&](int c) {
    const V topC = Mix(hn::LoadU(d, t[c]), hn::LoadU(d, t[3 + c]), ax, oneMinusAx);
    const V bottomC = Mix(hn::LoadU(d, t[6 + c]), hn::LoadU(d, t[9 + c]), ax, oneMinusAx);
    return Mix(topC, bottomC, ay, oneMinusAy);
  };
  outR = channel(0), outG = channel(1), outB = channel(2);
}

// hammerGradient(x, y, slope) (shading.cpp): the dimples of the nine cells around, the cells'
// centres hashed from their indices.
template <class D, class V = hn::Vec<D>>
HWY_INLINE void Dimples(D d, double slope, V x, V y, V& gx, V& gy) {
  using H = emboss::Hammer;
  const double k0 = H::k0(slope);
  const hn::Rebind<int32_t, D> di;
  const hn::Rebind<uint32_t, D> du;
  const V cell = hn::Set(d, H::kCell);
  const auto cx = hn::DemoteTo(di, hn::Floor(hn::Div(x, cell)));
  const auto cy = hn::DemoteTo(di, hn::Floor(hn::Div(y, cell)));
  const V k0v = hn::Set(d, k0), invR2 = hn::Set(d, H::kInvR2), one = hn::Set(d, 1.0), zero = hn::Zero(d);
  const V jitter = hn::Set(d, H::kJitter), offset = hn::Set(d, H::kOffset);
  const auto low16 = hn::Set(du, 0xFFFFu);
  gx = zero, gy = zero;
  for (int n = 0; n < 9; ++n) {
    const auto i = hn::Add(cx, hn::Set(di, n % 3 - 1)), j = hn::Add(cy, hn::Set(di, n / 3 - 1));
    auto h = hn::Xor(hn::Mul(hn::BitCast(du, i), hn::Set(du, H::kHash[0])), hn::Mul(hn::BitCast(du, j), hn::Set(du, H::kHash[1])));
    h = hn::Xor(h, hn::ShiftRight<15>(h)), h = hn::Mul(h, hn::Set(du, H::kHash[2]));
    h = hn::Xor(h, hn::ShiftRight<12>(h)), h = hn::Mul(h, hn::Set(du, H::kHash[3]));
    h = hn::Xor(h, hn::ShiftRight<15>(h));
    // (Both halves are below 2^16: as int32 they convert to the same doubles.)
    const V hx = hn::PromoteTo(d, hn::BitCast(di, hn::And(h, low16)));
    const V hy = hn::PromoteTo(d, hn::BitCast(di, hn::ShiftRight<16>(h)));
    const V fx = hn::Mul(hn::Add(hn::Add(hn::PromoteTo(d, i), offset), hn::Mul(jitter, hx)), cell);
    const V fy = hn::Mul(hn::Add(hn::Add(hn::PromoteTo(d, j), offset), hn::Mul(jitter, hy)), cell);
    const V dx = hn::Sub(x, fx), dy = hn::Sub(y, fy);
    const V k = hn::Mul(k0v, hn::Max(zero, hn::Sub(one, hn::Mul(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), invR2))));
    gx = hn::Add(gx, hn::Mul(k, dx)), gy = hn::Add(gy, hn::Mul(k, dy));
  }
}

void ShadeLanes(const MetalLaneParams& s, ShadeBatch& b) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const hn::Rebind<int32_t, decltype(d)> di;
  const size_t lanes = hn::Lanes(d);
  // The lanes past n: a hit straight on, seen from above.
  const int padded = static_cast<int>((static_cast<size_t>(b.n) + lanes - 1) / lanes * lanes);
  for (int k = b.n; k < padded && k < ShadeBatch::kCapacity; ++k) {
    b.px[k] = b.py[k] = b.pz[k] = 0.0, b.nx[k] = b.ny[k] = 0.0, b.nz[k] = 1.0;
    b.vx[k] = b.vy[k] = 0.0, b.vz[k] = -1.0, b.cavity[k] = 0.0;
  }
  const V one = hn::Set(d, 1.0), zero = hn::Zero(d), two = hn::Set(d, 2.0);
  for (int k = 0; k < b.n; k += static_cast<int>(lanes)) {
    const V px = hn::LoadU(d, b.px + k), py = hn::LoadU(d, b.py + k), pz = hn::LoadU(d, b.pz + k);
    V nx = hn::LoadU(d, b.nx + k), ny = hn::LoadU(d, b.ny + k), nz = hn::LoadU(d, b.nz + k);
    const V vx = hn::LoadU(d, b.vx + k), vy = hn::LoadU(d, b.vy + k), vz = hn::LoadU(d, b.vz + k);
    const V cavity = hn::LoadU(d, b.cavity + k);
    // Seen from behind: the face seen is lit.
    const auto behind = hn::Gt(Dot(nx, ny, nz, vx, vy, vz), zero);
    nx = hn::IfThenElse(behind, hn::Neg(nx), nx), ny = hn::IfThenElse(behind, hn::Neg(ny), ny);
    nz = hn::IfThenElse(behind, hn::Neg(nz), nz);
    if (s.hammer > 0) {
      V gx, gy;
      Dimples(d, s.hammer, px, py, gx, gy);
      const V mx = hn::Sub(nx, hn::Mul(gx, nz)), my = hn::Sub(ny, hn::Mul(gy, nz)), mz = hn::Sub(nz, hn::Mul(zero, nz));
      const V inv = hn::Div(one, hn::Sqrt(Dot(mx, my, mz, mx, my, mz)));
      nx = hn::Mul(mx, inv), ny = hn::Mul(my, inv), nz = hn::Mul(mz, inv);
    }
    const V cosV = ClampTo(hn::Neg(Dot(vx, vy, vz, nx, ny, nz)), hn::Set(d, 1e-4), one);
    const V dnv = Dot(nx, ny, nz, vx, vy, vz);
    const V rx = hn::Sub(vx, hn::Mul(hn::Mul(nx, dnv), two));
    const V ry = hn::Sub(vy, hn::Mul(hn::Mul(ny, dnv), two));
    const V rz = hn::Sub(vz, hn::Mul(hn::Mul(nz, dnv), two));
    // MetalResponse::at(cosV).
    const V f = hn::Mul(ClampTo(cosV, zero, one), hn::Set(d, static_cast<double>(s.bins)));
    const auto bin = hn::Min(hn::DemoteTo(di, f), hn::Set(di, s.bins - 1));
    const V a = hn::Sub(f, hn::PromoteTo(d, bin)), oneMinusA = hn::Sub(one, a);
    constexpr size_t kMax = 32;
    HWY_ALIGN int32_t bins[kMax];
    HWY_ALIGN double t[8][kMax];
    hn::StoreU(bin, di, bins);
    for (size_t l = 0; l < lanes; ++l) {
      const double* s0 = s.single + static_cast<size_t>(bins[l]) * 3;
      for (int c = 0; c < 3; ++c) t[c][l] = s0[c], t[3 + c][l] = s0[3 + c];
      t[6][l] = s.albedo[bins[l]], t[7][l] = s.albedo[bins[l] + 1];
    }
    // (Channels are named one by one: SVE's sizeless vectors cannot be array elements.)
    const V albedo0 = hn::LoadU(d, t[6]);
    const V e1 = hn::Add(albedo0, hn::Mul(hn::Sub(hn::LoadU(d, t[7]), albedo0), a));
    const auto single = [&](int c) { return Mix(hn::LoadU(d, t[c]), hn::LoadU(d, t[3 + c]), a, oneMinusA); };
    const auto multiple = [&](int c) { return hn::Mul(hn::Set(d, s.fms[c]), hn::Sub(one, e1)); };
    const V ssR = single(0), ssG = single(1), ssB = single(2);
    const V msR = multiple(0), msG = multiple(1), msB = multiple(2);
    // The tinge settles in the hollows (no patina here: the renderer shades those one by one).
    V tintR = one, tintG = one, tintB = one;
    if (s.tingeStrength > 0) {
      const V settle = hn::Max(ClampTo(hn::Div(hn::Sub(hn::Set(d, s.frontZ), pz), hn::Set(d, s.tingeDepth)), zero, one), cavity);
      const V kk = ClampTo(hn::Mul(hn::Set(d, s.tingeStrength), hn::Add(hn::Set(d, 0.25), hn::Mul(hn::Set(d, 1.0 - 0.25), settle))), zero, one);
      const V oneMinusK = hn::Sub(one, kk);
      tintR = hn::Mul(tintR, Mix(one, hn::Set(d, s.tingeColor[0]), kk, oneMinusK));
      tintG = hn::Mul(tintG, Mix(one, hn::Set(d, s.tingeColor[1]), kk, oneMinusK));
      tintB = hn::Mul(tintB, Mix(one, hn::Set(d, s.tingeColor[2]), kk, oneMinusK));
    }
    const V open = hn::Sub(one, hn::Mul(hn::Set(d, 0.75), ClampTo(cavity, zero, one)));
    V envR, envG, envB, irrR, irrG, irrB;
    Lookup(d, s.specular, rx, ry, rz, envR, envG, envB);
    Lookup(d, s.irradiance, nx, ny, nz, irrR, irrG, irrB);
    const auto out = [&](V tint, V env, V ss, V irr, V ms, double* to) {
      const V spec = hn::Add(hn::Mul(env, ss), hn::Mul(irr, ms));
      hn::StoreU(hn::Mul(hn::Mul(tint, spec), open), d, to);
    };
    out(tintR, envR, ssR, irrR, msR, b.r + k);
    out(tintG, envG, ssG, irrG, msG, b.g + k);
    out(tintB, envB, ssB, irrB, msB, b.b + k);
  }
}

// NOLINTNEXTLINE(google-readability-namespace-comments)
}  // namespace HWY_NAMESPACE
}  // namespace emboss
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace emboss {

HWY_EXPORT(ShadeLanes);

void shadeMetalLanes(const MetalLaneParams& params, ShadeBatch& batch) {
  if (batch.n > 0) HWY_DYNAMIC_DISPATCH(ShadeLanes)(params, batch);
}

}  // namespace emboss
#endif  // HWY_ONCE
