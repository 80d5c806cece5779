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

// Segments [begin, end) of the path (whole vectors) into each lane's least squared distance from
// (px, py) and the first segment with it: kernels::segmentDistance2 for each (a zero-length
// segment's inv is 0: t is 0 and q is p, its value too); a segment replaces a lane's when its
// value is less, or equal with a lower index (chunks come in any order).
template <class D, class V = hn::Vec<D>>
HWY_INLINE void SegmentsInto(D d, const PathFields& f, size_t begin, size_t end, V px, V py, V& best, V& at) {
  const size_t lanes = hn::Lanes(d);
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), lane = hn::Iota(d, 0.0);
  for (size_t i = begin; i < end; i += lanes) {
    const V qx0 = hn::Sub(px, hn::LoadU(d, f.ax.data() + i)), qy0 = hn::Sub(py, hn::LoadU(d, f.ay.data() + i));
    const V ex = hn::LoadU(d, f.ex.data() + i), ey = hn::LoadU(d, f.ey.data() + i);
    V t = hn::Mul(hn::Add(hn::Mul(qx0, ex), hn::Mul(qy0, ey)), hn::LoadU(d, f.inv.data() + i));
    t = hn::Min(hn::Max(t, zero), one);
    const V qx = hn::Sub(qx0, hn::Mul(t, ex)), qy = hn::Sub(qy0, hn::Mul(t, ey));
    const V v = hn::Add(hn::Mul(qx, qx), hn::Mul(qy, qy)), index = hn::Add(lane, hn::Set(d, static_cast<double>(i)));
    const auto take = hn::Or(hn::Lt(v, best), hn::And(hn::Eq(v, best), hn::Lt(index, at)));
    best = hn::IfThenElse(take, v, best);
    at = hn::IfThenElse(take, index, at);
  }
}

// The least of the lanes' values, and the lowest segment of the lanes holding it.
template <class D, class V = hn::Vec<D>>
HWY_INLINE double LeastOf(D d, V best, V at, size_t* index) {
  const double v = hn::GetLane(hn::MinOfLanes(d, best));
  *index = static_cast<size_t>(hn::GetLane(
      hn::MinOfLanes(d, hn::IfThenElse(hn::Eq(best, hn::Set(d, v)), at, hn::Set(d, std::numeric_limits<double>::infinity())))));
  return v;
}

// Paths of at most this many chunks are read whole, their boxes not looked at.
constexpr size_t kUnboxedChunks = 8;

double NearestSegment(const PathFields& f, double x, double y, uint32_t* index) {
  const hn::ScalableTag<double> d;
  const size_t lanes = hn::Lanes(d), chunks = f.size() / PathFields::kChunk, count = f.size();
  size_t at = 0;
  double value = 0.0;
  if (PathFields::kChunk % lanes != 0) {
    // Vectors wider than a chunk (SVE's widest): one segment at a time, the first of the least.
    for (size_t i = 0; i < f.segments; ++i) {
      const double qx0 = x - f.ax[i], qy0 = y - f.ay[i];
      double t = (qx0 * f.ex[i] + qy0 * f.ey[i]) * f.inv[i];
      t = std::min(std::max(t, 0.0), 1.0);
      const double qx = qx0 - t * f.ex[i], qy = qy0 - t * f.ey[i], v = qx * qx + qy * qy;
      if (i == 0 || v < value) value = v, at = i;
    }
    *index = static_cast<uint32_t>(at);
    return value;
  }
  const auto px = hn::Set(d, x), py = hn::Set(d, y);
  auto best = hn::Set(d, std::numeric_limits<double>::infinity()), where = best;
  if (chunks <= kUnboxedChunks) {  // (a short path: every segment, no boxes)
    SegmentsInto(d, f, 0, count, px, py, best, where);
    value = LeastOf(d, best, where, &at);
    *index = static_cast<uint32_t>(std::min(at, f.segments - 1));  // (a padding copy ties with the last)
    return value;
  }
  // By chunks of consecutive segments: first the chunk that held this thread's last nearest
  // segment of this path (the exporter's and the tracers' points come in order: the nearest
  // chunk then is mostly the one before), then every other chunk whose box is not farther than
  // that chunk's least distance by more than rounding can account for (a micrometre squared: the
  // segments' values err by far less). A chunk passed over holds no segment whose value is at
  // most the least one: the min is the same value, and its first segment the same, whichever
  // chunk came first.
  thread_local const PathFields* lastPath = nullptr;
  thread_local size_t lastChunk = 0;
  const size_t guess = lastPath == &f && lastChunk < chunks ? lastChunk : 0;
  auto chunk = [&](size_t c) { SegmentsInto(d, f, c * PathFields::kChunk, (c + 1) * PathFields::kChunk, px, py, best, where); };
  chunk(guess);
  const double first = LeastOf(d, best, where, &at);
  const double reach = first + 1e-6 + 1e-9 * first;
  const auto zero = hn::Zero(d);
  for (size_t c = 0; c < chunks; c += lanes) {  // (the boxes come in whole vectors: PathFields)
    const auto dx = hn::Max(hn::Max(hn::Sub(hn::LoadU(d, f.boxX0.data() + c), px), hn::Sub(px, hn::LoadU(d, f.boxX1.data() + c))), zero);
    const auto dy = hn::Max(hn::Max(hn::Sub(hn::LoadU(d, f.boxY0.data() + c), py), hn::Sub(py, hn::LoadU(d, f.boxY1.data() + c))), zero);
    const auto maybe = hn::Not(hn::Gt(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Set(d, reach)));
    if (hn::AllFalse(d, maybe)) continue;
    uint8_t bits[8] = {};  // (up to 64 lanes)
    hn::StoreMaskBits(d, maybe, bits);
    for (size_t l = 0; l < lanes; ++l)
      if (c + l != guess && ((bits[l / 8] >> (l % 8)) & 1)) chunk(c + l);
  }
  value = LeastOf(d, best, where, &at);
  lastPath = &f, lastChunk = at / PathFields::kChunk;
  *index = static_cast<uint32_t>(std::min(at, f.segments - 1));  // (a padding copy ties with the last)
  return value;
}

