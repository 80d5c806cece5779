// What the renderer's parts share (renderer.cpp: frames, the exact tracer and dirty regions;
// renderer_sync.cpp: the model and camera taken in; renderer_field.cpp: the field tracer's values;
// renderer_walk.cpp: its walk along a ray; renderer_lanes.cpp: the walks in SIMD lanes): the
// tracers' constants, small geometry helpers, and the per-ray context. Not for use elsewhere.
#pragma once

#include "render/renderer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <mutex>
#include <limits>
#include <numbers>
#include <numeric>
#include <type_traits>

#include "frep/kernels.h"
#include "frep/vm_model.h"
#include "frep/workpieces.h"
#include "render/set_op_bounds.h"
#include "render/srgb8.h"

namespace emboss {
namespace render_internal {


// Exact tracer.
inline constexpr int kSpanSteps = 8;
inline constexpr int kBisections = 40;
inline constexpr int kThinSplits = 3;

// Field tracer.
inline constexpr double kFieldSpacing = 0.125;    // mm between displacement samples
inline constexpr double kMaxFieldSamples = 32e6;  // beyond this the spacing grows (a huge workpiece)
inline constexpr double kFieldMargin = 2.0;       // mm of field beyond the workpiece's bounds
// Set operations' boxes a field-tracer ray crosses from which it is searched on its cells' ends
// inside their window (traceField: a tangle of a blending punch's beads).
inline constexpr int kDenseSetOps = 8;
// The operation grid's smallest cell under the sheet model, mm (Renderer::sync()).
inline constexpr double kSheetGridCell = 1.0;
// A cell is searched down to h / 16 (docs/rendering.md, "The root finder": h / 64 cost 6 % more
// instructions a frame, and differed in a few hundred pixels of a million).
inline constexpr int kSubdivisions = 16;
// Sub-pixel offsets of the extra samples on an edge: with the centre, three on the pixel's
// diagonal, so that no two share a row or column (a horizontal or a vertical edge gets four levels).
inline constexpr double kEdgeSamples[2][2] = {{-0.3333, -0.3333}, {0.3333, 0.3333}};
inline constexpr double kPruneEps = 1e-7;         // mm: a bound must clear zero by this much to skip
// The margin a Lipschitz step inside a window (RayContext::winRaise) keeps below zero for rounding
// in the set operations' values (each off by a few units in the last place of numbers of a few
// hundred mm at most) and for kPruneEps.
inline constexpr double kRaiseMargin = 1e-6;
// A walk step's stretch is found for a slope bound of at least this along the ray (traceField()).
inline constexpr double kStepRate = 0.9;
inline constexpr int kRecomputeTile = 64;         // samples per side of a field tile recomputed in parallel

inline P3<Interval> boxOf(const glm::dvec3& a, const glm::dvec3& b) {
  return {Interval(std::min(a.x, b.x), std::max(a.x, b.x)), Interval(std::min(a.y, b.y), std::max(a.y, b.y)),
          Interval(std::min(a.z, b.z), std::max(a.z, b.z))};
}

// The parameter range [t0, t1] (t0 >= 0) where a ray is inside a box (slabs), for one ray and
// many boxes: the direction's reciprocals are found once.
class RayClip {
 public:
  explicit RayClip(const Ray& ray) {
    for (int k = 0; k < 3; ++k) {
      o_[k] = ray.origin[k];
      along_[k] = !(std::abs(ray.dir[k]) < 1e-15);
      inv_[k] = along_[k] ? 1.0 / ray.dir[k] : 0.0;
    }
  }
  bool operator()(const Box3& b, double& t0, double& t1) const {
    t0 = 0.0, t1 = 1e30;
    const double lo[3] = {b.x0, b.y0, b.z0}, hi[3] = {b.x1, b.y1, b.z1};
    for (int k = 0; k < 3; ++k) {
      if (!along_[k]) {
        if (o_[k] < lo[k] || o_[k] > hi[k]) return false;
        continue;
      }
      double ta = (lo[k] - o_[k]) * inv_[k], tb = (hi[k] - o_[k]) * inv_[k];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta), t1 = std::min(t1, tb);
      if (!(t0 < t1)) return false;
    }
    return t0 < t1;
  }

