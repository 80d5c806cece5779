// The field tracer's centre rays of a row, their walks taken several at once in SIMD lanes
// (walk_lanes.h) where they are plain Lipschitz steps, each ray set up and finished alone.
#include <algorithm>
#include <cmath>
#include <limits>

#include "frep/workpiece.h"
#include "render/ray_lanes.h"
#include "render/renderer_internal.h"
#include "render/walk_lanes.h"
#include "util/portable_math.h"

namespace emboss {

using namespace render_internal;

namespace {

// The rays a step of the lanes walks at once here.
int laneCount() {
  static const int n = std::min(walkLaneCount(), kMaxWalkLanes);
  return n;
}

}  // namespace

bool Renderer::walkFitsLanes(Walk& walk, RenderStats& st, long& window, long& end, LaneFar& far) const {
  const RayContext& rc = walk.rc;
  far = LaneFar{};
  if (!rc.lipschitz || rc.dense) return false;
  // The walk's first turns while each is a skip (endWalk()'s loop: the same state after them).
  while (walk.q < walk.q1 && !rc.inWindow(walk.q, walk.q)) {
    const long e = rc.skipEnd(walk.q);
    if (e < walk.q) break;
    ++st.steps;
    walk.q = e + 1;
    walk.known = false;
    walk.prevQ = walk.q0 - 2;
  }
  if (walk.q >= walk.q1 || walk.known) return false;
  // The window the walk is in or comes to first: a ball's far window the lane walks through too
  // (endWalk(): outside the windows' walk, its steps shortened), stopping at its end.
  int first = 0;
  while (first < rc.windows && rc.winHi[first] < walk.q) ++first;
  const bool farAhead = first < rc.windows && rc.winFar[first];
  if (!farAhead && rc.inWindow(walk.q, walk.q)) return false;
  // The lane stops at the next window, the next skip, the clip's end, or, when a set operation is
  // listed without a window (passed within a hair of its box), where the ray's (x, y) may enter a
  // set operation's support (two points early: f there may not be the workpiece's alone). A set
  // operation whose box (a ball's: capsule) the ray crosses changes f only in the stretch its
  // window holds with a point to spare each way (beginWalkFrom()): before it f is W.
  if (farAhead) {
    far.lo = rc.winLo[first], far.hi = rc.winHi[first];
    far.raise = rc.farRaiseOf(first);
    far.after = rc.nextWindow(far.hi + 1, walk.q1 + 1);
    window = std::max(walk.q + 1, far.lo);  // (before it: the step's cap; inside it, `after`)
    end = std::min(walk.q1, far.hi + 1);
  } else {
    window = rc.nextWindow(walk.q + 1, walk.q1 + 1);  // (q is in none: the first after it)
    end = std::min(walk.q1, window);
  }
  for (int i = 0; i < rc.skips; ++i)
    if (rc.skipLo[i] > walk.q) end = std::min(end, rc.skipLo[i]);
  if (rc.unwindowed == 0) return true;
  const RayClip clip(walk.ray);
  for (int k = 0; k < rc.setOpCount; ++k) {
    const Box2& s = rc.setOps[k]->support;
    double ta, tb;
    if (!clip(Box3{s.x0, s.y0, -1e30, s.x1, s.y1, 1e30}, ta, tb)) continue;
    const long entry = floorToLong(ta / walk.h8) - 2;
    if (entry <= walk.q) return false;
    end = std::min(end, entry);
  }
  return true;
}

WalkSheet Renderer::walkSheet() const {
  const Box3 b = model_->workpiece().bounds();  // (-w, -h, -d, w, h, d); a disc's w is its radius
  WalkSheet sheet{field_.lattice(), field_.domain(), &field_, workpieceKind_, b.x1, b.y1, b.z1, {}};
  if (workpieceKind_ == 4) {
    const ColumnMap& c = columns_;
    sheet.d = c.halfThickness;
    sheet.columns = c.view();
  }
  return sheet;
}

bool Renderer::walksInLanes() const {
  return options_.walkLanes && laneCount() >= 2 && (workpieceKind_ == 1 || workpieceKind_ == 2 || workpieceKind_ == 4) &&
         field_.configured();
}

void Renderer::sheetNormals(const double* x, const double* y, const double* z, const double* dv, const double* dgx,
                            const double* dgy, int n, double* nx, double* ny, double* nz, bool* done,
                            RenderStats& st) const {
  const int inLanes = walksInLanes() ? sheetNormalLanes(walkSheet(), x, y, z, dv, dgx, dgy, n, nx, ny, nz) : 0;
  if (inLanes == 0) {
    std::fill_n(done, n, false);
    return;
  }
  for (int k = 0; k < n; ++k) {
    // (fieldNormal() reads D from the field inside its domain, and applies the set operations
    // whose support holds the point: those are its own.)
    bool ok = k < inLanes && field_.contains(x[k], y[k]);
    // (An outline sheet's: where W is the slab.)
    if (ok && workpieceKind_ == 4) ok = columns_.halfThickness - std::abs(z[k] - dv[k]) <= columns_.at(x[k], y[k]).lo;
    if (ok) setOpSupports_.holding(x[k], y[k], [&](std::uint32_t) { ok = false; });
    done[k] = ok;
    if (ok) ++st.evaluations, ++st.fieldEvaluations;
  }
}

void Renderer::findFieldHits(const double* xs, const double* ys, int count, const Rect& reach, RenderStats& st,
                             std::vector<std::uint32_t>& scratch, double* kept, bool reuse,
                             std::optional<Hit>* out) const {
  const int lanes = laneCount();
  if (!walksInLanes()) {
    for (int i = 0; i < count; ++i)
      out[i] = findHit(xs[i], ys[i], true, reach, st, scratch, kept ? kept + i : nullptr, reuse, false);
    return;
  }
  const WalkSheet sheet = walkSheet();
  thread_local WalkLanes lane;
  thread_local Walk walks[kMaxWalkLanes];
  thread_local std::vector<const SetOp*> ops[kMaxWalkLanes];
  int pointOf[kMaxWalkLanes];
  for (int k = 0; k < kMaxWalkLanes; ++k) lane.state[k] = 0.0;
  lane.farLanes = 0;
  auto record = [&](int i, const std::optional<Hit>& hit) {
    out[i] = hit;
    if (kept) kept[i] = hit ? hit->t : std::numeric_limits<double>::infinity();
  };
  // A walk into lane k.
  auto load = [&](int k, const Walk& walk, long window, long end, const LaneFar& far) {
    const glm::dvec3 &o = walk.ray.origin, &d = walk.ray.dir;
    lane.ox[k] = o.x, lane.oy[k] = o.y, lane.oz[k] = o.z;
    lane.dx[k] = d.x, lane.dy[k] = d.y, lane.dz[k] = d.z;
    lane.h8[k] = walk.h8;
    lane.invStep[k] = walk.invStepH8, lane.invRay[k] = walk.invRayH8;
    lane.q0[k] = static_cast<double>(walk.q0), lane.q1[k] = static_cast<double>(walk.q1);
    lane.window[k] = static_cast<double>(window), lane.end[k] = static_cast<double>(end);
    lane.farLo[k] = static_cast<double>(far.lo), lane.farHi[k] = static_cast<double>(far.hi);
    lane.farRaise[k] = far.raise, lane.after[k] = static_cast<double>(far.after);
    if (far.lo <= far.hi) ++lane.farLanes;
    lane.ax[k] = d.x >= 0 ? d.x : 0.0, lane.bx[k] = d.x < 0 ? d.x : 0.0;
    lane.ay[k] = d.y >= 0 ? d.y : 0.0, lane.by[k] = d.y < 0 ? d.y : 0.0;
    lane.side[k] = workpieceKind_ == 1   ? std::max(std::abs(d.x), std::abs(d.y))
                   : workpieceKind_ == 2 ? std::sqrt(d.x * d.x + d.y * d.y)
                                         : 0.0;  // (lipschitzAlong(): the slab's rate alone)
    lane.q[k] = static_cast<double>(walk.q), lane.prevQ[k] = static_cast<double>(walk.prevQ);
    lane.prevF[k] = walk.prevF, lane.shortSteps[k] = walk.shortSteps;
    lane.f[k] = lane.l[k] = 0.0;
    lane.state[k] = 1.0;
  };
  // Lane k into the walk it stopped, which goes on alone (true) or in the lane again (false).
  auto finish = [&](int k) -> bool {
    Walk& walk = walks[k];
    walk.q = static_cast<long>(lane.q[k]);
    walk.prevQ = static_cast<long>(lane.prevQ[k]);
    walk.prevF = lane.prevF[k];
    walk.shortSteps = static_cast<int>(lane.shortSteps[k]);
    walk.known = lane.state[k] == 3.0;
    if (walk.known) walk.fa = lane.f[k], walk.fl = lane.l[k];
    // A point of a ball's far window: its f was W's there, not the ray's (never read as f).
    if (walk.prevQ >= static_cast<long>(lane.farLo[k]) && walk.prevQ <= static_cast<long>(lane.farHi[k]))
      walk.prevQ = walk.q0 - 2;
    if (lane.farLo[k] <= lane.farHi[k]) --lane.farLanes;
    lane.state[k] = 0.0;
    // A lane that stopped without f at the end of its stretch (a ball's far window passed, a
    // skip or a window reached; not one stopped off the field) goes on in lanes from there where
    // the rest of the walk fits them again (walkFitsLanes(): endWalk()'s turns through a skip
    // first): the same points, the same hit. Until stop 75 it went on alone: every ray that
    // passed under the ball of the visitor's sheet, high in its capsule, walked down alone.
    if (!walk.known && walk.q >= static_cast<long>(lane.end[k]) && walk.q < walk.q1) {
      long window = 0, end = 0;
      LaneFar far;
      if (walkFitsLanes(walk, st, window, end, far)) {
        load(k, walk, window, end, far);
        return false;
      }
    }
    record(pointOf[k], endWalk(walk, st, scratch, false));
    return true;
  };
  // The rays that walk, set up in lanes: their index among them (kKept for a kept hit reused,
  // kMisses for a ray outside the projection of every surface).
  constexpr int kKept = -1, kMisses = -2;
  thread_local std::vector<int> startOf;
  thread_local std::vector<double> wx, wy;
  thread_local RayStarts starts;
  startOf.resize(static_cast<size_t>(count)), wx.clear(), wy.clear();
  for (int i = 0; i < count; ++i) {
    if (kept && reuse && !std::isnan(kept[i])) {
      startOf[static_cast<size_t>(i)] = kKept;
      continue;
    }
    if (missesSurely(xs[i], ys[i], true, reach)) {
      startOf[static_cast<size_t>(i)] = kMisses;
      continue;
    }
    startOf[static_cast<size_t>(i)] = static_cast<int>(wx.size());
    wx.push_back(xs[i]), wy.push_back(ys[i]);
  }
  raysInLanes(camera_->basis(), fieldClip_, step_, step_ / kSubdivisions, wx.data(), wy.data(), static_cast<int>(wx.size()),
              starts);
  int next = 0, walking = 0;
  for (;;) {
    // Free lanes take the next rays that walk (the others are found here alone).
    for (int k = 0; k < lanes && next < count; ++k) {
      if (lane.state[k] != 0.0) continue;
      while (next < count) {
        const int i = next++;
        const double sx = xs[i], sy = ys[i];
        double* const k1 = kept ? kept + i : nullptr;
        const int j = startOf[static_cast<size_t>(i)];
        if (j == kKept) {
          out[i] = findHit(sx, sy, true, reach, st, scratch, k1, reuse, false);
          continue;
        }
        if (j == kMisses) {  // (as findHit() answers it)
          ++st.rays;
          record(i, std::nullopt);
          continue;
        }
        Walk& walk = walks[k];
        bool begun = false;
        switch (starts.state[static_cast<size_t>(j)]) {
          case RayStarts::kAlone:
            begun = beginWalk(sx, sy, st, ops[k], walk, 0);
            break;
          case RayStarts::kClipped: {
            ++st.rays;
            const size_t u = static_cast<size_t>(j);
            RayStart rs;
            rs.ray = Ray{{starts.ox[u], starts.oy[u], starts.oz[u]}, {starts.dx[u], starts.dy[u], starts.dz[u]}};
            rs.q0 = kSubdivisions * static_cast<long>(starts.g0[u]);
            rs.q1 = kSubdivisions * static_cast<long>(starts.g1[u]);
            rs.reach = Box2{starts.rx0[u], starts.ry0[u], starts.rx1[u], starts.ry1[u]};
            begun = beginWalkFrom(rs, st, ops[k], walk, 0);
            break;
          }
          default:  // (the ray misses the field's box)
            ++st.rays;
            break;
        }
        if (!begun) {
          record(i, std::nullopt);
          continue;
        }
        long window = 0, end = 0;
        LaneFar far;
        if (!walkFitsLanes(walk, st, window, end, far)) {
          record(i, endWalk(walk, st, scratch, false));
          continue;
        }
        load(k, walk, window, end, far);
        ++st.laneRays;
        pointOf[k] = i;
        ++walking;
        break;
      }
    }
    if (walking == 0) break;
    std::uint64_t evaluations = 0;
    walkLanes(sheet, lane, st.steps, evaluations, st.farSteps);
    st.evaluations += evaluations, st.fieldEvaluations += evaluations;
    for (int k = 0; k < lanes; ++k)
      if ((lane.state[k] == 2.0 || lane.state[k] == 3.0) && finish(k)) --walking;
  }
}

}  // namespace emboss
