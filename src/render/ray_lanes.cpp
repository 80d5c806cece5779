// raysInLanes for each SIMD target Highway knows (compiled once per target by foreach_target.h),
// and the run-time choice among them. Each line mirrors Camera::rayAt() (camera.cpp), clipRay()
// (renderer_internal.h) or Renderer::beginWalk() (renderer_walk.cpp): the same operations in the
// same order, so the same bits.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/ray_lanes.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "render/ray_lanes.h"
#include "render/std_minmax-inl.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>

HWY_BEFORE_NAMESPACE();
namespace emboss {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void RaysInLanes(const CameraBasis& cam, const Box3& clip, double h, double h8, const double* sx, const double* sy,
                 int n, RayStarts& out) {
  // (No arrays of vectors and no vector left unset: SVE's vectors have no size.)
  const hn::CappedTag<double, 8> d;
  using V = hn::Vec<decltype(d)>;
  const size_t lanes = hn::Lanes(d);
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), two = hn::Set(d, 2.0);
  const V width = hn::Set(d, cam.width), height = hn::Set(d, cam.height);
  const V aspect = hn::Set(d, cam.aspect), halfH = hn::Set(d, cam.halfH);
  const V tiny = hn::Set(d, 1e-15), vh = hn::Set(d, h), vh8 = hn::Set(d, h8), sixteen = hn::Set(d, 16.0);
  // The last few points go through buffers of 8 (their other lanes are image point (0, 0)); so do
  // their values.
  HWY_ALIGN double bx[8] = {}, by[8] = {}, buf[8];
  double* const dest[12] = {out.ox.data(), out.oy.data(), out.oz.data(), out.dx.data(), out.dy.data(), out.dz.data(),
                            out.g0.data(), out.g1.data(), out.rx0.data(), out.ry0.data(), out.rx1.data(), out.ry1.data()};
  for (size_t i = 0; i < static_cast<size_t>(n); i += lanes) {
    const size_t count = std::min(lanes, static_cast<size_t>(n) - i);
    const bool whole = count == lanes;
    if (!whole) std::copy_n(sx + i, count, bx), std::copy_n(sy + i, count, by);
    const V x = whole ? hn::LoadU(d, sx + i) : hn::Load(d, bx);
    const V y = whole ? hn::LoadU(d, sy + i) : hn::Load(d, by);
    auto put = [&](int k, V value) {
      if (whole) {
        hn::StoreU(value, d, dest[k] + i);
      } else {
        hn::Store(value, d, buf);
        std::copy_n(buf, count, dest[k] + i);
      }
    };
    // Camera::rayAt(): u = (2 sx / width - 1) aspect halfH, v = (1 - 2 sy / height) halfH.
    const V u = hn::Mul(hn::Mul(hn::Sub(hn::Div(hn::Mul(two, x), width), one), aspect), halfH);
    const V v = hn::Mul(hn::Sub(one, hn::Div(hn::Mul(two, y), height)), halfH);
    // forward + u right + v up (perspective: normalized, the vector times 1 / sqrt of its dot with
    // itself, summed x, y, z, as glm does), or eye + u right + v up along forward (orthographic).
    auto across = [&](const double* base, int k) {
      return hn::Add(hn::Add(hn::Set(d, base[k]), hn::Mul(u, hn::Set(d, cam.right[k]))), hn::Mul(v, hn::Set(d, cam.up[k])));
    };
    const V wx = across(cam.ortho ? cam.eye : cam.forward, 0), wy = across(cam.ortho ? cam.eye : cam.forward, 1),
            wz = across(cam.ortho ? cam.eye : cam.forward, 2);
    const V inv = cam.ortho ? one : hn::Div(one, hn::Sqrt(hn::Add(hn::Add(hn::Mul(wx, wx), hn::Mul(wy, wy)), hn::Mul(wz, wz))));
    const V ox = cam.ortho ? wx : hn::Set(d, cam.eye[0]), oy = cam.ortho ? wy : hn::Set(d, cam.eye[1]),
            oz = cam.ortho ? wz : hn::Set(d, cam.eye[2]);
    const V dx = cam.ortho ? hn::Set(d, cam.forward[0]) : hn::Mul(wx, inv),
            dy = cam.ortho ? hn::Set(d, cam.forward[1]) : hn::Mul(wy, inv),
            dz = cam.ortho ? hn::Set(d, cam.forward[2]) : hn::Mul(wz, inv);
    // clipRay(): the slabs x, y, z in turn; a component under 1e-15 leaves the ray to the caller.
    V t0 = zero, t1 = hn::Set(d, 1e30);
    auto slab = [&](V o, V dir, double lo, double hi) {
      const V r = hn::Div(one, dir);
      const V ta = hn::Mul(hn::Sub(hn::Set(d, lo), o), r), tb = hn::Mul(hn::Sub(hn::Set(d, hi), o), r);
      const auto swap = hn::Gt(ta, tb);
      t0 = MaxOf(t0, hn::IfThenElse(swap, tb, ta));
      t1 = MinOf(t1, hn::IfThenElse(swap, ta, tb));
    };
    slab(ox, dx, clip.x0, clip.x1);
    slab(oy, dy, clip.y0, clip.y1);
    slab(oz, dz, clip.z0, clip.z1);
    const auto alone = hn::Or(hn::Or(hn::Lt(hn::Abs(dx), tiny), hn::Lt(hn::Abs(dy), tiny)), hn::Lt(hn::Abs(dz), tiny));
    // (Once t0 < t1 fails it fails for good: t0 only grows and t1 only shrinks.)
    const auto clipped = hn::Lt(t0, t1);
    // beginWalk(): q0 = 16 floor(t0 / h), q1 = 16 ceil(t1 / h); the points there,
    // origin + (q h8) dir, and their (x, y) box.
    const V g0 = hn::Floor(hn::Div(t0, vh)), g1 = hn::Ceil(hn::Div(t1, vh));
    const V s0 = hn::Mul(hn::Mul(sixteen, g0), vh8), s1 = hn::Mul(hn::Mul(sixteen, g1), vh8);
    const V pax = hn::Add(ox, hn::Mul(s0, dx)), pay = hn::Add(oy, hn::Mul(s0, dy));
    const V pbx = hn::Add(ox, hn::Mul(s1, dx)), pby = hn::Add(oy, hn::Mul(s1, dy));
    put(0, ox), put(1, oy), put(2, oz), put(3, dx), put(4, dy), put(5, dz), put(6, g0), put(7, g1);
    put(8, MinOf(pax, pbx)), put(9, MinOf(pay, pby)), put(10, MaxOf(pax, pbx)), put(11, MaxOf(pay, pby));
    hn::Store(hn::IfThenElse(alone, two, hn::IfThenElseZero(clipped, one)), d, buf);
    for (size_t k = 0; k < count; ++k) out.state[i + k] = static_cast<std::uint8_t>(buf[k]);
  }
}

// NOLINTNEXTLINE(google-readability-namespace-comments)
}  // namespace HWY_NAMESPACE
}  // namespace emboss
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace emboss {

HWY_EXPORT(RaysInLanes);

void RayStarts::resize(size_t n) {
  for (std::vector<double>* v : {&ox, &oy, &oz, &dx, &dy, &dz, &g0, &g1, &rx0, &ry0, &rx1, &ry1}) v->resize(n);
  state.resize(n);
}

void raysInLanes(const CameraBasis& camera, const Box3& clip, double h, double h8, const double* sx, const double* sy,
                 int n, RayStarts& out) {
  out.resize(static_cast<size_t>(std::max(n, 0)));
  if (n > 0) HWY_DYNAMIC_DISPATCH(RaysInLanes)(camera, clip, h, h8, sx, sy, n, out);
}

}  // namespace emboss
#endif  // HWY_ONCE