 private:
  double o_[3], inv_[3];
  bool along_[3];  // the ray is not parallel to the axis
};

// The stretch [t0, t1] (t >= 0) of a ray within `radius` of the vertical segment from (x, y, z0) to
// (x, y, z1), z0 <= z1 (a capsule standing upright): false when the ray misses it. The capsule is
// convex, so the stretch is the hull of the ray's stretches in its side and in its two end balls.
// Near a tangent the roots are as good as the discriminant: a caller grows the radius by more.
inline bool clipUprightCapsule(const Ray& ray, double x, double y, double z0, double z1, double radius, double& t0,
                               double& t1) {
  const glm::dvec3& o = ray.origin;
  const glm::dvec3& d = ray.dir;
  const double r2 = radius * radius, ox = o.x - x, oy = o.y - y;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  // The side: the infinite cylinder within the slab z0..z1.
  const double a = d.x * d.x + d.y * d.y, b = ox * d.x + oy * d.y, c = ox * ox + oy * oy - r2;
  double sa = -1e300, sb = 1e300;
  if (a > 0.0) {
    const double disc = b * b - a * c;
    if (disc >= 0.0) {
      const double root = std::sqrt(disc);
      sa = (-b - root) / a, sb = (-b + root) / a;
    } else {
      sa = 1.0, sb = 0.0;
    }
  } else if (c > 0.0) {
    sa = 1.0, sb = 0.0;
  }
  if (d.z != 0.0) {
    double za = (z0 - o.z) / d.z, zb = (z1 - o.z) / d.z;
    if (za > zb) std::swap(za, zb);
    sa = std::max(sa, za), sb = std::min(sb, zb);
  } else if (o.z < z0 || o.z > z1) {
    sa = 1.0, sb = 0.0;
  }
  if (sa <= sb) lo = sa, hi = sb;
  // The end balls.
  const double dd = glm::dot(d, d);
  for (const double z : {z0, z1}) {
    const double oz = o.z - z;
    const double bb = b + oz * d.z, cc = ox * ox + oy * oy + oz * oz - r2;
    const double disc = bb * bb - dd * cc;
    if (disc < 0.0) continue;
    const double root = std::sqrt(disc);
    lo = std::min(lo, (-bb - root) / dd), hi = std::max(hi, (-bb + root) / dd);
  }
  t0 = std::max(lo, 0.0), t1 = hi;
  return t0 < t1;
}

// RayClip for one box.
inline bool clipRay(const Ray& ray, const Box3& b, double& t0, double& t1) { return RayClip(ray)(b, t0, t1); }

inline double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// A Lipschitz constant along the unit direction d of f = W(x, y, z - D(x, y)), where D's slopes
// are bounded by b and W is one of the built-in workpieces: each is the min of terms whose rates
// along d are bounded by |dx|, |dy| (the plate's sides), |(dx, dy)| (a round rim), |dz'| (the
// faces; z' = z - D, dz'/dt = dz - grad D . (dx, dy)) or |(dx, dy, dz')| (the bowl's shell), and a
// min changes no faster than its fastest term. Kind 4 (outline sheets) bounds the slab d - |z'|.
// Always inlined: GCC called it, once a walk step (1 to 2 % of a frame on one thread; the same bytes).
[[gnu::always_inline]] inline double lipschitzAlong(const glm::dvec3& d, const HeightField::Bound& b, int workpieceKind) {
  const double slo = b.gxlo * (d.x >= 0 ? d.x : 0.0) + b.gxhi * (d.x < 0 ? d.x : 0.0) + b.gylo * (d.y >= 0 ? d.y : 0.0) +
                     b.gyhi * (d.y < 0 ? d.y : 0.0);
  const double shi = b.gxhi * (d.x >= 0 ? d.x : 0.0) + b.gxlo * (d.x < 0 ? d.x : 0.0) + b.gyhi * (d.y >= 0 ? d.y : 0.0) +
                     b.gylo * (d.y < 0 ? d.y : 0.0);
  const double dz = std::max(std::abs(d.z - slo), std::abs(d.z - shi));
  double l;
  switch (workpieceKind) {
    case 1: l = std::max({std::abs(d.x), std::abs(d.y), dz}); break;              // plate
    case 2: l = std::max(std::sqrt(d.x * d.x + d.y * d.y), dz); break;            // disc
    case 4: l = dz; break;                                                         // the slab alone
    default: l = std::sqrt(d.x * d.x + d.y * d.y + dz * dz); break;               // bowl
  }
  return l * (1.0 + 1e-9) + 1e-12;
}

inline Box2 xyBox(const glm::dvec3& a, const glm::dvec3& b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::max(a.x, b.x), std::max(a.y, b.y)};
}