bool InsideContour(const ContourEdges& e, double x, double y) {
  // Only the edges of y's band can cross its row (ContourEdges); none outside the bands.
  if (e.size() == 0 || !(y >= e.y0 && y <= e.y1)) return false;
  const size_t band = e.bandOf(y), begin = e.bandStart[band], end = e.bandStart[band + 1];
  const hn::ScalableTag<double> d;
  const size_t lanes = hn::Lanes(d);
  const auto px = hn::Set(d, x), py = hn::Set(d, y);
  size_t crossings = 0, i = begin;
  for (; i + lanes <= end; i += lanes) {
    const auto ix = hn::LoadU(d, e.ix.data() + i), iy = hn::LoadU(d, e.iy.data() + i);
    const auto jx = hn::LoadU(d, e.jx.data() + i), jy = hn::LoadU(d, e.jy.data() + i);
    const auto straddles = hn::Xor(hn::VecFromMask(d, hn::Gt(iy, py)), hn::VecFromMask(d, hn::Gt(jy, py)));
    // (Lanes that do not straddle the row may divide by zero: their crossing is not counted.)
    const auto xc = hn::Add(jx, hn::Div(hn::Mul(hn::Sub(py, jy), hn::Sub(ix, jx)), hn::Sub(iy, jy)));
    crossings += hn::CountTrue(d, hn::And(hn::MaskFromVec(straddles), hn::Lt(px, xc)));
  }
  for (; i < end; ++i)
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
HWY_EXPORT(NearestSegment);
HWY_EXPORT(InsideContour);
HWY_EXPORT(TargetName);

PathFields::PathFields(std::span<const PathSegment> segments) {
  for (auto* v : {&ax, &ay, &ex, &ey, &inv}) v->reserve(segments.size());
  for (const PathSegment& g : segments)
    ax.push_back(g.ax), ay.push_back(g.ay), ex.push_back(g.ex), ey.push_back(g.ey), inv.push_back(g.inv);
  this->segments = segments.size();
  // Padded to whole chunks with the last segment again (a copy changes no min): a short path is
  // one vector or two, not a scalar loop.
  while (!ax.empty() && ax.size() % kChunk != 0)
    ax.push_back(ax.back()), ay.push_back(ay.back()), ex.push_back(ex.back()), ey.push_back(ey.back()), inv.push_back(inv.back());
  for (size_t c = 0; c * kChunk < ax.size(); ++c) {
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    for (size_t i = c * kChunk; i < (c + 1) * kChunk; ++i)
      for (double t : {0.0, 1.0}) {
        const double px = ax[i] + t * ex[i], py = ay[i] + t * ey[i];
        x0 = std::min(x0, px), y0 = std::min(y0, py), x1 = std::max(x1, px), y1 = std::max(y1, py);
      }
    boxX0.push_back(x0), boxY0.push_back(y0), boxX1.push_back(x1), boxY1.push_back(y1);
  }
  // The boxes too to whole chunks, with empty ones (infinitely far: never read): a chunk's test
  // takes whole vectors of boxes.
  while (boxX0.size() % kChunk != 0) boxX0.push_back(1e300), boxY0.push_back(1e300), boxX1.push_back(-1e300), boxY1.push_back(-1e300);
}

double nearestDistance2(const PathFields& path, double x, double y) {
  std::uint32_t index = 0;
  return HWY_DYNAMIC_DISPATCH(NearestSegment)(path, x, y, &index);
}

double nearestSegment(const PathFields& path, double x, double y, std::uint32_t* index) {
  return HWY_DYNAMIC_DISPATCH(NearestSegment)(path, x, y, index);
}

ContourEdges::ContourEdges(std::span<const double> xy) {
  const size_t n = xy.size() / 2;
  if (n == 0) return;
  y0 = 1e300, y1 = -1e300;
  for (size_t i = 0; i < n; ++i) y0 = std::min(y0, xy[2 * i + 1]), y1 = std::max(y1, xy[2 * i + 1]);
  // Bands of equal height, about four edges each; an edge is listed in every band its heights
  // meet (bandOf() of its lowest and highest point and those between: bandOf() never decreases
  // with y, so a row's band lists every edge that can cross it).
  bands = std::clamp<size_t>(n / 4, 1, 4096);
  invHeight = y1 > y0 ? static_cast<double>(bands) / (y1 - y0) : 0.0;
  std::vector<std::vector<size_t>> in(bands);
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    const double a = xy[2 * i + 1], b = xy[2 * j + 1];
    for (size_t k = bandOf(std::min(a, b)); k <= bandOf(std::max(a, b)); ++k) in[k].push_back(i);
  }
  bandStart.push_back(0);
  for (const auto& list : in) {
    for (size_t i : list) {
      const size_t j = i == 0 ? n - 1 : i - 1;
      ix.push_back(xy[2 * i]), iy.push_back(xy[2 * i + 1]), jx.push_back(xy[2 * j]), jy.push_back(xy[2 * j + 1]);
    }
    bandStart.push_back(ix.size());
  }
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
