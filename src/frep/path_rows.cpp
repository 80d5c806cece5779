// nearestSegments for each SIMD target Highway knows (compiled once per target by foreach_target.h),
// and the run-time choice among them.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "frep/path_rows.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "frep/path_rows.h"

#include <algorithm>
#include <limits>

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

double NearestDistance2(const PathFields& f, double x, double y) {
  const hn::ScalableTag<double> d;
  const size_t lanes = hn::Lanes(d), count = f.size();
  const auto px = hn::Set(d, x), py = hn::Set(d, y), zero = hn::Zero(d), one = hn::Set(d, 1.0);
  auto best = hn::Set(d, std::numeric_limits<double>::infinity());
  size_t i = 0;
  for (; i + lanes <= count; i += lanes) {
    // kernels::segmentDistance2 (a zero-length segment's inv is 0: t is 0 and q is p, its value too).
    const auto qx0 = hn::Sub(px, hn::LoadU(d, f.ax.data() + i)), qy0 = hn::Sub(py, hn::LoadU(d, f.ay.data() + i));
    const auto ex = hn::LoadU(d, f.ex.data() + i), ey = hn::LoadU(d, f.ey.data() + i);
    auto t = hn::Mul(hn::Add(hn::Mul(qx0, ex), hn::Mul(qy0, ey)), hn::LoadU(d, f.inv.data() + i));
    t = hn::Min(hn::Max(t, zero), one);
    const auto qx = hn::Sub(qx0, hn::Mul(t, ex)), qy = hn::Sub(qy0, hn::Mul(t, ey));
    best = hn::Min(best, hn::Add(hn::Mul(qx, qx), hn::Mul(qy, qy)));
  }
  double v = hn::GetLane(hn::MinOfLanes(d, best));
  for (; i < count; ++i) {
    const double qx0 = x - f.ax[i], qy0 = y - f.ay[i];
    double t = (qx0 * f.ex[i] + qy0 * f.ey[i]) * f.inv[i];
    t = std::min(std::max(t, 0.0), 1.0);
    const double qx = qx0 - t * f.ex[i], qy = qy0 - t * f.ey[i];
    v = std::min(v, qx * qx + qy * qy);
  }
  return v;
}

bool InsideContour(const ContourEdges& e, double x, double y) {
  const hn::ScalableTag<double> d;
  const size_t lanes = hn::Lanes(d), count = e.size();
  const auto px = hn::Set(d, x), py = hn::Set(d, y);
  size_t crossings = 0, i = 0;
  for (; i + lanes <= count; i += lanes) {
    const auto ix = hn::LoadU(d, e.ix.data() + i), iy = hn::LoadU(d, e.iy.data() + i);
    const auto jx = hn::LoadU(d, e.jx.data() + i), jy = hn::LoadU(d, e.jy.data() + i);
    const auto straddles = hn::Xor(hn::VecFromMask(d, hn::Gt(iy, py)), hn::VecFromMask(d, hn::Gt(jy, py)));
    // (Lanes that do not straddle the row may divide by zero: their crossing is not counted.)
    const auto xc = hn::Add(jx, hn::Div(hn::Mul(hn::Sub(py, jy), hn::Sub(ix, jx)), hn::Sub(iy, jy)));
    crossings += hn::CountTrue(d, hn::And(hn::MaskFromVec(straddles), hn::Lt(px, xc)));
  }
  for (; i < count; ++i)
    if ((e.iy[i] > y) != (e.jy[i] > y)) {
      const double xc = e.jx[i] + (y - e.jy[i]) * (e.ix[i] - e.jx[i]) / (e.iy[i] - e.jy[i]);
      if (x < xc) ++crossings;
    }
  return (crossings & 1) != 0;
}

const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace emboss
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace emboss {

HWY_EXPORT(NearestSegments);
HWY_EXPORT(NearestDistance2);
HWY_EXPORT(InsideContour);
HWY_EXPORT(TargetName);

PathFields::PathFields(std::span<const PathSegment> segments) {
  for (auto* v : {&ax, &ay, &ex, &ey, &inv}) v->reserve(segments.size());
  for (const PathSegment& g : segments)
    ax.push_back(g.ax), ay.push_back(g.ay), ex.push_back(g.ex), ey.push_back(g.ey), inv.push_back(g.inv);
}

double nearestDistance2(const PathFields& path, double x, double y) {
  return HWY_DYNAMIC_DISPATCH(NearestDistance2)(path, x, y);
}

ContourEdges::ContourEdges(std::span<const double> xy) {
  const size_t n = xy.size() / 2;
  for (auto* v : {&ix, &iy, &jx, &jy}) v->reserve(n);
  for (size_t i = 0, j = n - 1; i < n; j = i++)
    ix.push_back(xy[2 * i]), iy.push_back(xy[2 * i + 1]), jx.push_back(xy[2 * j]), jy.push_back(xy[2 * j + 1]);
}

bool insideContour(const ContourEdges& edges, double x, double y) {
  return HWY_DYNAMIC_DISPATCH(InsideContour)(edges, x, y);
}

void nearestSegments(std::span<const PathSegment> segments, double y, const double* xs, int n,
                     std::uint32_t* best, double* bestV) {
  if (segments.empty() || n <= 0) return;
  HWY_DYNAMIC_DISPATCH(NearestSegments)(segments.data(), static_cast<std::uint32_t>(segments.size()), y, xs, n,
                                        best, bestV);
}

const char* simdTargetName() { return HWY_DYNAMIC_DISPATCH(TargetName)(); }

}  // namespace emboss
#endif
