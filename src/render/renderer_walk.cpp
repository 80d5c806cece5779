// The field tracer's walk along a ray (renderer.h; docs/rendering.md, "The root finder"): the ray
// set up (its clip, grid, reach, slope bound, windows and skips), walked along its grid to the
// first point with f >= 0, and its hit placed inside that point's bracket. The values the walk
// reads (f, its bounds over a stretch, the normal) are renderer_field.cpp's; the walks taken in
// SIMD lanes, renderer_lanes.cpp's.
#include <algorithm>
#include <limits>

#include "render/renderer_internal.h"
#include "util/portable_math.h"

namespace emboss {

using namespace render_internal;

bool Renderer::beginWalk(double sx, double sy, RenderStats& st, std::vector<const SetOp*>& rayOps, Walk& walk,
                         int startRefinements) const {
  // (The ray and h8 in locals here and in endWalk(), as traceField() had them whole: read through
  // `walk` they would be read again after every call.)
  RayStart s;
  s.ray = camera_->rayAt(sx, sy);
  ++st.rays;
  double t0, t1;
  if (!clipRay(s.ray, fieldClip_, t0, t1)) {
    walk.ray = s.ray;
    return false;
  }
  const double h = step_, h8 = h / kSubdivisions;
  // Points of the ray are t = q h / kSubdivisions for integers q: the same points whatever the clip.
  s.q0 = kSubdivisions * floorToLong(t0 / h);
  s.q1 = kSubdivisions * ceilToLong(t1 / h);
  const glm::dvec3 pa = s.ray.origin + (static_cast<double>(s.q0) * h8) * s.ray.dir;
  const glm::dvec3 pb = s.ray.origin + (static_cast<double>(s.q1) * h8) * s.ray.dir;
  s.reach = Box2{std::min(pa.x, pb.x), std::min(pa.y, pb.y), std::max(pa.x, pb.x), std::max(pa.y, pb.y)};
  return beginWalkFrom(s, st, rayOps, walk, startRefinements);
}

bool Renderer::beginWalkFrom(const RayStart& start, RenderStats& st, std::vector<const SetOp*>& rayOps, Walk& walk,
                             int startRefinements) const {
  const Ray ray = start.ray;
  walk.ray = ray;
  const double h8 = step_ / kSubdivisions;
  walk.h8 = h8;
  const long q0 = start.q0, q1 = start.q1;
  walk.q0 = q0, walk.q1 = q1;
  auto at = [&](long q) { return ray.origin + (static_cast<double>(q) * h8) * ray.dir; };

  RayContext& rc = walk.rc;  // (its lists' arrays are read only up to their counts)
  rc.setOps = nullptr, rc.setOpCount = 0, rc.dense = false, rc.lipschitz = false, rc.lf = 0.0;
  rc.windows = 0, rc.skips = 0, rc.unwindowed = 0;
  const Box2 reach = start.reach;
  // The set operations the ray can meet: of those whose support meets its reach, those whose box
  // (the support, the z range) the ray crosses or passes within a hair of (SetOp::hair: the ray's
  // points as rounded; the z range's rounding margin, SetOp::toolZlo). No other changes f at a
  // point of the ray, so none can change a value, or a test's bound for a stretch of the ray:
  // leaving them out of the ray's list changes no hit (a third of those listed by support alone,
  // on the visitor's sheet). The boxes it crosses keep their stretches of the ray, in order, for
  // the windows below (the first kDenseSetOps; more make the ray dense).
  int crossed = 0;
  double denseA = 1e300, denseB = -1e300, denseRaise = 0.0;
  double crossA[kDenseSetOps], crossB[kDenseSetOps], crossRaise[kDenseSetOps];
  // A ball's smooth union crossed: the stretch of its window near the tool (crossNearA > crossNearB:
  // none), the rest of the window far (its raise there, SetOp::farRaise; infinite: not a ball's).
  double crossNearA[kDenseSetOps], crossNearB[kDenseSetOps], crossFarRaise[kDenseSetOps];
  const bool farWindows = options_.ballFarWindows && workpieceKind_ != 4;
  double listedRaise = 0.0;  // of those listed without crossing their box: they count in every window
  rayOps.clear();
  const RayClip clip(ray);
  const bool roundWindows = options_.roundWindows;
  setOpSupports_.meeting(reach, [&](std::uint32_t k) {
    const SetOp& s = setOps_[k];
    const Box3 box{s.support.x0, s.support.y0, s.zlo, s.support.x1, s.support.y1, s.zhi};
    // A ball's window is its capsule (grown by the hair, past the roots' rounding) within the box;
    // a ray that misses the capsule passes where f is exactly W's, and is not listed.
    const bool ball = s.round && roundWindows;
    double ta, tb;
    bool crosses = clip(box, ta, tb);
    if (crosses && ball) {
      double ca, cb;
      crosses = clipUprightCapsule(ray, s.cx, s.cy, s.czlo, s.czhi, s.radius + s.hair, ca, cb) &&
                std::max(ta, ca) < std::min(tb, cb);
      if (crosses) ta = std::max(ta, ca), tb = std::min(tb, cb);
    }
    if (crosses) {
      const double raise = s.upper.raise();
      if (crossed < kDenseSetOps) {
        crossA[crossed] = ta, crossB[crossed] = tb, crossRaise[crossed] = raise;
        crossFarRaise[crossed] = ball && farWindows ? s.farRaise : std::numeric_limits<double>::infinity();
        if (std::isfinite(crossFarRaise[crossed])) {
          // The stretch near the tool: the ray in the capsule of nearRadius (grown by the hair)
          // within the window.
          double na, nb;
          const bool near = clipUprightCapsule(ray, s.cx, s.cy, s.czlo, s.czhi, s.nearRadius + s.hair, na, nb);
          crossNearA[crossed] = near ? std::max(ta, na) : 1.0, crossNearB[crossed] = near ? std::min(tb, nb) : 0.0;
        }
      }
      ++crossed, denseA = std::min(denseA, ta), denseB = std::max(denseB, tb), denseRaise += raise;
    } else {
      if (options_.cullRaySetOps) {
        const double h = s.hair;
        if (ball || !clip(Box3{box.x0 - h, box.y0 - h, box.z0 - h, box.x1 + h, box.y1 + h, box.z1 + h}, ta, tb)) {
          ++st.setOpsLeftOut;
          return;
        }
      }
      listedRaise += s.upper.raise();
      ++rc.unwindowed;
    }
    rayOps.push_back(&s);
  });
  rc.setOps = rayOps.data();
  rc.setOpCount = static_cast<int>(rayOps.size());
  const Box2 dom = field_.domain();
  double tda = 0, tdb = 0;
  const bool reachInDomain = field_.containsBox(reach);
  if (reachInDomain) tda = static_cast<double>(q0) * h8 - 1.0, tdb = static_cast<double>(q1) * h8 + 1.0;
  if (workpieceKind_ != 0 && (reachInDomain || clipRay(ray, Box3{dom.x0, dom.y0, -1e30, dom.x1, dom.y1, 1e30}, tda, tdb))) {
    // W(x, y, z - D) with a known Lipschitz bound for W (see lipschitzAlong()), D's slopes from
    // the field. Beyond the field's domain (the workpiece's bounds and a margin) W < 0: skipped.
    rc.lipschitz = true;
    const Box2 r = reach.intersected(dom);
    const HeightField::Bound rb = field_.bound(r);
    rc.lf = lipschitzAlong(ray.dir, rb, workpieceKind_);
    const long qa = ceilToLong(tda / h8) - 2, qb = floorToLong(tdb / h8) + 2;
    if (qa >= q0) rc.skipLo[rc.skips] = q0, rc.skipHi[rc.skips] = qa, ++rc.skips;
    if (qb <= q1) rc.skipLo[rc.skips] = qb, rc.skipHi[rc.skips] = q1, ++rc.skips;
    // The windows where a set operation can act: the ray inside its box (found above).
    // A ray through many set operations' boxes (a tangle of a blending punch's beads) is dense:
    // one window from the first box to the last, searched on the cells' ends (below). Whether a
    // ray is dense and its window are functions of the ray and the model alone (every set
    // operation's box, whatever the clip), so a dirty update finds the hit a full render finds.
    // A box the ray crosses lies in the clip box, so its support overlaps the ray's reach: the
    // operations found above are all the ray can cross.
    if (crossed >= kDenseSetOps) {
      rc.dense = true;
      ++st.denseRays;
      rc.addWindow(floorToLong(denseA / h8) - 1, ceilToLong(denseB / h8) + 1, q1, denseRaise + listedRaise);
    } else {
      for (int i = 0; i < crossed; ++i) {
        const long lo = floorToLong(crossA[i] / h8) - 1, hi = ceilToLong(crossB[i] / h8) + 1;
        // (Three windows a ball: split only where they all fit, else one window as before.)
        const double farRaise = crossFarRaise[i];
        if (!std::isfinite(farRaise) || crossed > RayContext::kMaxWindows / 3) {
          rc.addWindow(lo, hi, q1, crossRaise[i]);
          continue;
        }
        // A ball's smooth union: its near stretch (a point to spare each way) as any window, the
        // rest of the window before and after it far windows.
        if (crossNearA[i] > crossNearB[i]) {
          rc.addWindow(lo, hi, q1, farRaise, true);
          continue;
        }
        const long nlo = floorToLong(crossNearA[i] / h8) - 1, nhi = ceilToLong(crossNearB[i] / h8) + 1;
        if (lo <= nlo - 1) rc.addWindow(lo, nlo - 1, q1, farRaise, true);
        rc.addWindow(std::max(lo, nlo), std::min(hi, nhi), q1, crossRaise[i]);
        if (nhi + 1 <= hi) rc.addWindow(nhi + 1, hi, q1, farRaise, true);
      }
      // Those listed without a window count in every window; a far one's bound then no longer holds.
      for (int i = 0; i < rc.windows; ++i) {
        if (rc.winFar[i] && listedRaise != 0.0) rc.winRaise[i] = std::numeric_limits<double>::infinity(), rc.winFar[i] = false;
        rc.winRaise[i] += listedRaise;
      }
    }
    // Above the sheet's front face over the ray's reach f < 0 (outside the windows): a ray from
    // above skips to where it goes under that face's highest point (the clip box also holds the
    // set operations' tools), or to the first window.
    if (frontThickness_ >= 0.0 && ray.dir.z < 0.0 && reachInDomain) {
      const double perQ = 1.0 / (ray.dir.z * h8);  // (a reciprocal: this is asked up to four times)
      auto under = [&](double hi) { return floorToLong((hi + frontThickness_ + 1e-6 - ray.origin.z) * perQ) - 1; };
      long topQ = under(rb.hi);
      // The rest of the ray, from there, reaches less of the sheet: its highest point there may be
      // lower (a ray over flat metal beside a raised motif), a few times over (each time a bound
      // from the field's pyramid: worth it for a ray that walks alone, not for one in lanes).
      for (int k = 0; k < startRefinements && topQ > q0 && topQ < q1; ++k) {
        const long next = under(field_.bound(xyBox(at(topQ), at(q1))).hi);
        if (next <= topQ) break;
        topQ = next;
      }
      const long e = std::min({topQ, q1, rc.nextWindow(q0, q1 + 1) - 1});
      if (e >= q0) rc.skipLo[rc.skips] = q0, rc.skipHi[rc.skips] = e, ++rc.skips;
    }
    if (workpieceKind_ == 4 && columns_.anyOutside(reach)) {
      // Outline sheets: follow the ray over the column blocks (a 2D DDA); stretches over outside
      // columns are skipped (where the ray's reach has any: most rays have none).
      const ColumnMap& c = columns_;
      const double tStart = static_cast<double>(q0) * h8, tEnd = static_cast<double>(q1) * h8;
      SquareWalk blocks(ray, tStart, c.x0, c.y0, c.size, c.inv);
      double t = tStart, runStart = tStart;
      int runClass = -1;
      auto endRun = [&](double tb) {
        // Boundary columns need no window: W <= the slab there, whose Lipschitz bound holds.
        if (runClass == 0 && rc.skips < RayContext::kMaxWindows) {
          const long lo = ceilToLong(runStart / h8) + 1, hi = floorToLong(tb / h8) - 1;
          if (lo <= hi) rc.skipLo[rc.skips] = lo, rc.skipHi[rc.skips] = hi, ++rc.skips;
        }
      };
      for (int guard = 0; t < tEnd; ++guard) {
        const int k = c.block(blocks.i, blocks.j).hi < 0.0f ? 0 : 1;  // 0: outside
        if (k != runClass) {
          endRun(t);
          runClass = k, runStart = t;
        }
        if (guard > 4096) break;  // a very long path: the rest is not skipped
        t = blocks.next();
      }
      endRun(std::min(t, tEnd));
    }
  } else {
    rc.winLo[0] = q0, rc.winHi[0] = q1, rc.winRaise[0] = std::numeric_limits<double>::infinity(), rc.winFar[0] = false;
    rc.windows = 1;
  }
  // The walk's state at the top of its loop, at its start.
  walk.q = q0;
  walk.known = false;
  walk.fa = walk.fl = 0.0;
  walk.prevQ = q0 - 2;
  walk.prevF = -1.0;
  walk.shortSteps = 0;
  walk.invStepH8 = 1.0 / (kStepRate * h8), walk.invRayH8 = 1.0 / (rc.lf * h8);
  return true;
}

std::optional<Renderer::Hit> Renderer::endWalk(Walk& walk, RenderStats& st, std::vector<std::uint32_t>& scratch,
                                               bool normal) const {
  // A walk the lanes handed back at a hit they bracketed (f(q) >= 0 known, f(q - 1) < 0 just
  // before it): the loop's first turn below would find just that; the secant at once.
  if (walk.known && walk.fa >= 0.0 && walk.prevQ == walk.q - 1 && walk.q > walk.q0 && walk.q < walk.q1 &&
      !walk.rc.inWindow(walk.q, walk.q) && walk.rc.skipEnd(walk.q) < walk.q) {
    ++st.steps;
    return bracketHit(walk, walk.q, walk.prevF, walk.fa, st, scratch, normal);
  }
  const Ray ray = walk.ray;
  const RayContext& rc = walk.rc;
  const double h8 = walk.h8;
  const long q0 = walk.q0, q1 = walk.q1;
  const Box2 dom = field_.domain();
  auto at = [&](long q) { return ray.origin + (static_cast<double>(q) * h8) * ray.dir; };  // (as beginWalk's)

  // f at grid point q, and the value its Lipschitz bound holds for.
  struct Val {
    double f, l;
  };
  auto value = [&](long q) {
    Val v;
    v.f = fieldValue(rc, at(q), st, scratch, &v.l);
    return v;
  };
  // Whether f < 0 is proven over [qa, qb] (never decides a hit, only skips work).
  auto empty = [&](long qa, const Val& a, long qb, const Val& b) {
    const bool window = rc.inWindow(qa, qb);
    if (!window && rc.inSkip(qa, qb)) return true;
    if (!window && field_.contains(at(qa).x, at(qa).y) && field_.contains(at(qb).x, at(qb).y)) {
      if (0.5 * (a.l + b.l + rc.lf * static_cast<double>(qb - qa) * h8) < -kPruneEps) return true;
      // Outline sheets inside the slab, over boundary columns: the columns, then intervals.
      if (workpieceKind_ != 4) return false;
    }
    return fieldExcluded(rc, at(qa), at(qb), st, scratch);
  };
  const Val unknown{-1.0, -1.0};
  constexpr long kCell = kSubdivisions;
  // The end of a cell of the whole ray's grid at or before q: the multiple of kCell (q may be negative).
  const auto cellEndAtOrBefore = [](long q) { return (q >= 0 ? q / kCell : -((-q + kCell - 1) / kCell)) * kCell; };
  const bool linearCells = workpieceKind_ == 4 && rc.setOpCount == 0 && options_.scanOutlineCells;
  // The first q in (qa, qb] with f(q) >= 0, given f(qa) < 0: sets the bracket [q - 1, q].
  long bq = 0;
  double bfa = 0, bfb = 0;
  auto search = [&](auto& self, long qa, const Val& a, long qb, const Val& b, bool checked) -> bool {
    ++st.steps;
    // A single step is decided by its end alone: no interval test (it could only say what b.f
    // says). Two steps are decided by their middle: a test would save that one value when it
    // passed, and it passed a third of the time (the visitor's sheet, in windows). Until stop 60
    // both were tested: two thirds of a bisection's tests on that sheet.
    if (qb - qa == 1) {
      if (b.f < 0.0) return false;
      bq = qb, bfa = a.f, bfb = b.f;
      return true;
    }
    // A dense ray's window is sampled: a cell whose end is outside is passed, and one whose end is
    // inside is bisected to a crossing (no interval tests, which fail near such a tangle and
    // would send the search down to every sixteenth of the cell).
    if (b.f < 0.0 && !checked && ((rc.dense && rc.inWindow(qa, qb)) || (qb - qa > 2 && empty(qa, a, qb, b))))
      return false;
    // An outline sheet's cell near the outline (its interval test failed) is scanned point by
    // point, not bisected: the smaller boxes straddle the outline's wall as the cell did, and a
    // point through its block's tape costs less than an interval. The same first point with
    // f >= 0, so the same hit (performance.md, "Stop 52").
    if (linearCells && qb - qa <= kCell) {
      Val prev = a;
      for (long q = qa + 1; q <= qb; ++q) {
        const Val v = q == qb ? b : value(q);
        if (v.f >= 0.0) {
          bq = q, bfa = prev.f, bfb = v.f;
          return true;
        }
        prev = v;
      }
      return false;
    }
    const long qm = qa + (qb - qa) / 2;
    const Val m = value(qm);
    if (self(self, qa, a, qm, m, false)) return true;
    return self(self, qm, m, qb, b, false);
  };

  std::optional<double> tHit;
  bool bracketed = false;
  constexpr long kSpan = 8 * kSubdivisions;  // interval spans of 8 cells
  long q = walk.q;
  bool known = walk.known;  // fa = f(q)
  Val fa{walk.fa, walk.fl};
  long prevQ = walk.prevQ;  // the last point evaluated before q, and its value
  double prevF = walk.prevF;
  int shortSteps = walk.shortSteps;
  // Inside windows: the stretches whose interval tests failed (none yet: a walk comes here from its
  // start or from the lanes, which never enter a window).
  long failedUntil[3] = {q0 - 1, q0 - 1, q0 - 1};
  constexpr long kLevels[4] = {4 * kSpan, kSpan, 2 * kCell, kCell};  // (the tests' stretches, below)
  // Of a step's quotients (below), the two whose divisors are fixed for the ray are products with
  // these reciprocals (Walk): a division is the slowest link of the step's chain.
  const double invStepH8 = walk.invStepH8, invRayH8 = walk.invRayH8;
  // Lipschitz steps inside windows (below): where W's bound holds (not an outline sheet, whose
  // Lipschitz value is the slab). A dense ray's window is sampled on the cells' ends: its steps
  // land on them.
  const bool lipschitzInWindows = options_.lipschitzInWindows && rc.lipschitz && workpieceKind_ != 4;
  long lipschitzTriedUntil = q0 - 1;
  const bool pileTops = pileTopsNow_ && options_.pileTops && pileTops_.top && ray.dir.z < 0.0;
  while (q < q1) {
    ++st.steps;
    bool cellChecked = false;  // the interval test of [q, q + kCell] ran (and failed)
    const int wq = rc.windowOf(q);
    if (wq < 0 || rc.winFar[wq]) {
      // In a ball's far window the walk is the same, its steps shortened by the window's raise:
      // f < 0 wherever W < -raise there (SetOp::farRaise).
      const double raise = wq < 0 ? 0.0 : rc.farRaiseOf(wq);
      if (const long e = rc.skipEnd(q); e >= q) {
        q = e + 1;
        known = false;
        prevQ = q0 - 2;
        continue;
      }
      // Outside the windows f = W(x, y, z - D): a Lipschitz walk along the grid. From q, every
      // point closer than -f(q) / lf is proven outside; the walk goes to the first one that is
      // not (never into a window unseen). The first point found with f >= 0 is the canonical one.
      if (!known) fa = value(q), known = true;
      if (fa.f >= 0.0) {
        if (q == q0) {  // the camera is inside the piece
          tHit = static_cast<double>(q) * h8;
          break;
        }
        bfa = prevQ == q - 1 ? prevF : value(q - 1).f;
        bq = q, bfb = fa.f, bracketed = true;
        break;
      }
      // The slopes of D where the walk can go (at most -f(q) / |dir| = -f(q) from q).
      long n = 0;
      const glm::dvec3 pq = at(q);
      if (!field_.contains(pq.x, pq.y)) {
        // At the edge of the field's domain: no Lipschitz bound; one point at a time.
      } else if (fa.l >= 0.0 && workpieceKind_ == 4) {
        // Within the slab of an outline sheet but outside the outline: no Lipschitz step; the
        // cell is searched with the columns' and the workpiece's bounds.
        if (fieldExcluded(rc, at(q), at(q + kCell), st, scratch)) {
          q += kCell;
          known = false;
          prevQ = q0 - 2;
          continue;
        }
        // The cell is searched below; its interval test (the one empty() would make) just failed.
        cellChecked = !rc.dense;
        shortSteps = 5;
      } else if (const double room = -fa.l - raise; room > 0.0) {
        // The stretch the step can reach when the ray's slope bound is at least kStepRate; a step
        // is never longer than the stretch its bound holds on (lf can be below 1 on a shallow
        // ray), and the whole ray's bound holds everywhere. It stops before the next window (in
        // a far window: the next after it).
        const long reachQ = std::min(q1, q + static_cast<long>(std::min(room * invStepH8, 1e15)) + 1);
        const Box2 step = xyBox(pq, at(reachQ));
        const Box2 inDomain = step.intersected(dom);
        const double lf = lipschitzAlong(ray.dir, field_.bound(inDomain), workpieceKind_);
        n = std::min(static_cast<long>(std::min((room - kPruneEps) / (lf * h8), 1e15)), reachQ - q - 1);
        n = std::max(n, static_cast<long>(std::min((room - kPruneEps) * invRayH8, 1e15)));
        n = std::max(0L, std::min(n, rc.nextWindow(wq < 0 ? q + 1 : rc.winHi[wq] + 1, q1 + 1) - q - 1));
      }
      if (wq >= 0) ++st.farSteps;
      shortSteps = n < kSubdivisions / 8 ? shortSteps + 1 : 0;
      if (shortSteps < 6) {
        prevQ = q, prevF = fa.f;
        q += n + 1;
        known = false;
        continue;
      }
      // Creeping along a near miss: search a whole cell at once instead.
      shortSteps = 0;
    } else {
      // Inside a window: skip what intervals prove empty, trying long stretches first (a failed
      // stretch is not tried again until it is passed): 32, 8, 2 cells, then one. A dense ray
      // stops at two: its window is sampled at the cells' ends, so a cell's test saves one value
      // at most, and near its tangle's surface such tests fail as often as not (the window of
      // the visitor's sheet in docs/performance.md, "Stop 59": 9 % less time than 32, 8 and 1
      // cells for every ray).
      // First the stretch above the pile's tops of the columns the ray crosses (pileSkip()), to
      // the next point (a dense ray: the last cell's end) not proven outside.
      if (pileTops) {
        const long last = pileSkip(ray, h8, q, q1);
        const long to = !rc.dense ? last + 1 : cellEndAtOrBefore(last);
        if (to > q) {
          ++st.pileSkips;
          q = std::min(to, q1);
          // Where it lands the pile is near: the tests of 32 and 8 cells would fail.
          failedUntil[0] = q + kLevels[0], failedUntil[1] = q + kLevels[1];
          known = false;
          prevQ = q0 - 2;
          continue;
        }
      }
      // Then, from high above the sheet, a Lipschitz step as outside: inside window w, f <= W +
      // winRaise[w] (the subtractions there raise f by their bumps at most), so every point
      // closer than -(W(q) + winRaise[w]) / lf is proven outside. Tried until it first falls
      // short of a cell in a window (near the surface it does, and the tests below take over).
      if (lipschitzInWindows && q >= lipschitzTriedUntil) {
        const int w = rc.windowOf(q);
        const glm::dvec3 pq = at(q);
        double room = -1.0;
        if (std::isfinite(rc.winRaise[w]) && field_.contains(pq.x, pq.y)) {  // (a union: no step)
          double l;
          if (known) {
            l = fa.l;
          } else {
            ++st.evaluations, ++st.fieldEvaluations;
            l = sheetValue(pq);
          }
          room = -l - rc.winRaise[w] - kRaiseMargin;
        }
        const long n = room > 0.0 ? static_cast<long>(std::min(room * invRayH8, 1e15)) : -1;
        // Every point up to q + n is proven outside: the walk goes on from the next, or a dense ray
        // from the last cell's end among them (its cells stay the whole ray's grid's).
        const long last = q + n;
        const long to = !rc.dense ? last + 1 : cellEndAtOrBefore(last);
        if (n >= kCell && to > q) {
          ++st.windowSteps;
          q = std::min(to, std::min(rc.winHi[w] + 1, q1));
          known = false;
          prevQ = q0 - 2;
          continue;
        }
        lipschitzTriedUntil = rc.winHi[w] + 1;
      }
      const int levels = rc.dense ? 3 : 4;
      bool skipped = false;
      for (int level = 0; level < levels && !skipped; ++level) {
        const long len = kLevels[level];
        const bool last = level == levels - 1;
        if (!last && q < failedUntil[level]) continue;
        if (empty(q, unknown, q + len, unknown)) {
          q += len;
          skipped = true;
        } else if (!last) {
          failedUntil[level] = q + len;
        }
      }
      if (skipped) {
        known = false;
        prevQ = q0 - 2;
        continue;
      }
      cellChecked = true;
      if (!known) fa = value(q), known = true;
      if (fa.f >= 0.0) {
        if (q == q0) {
          tHit = static_cast<double>(q) * h8;
          break;
        }
        bfa = prevQ == q - 1 ? prevF : value(q - 1).f;
        bq = q, bfb = fa.f, bracketed = true;
        break;
      }
    }
    // A dense ray's window is searched on the cells of the grid of the whole ray (q multiple of
    // kCell, whatever the clip): the first step into it goes to the next such end.
    const long qn = rc.dense ? cellEndAtOrBefore(q) + kCell : q + kCell;
    const Val fb = value(qn);
    if (search(search, q, fa, qn, fb, cellChecked)) {
      bracketed = true;
      break;
    }
    prevQ = q0 - 2;  // f(qn - 1) is not known
    q = qn, fa = fb;
  }
  if (bracketed) return bracketHit(walk, bq, bfa, bfb, st, scratch, normal);
  if (!tHit) return std::nullopt;
  ++st.hits;
  const glm::dvec3 p = ray.origin + *tHit * ray.dir;
  return Hit{p, normal ? fieldNormal(p, st, scratch) : glm::dvec3(0.0), ray.dir, *tHit};
}

Renderer::Hit Renderer::bracketHit(const Walk& walk, long bq, double bfa, double bfb, RenderStats& st,
                                   std::vector<std::uint32_t>& scratch, bool normal) const {
  // The secant inside [bq - 1, bq]: a function of f at those two points alone. That sixteenth
  // of a cell is at most 16 micrometres, a fifth of a pixel of the bench's closest view (a
  // regula falsi step inside a sixty-fourth changed three pixels in a million, for an
  // evaluation a hit).
  const double h8 = walk.h8;
  const double a = static_cast<double>(bq - 1) * h8, b = static_cast<double>(bq) * h8;
  const double t = std::clamp(b - bfb * (b - a) / (bfb - bfa), a, b);
  ++st.hits;
  const glm::dvec3 p = walk.ray.origin + t * walk.ray.dir;
  return Hit{p, normal ? fieldNormal(p, st, scratch) : glm::dvec3(0.0), walk.ray.dir, t};
}


std::optional<Renderer::Hit> Renderer::traceField(double sx, double sy, RenderStats& st,
                                                  std::vector<std::uint32_t>& scratch, bool normal) const {
  thread_local std::vector<const SetOp*> rayOps;
  Walk walk;
  if (!beginWalk(sx, sy, st, rayOps, walk, 3)) return std::nullopt;
  return endWalk(walk, st, scratch, normal);
}

}  // namespace emboss