// A ray crossing a grid of squares in the plane (side `size`, `inv` its reciprocal, corner (x0,
// y0)) from its point at t, square by square (a 2D DDA): the square (i, j) it is in, and the t
// where it leaves it across x (tx) and across y (ty). A direction of under 1e-15 along an axis
// never crosses it. The outline sheets' column blocks (beginWalkFrom()) and the pile's tops
// (pileSkip()) walk this way.
struct SquareWalk {
  int i, j, si, sj;
  double tx, ty, dtx, dty;
  SquareWalk(const Ray& ray, double t, double x0, double y0, double size, double inv) {
    const glm::dvec3 p = ray.origin + t * ray.dir;
    i = floorToInt((p.x - x0) * inv), j = floorToInt((p.y - y0) * inv);
    si = ray.dir.x > 0 ? 1 : -1, sj = ray.dir.y > 0 ? 1 : -1;
    const double inf = std::numeric_limits<double>::infinity();
    const bool alongX = std::abs(ray.dir.x) >= 1e-15, alongY = std::abs(ray.dir.y) >= 1e-15;
    tx = alongX ? (x0 + (i + (si > 0 ? 1 : 0)) * size - ray.origin.x) / ray.dir.x : inf;
    ty = alongY ? (y0 + (j + (sj > 0 ? 1 : 0)) * size - ray.origin.y) / ray.dir.y : inf;
    dtx = alongX ? size / std::abs(ray.dir.x) : inf, dty = alongY ? size / std::abs(ray.dir.y) : inf;
  }
  // Where it leaves the square it is in.
  double exit() const { return std::min(tx, ty); }
  // On into the next square; returns the t where it enters it.
  double next() {
    if (tx < ty) {
      const double t = tx;
      tx += dtx, i += si;
      return t;
    }
    const double t = ty;
    ty += dty, j += sj;
    return t;
  }
};

inline Box3 unite(const Box3& a, const Box3& b) {
  return {std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::min(a.z0, b.z0),
          std::max(a.x1, b.x1), std::max(a.y1, b.y1), std::max(a.z1, b.z1)};
}


}  // namespace render_internal

// Per ray: the set operations its cells can meet, the windows of the ray where they can act,
// and the Lipschitz constant of f outside those windows when there is one.
struct Renderer::RayContext {
  // The set operations whose support meets the ray's reach, in the model's order (held by a
  // per-thread list: any number of them, so that a ray over hundreds of a blending punch's beads
  // still tests only those its reach meets, each within its own window).
  const SetOp* const* setOps = nullptr;
  int setOpCount = 0;
  // Through at least kDenseSetOps set operations' boxes: its window is searched on the cells' ends.
  bool dense = false;
  // Lipschitz: W is 1-Lipschitz and D comes from the field along the whole ray, so outside the
  // windows |df/dt| <= lf; inside them (and everywhere without it) intervals bound f.
  bool lipschitz = false;
  double lf = 0.0;
  static constexpr int kMaxWindows = 8;
  long winLo[kMaxWindows], winHi[kMaxWindows];  // ascending, disjoint, in grid units
  // The most the set operations that can act in each window raise f anywhere (SetOpUpper::
  // raise(), summed; +infinity with a union among them): inside window i, f <= W + winRaise[i].
  double winRaise[kMaxWindows];
  // Whether window i is a ball's far stretch alone (SetOp::farRaise): f < 0 there wherever W <
  // -winRaise[i], a threshold rather than a raise that adds up, so any merge makes it unknown.
  bool winFar[kMaxWindows];
  int windows = 0;
  // What a walk's step in far window i is shortened by (its raise and the rounding's margin): the
  // walk alone and the lanes read this one value, so that they take the same steps.
  double farRaiseOf(int i) const { return winRaise[i] + render_internal::kRaiseMargin; }
  // Of the set operations listed, those without a window of their own (passed within a hair of
  // their box, not through it): a walk in lanes stops where it may enter their supports.
  int unwindowed = 0;
  bool inWindow(long qa, long qb) const {
    for (int i = 0; i < windows; ++i)
      if (winLo[i] <= qb && qa <= winHi[i]) return true;
    return false;
  }
  // The window holding q, or -1.
  int windowOf(long q) const {
    for (int i = 0; i < windows; ++i)
      if (winLo[i] <= q && q <= winHi[i]) return i;
    return -1;
  }
  // Stretches proven outside (beyond the field's domain; above the sheet's front face; outline
  // sheets: the ray over columns where W < 0).
  long skipLo[kMaxWindows], skipHi[kMaxWindows];
  int skips = 0;
  // The last point of the skip stretch holding q, or q - 1.
  long skipEnd(long q) const {
    for (int i = 0; i < skips; ++i)
      if (skipLo[i] <= q && q <= skipHi[i]) return skipHi[i];
    return q - 1;
  }
  bool inSkip(long qa, long qb) const {
    for (int i = 0; i < skips; ++i)
      if (skipLo[i] <= qa && qb <= skipHi[i]) return true;
    return false;
  }
  // Adds a window [lo, hi] where set operations raising f by at most `raise` act, merging
  // overlaps (their raises summed); too many windows become one up to `last`, its raise unknown.
  // A far window (`far`: a ball's far stretch, `raise` its farRaise) merged with any other has
  // an unknown raise.
  void addWindow(long lo, long hi, long last, double raise, bool far = false) {
    int i = 0;
    while (i < windows && winHi[i] < lo) ++i;
    int j = i;
    bool farMerged = false;
    while (j < windows && winLo[j] <= hi)
      lo = std::min(lo, winLo[j]), hi = std::max(hi, winHi[j]), raise += winRaise[j], farMerged |= far || winFar[j], ++j;
    if (farMerged) raise = std::numeric_limits<double>::infinity(), far = false;
    if (windows - (j - i) + 1 > kMaxWindows) {
      lo = std::min(lo, winLo[0]);
      winLo[0] = lo, winHi[0] = last, winRaise[0] = std::numeric_limits<double>::infinity(), winFar[0] = false, windows = 1;
      return;
    }
    const int tail = windows - j;
    std::move(winLo + j, winLo + j + tail, winLo + i + 1);
    std::move(winHi + j, winHi + j + tail, winHi + i + 1);
    std::move(winRaise + j, winRaise + j + tail, winRaise + i + 1);
    std::move(winFar + j, winFar + j + tail, winFar + i + 1);
    winLo[i] = lo, winHi[i] = hi, winRaise[i] = raise, winFar[i] = far;
    windows = i + 1 + tail;
  }
  // The first grid point >= q inside a window (or `none`).
  long nextWindow(long q, long none) const {
    for (int i = 0; i < windows; ++i)
      if (winHi[i] >= q) return std::max(q, winLo[i]);
    return none;
  }
};

// A ray of the field tracer clipped to the field's box (beginWalk()): its grid points from q0 to
// q1, and the (x, y) box of the points there.
struct Renderer::RayStart {
  Ray ray;
  long q0 = 0, q1 = 0;
  Box2 reach;
};

// A ray of the field tracer between its set-up (beginWalk()) and its end (endWalk()): the ray, its
// context, and its walk's state at the top of the walk's loop, where the walk can be handed over
// (to the walk in lanes, walk_lanes.h, and back).
struct Renderer::Walk {
  Ray ray;
  RayContext rc;
  double h8 = 0.0;    // grid points of the ray are t = q h8
  long q0 = 0, q1 = 0;  // the clip's, on the grid
  long q = 0;         // the walk's point
  bool known = false;  // f at q is known: fa (and fl, the value its Lipschitz bound holds for)
  double fa = 0.0, fl = 0.0;
  long prevQ = 0;      // the last point evaluated before q, and f there
  double prevF = -1.0;
  int shortSteps = 0;  // walk steps in a row shorter than kSubdivisions / 8
  double invStepH8 = 0.0, invRayH8 = 0.0;  // 1 / (kStepRate h8), 1 / (lf h8)
};

}  // namespace emboss
