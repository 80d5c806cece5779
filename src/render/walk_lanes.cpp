// walkLanes for each SIMD target Highway knows (compiled once per target by foreach_target.h), and
// the run-time choice among them. A step mirrors one turn of Renderer::endWalk()'s loop outside
// the windows (renderer_walk.cpp) line by line: the point, D, f, the stretch, its slope bound, the
// step.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/walk_lanes.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "render/walk_lanes.h"
#include "render/height_field.h"
#include "render/hermite-inl.h"
#include "render/std_minmax-inl.h"

#include <cstddef>
#include <cstdint>
#include <limits>

HWY_BEFORE_NAMESPACE();
namespace emboss {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using WalkTag = hn::CappedTag<double, kMaxWalkLanes>;

int WalkLaneCount() { return static_cast<int>(hn::Lanes(WalkTag())); }

// kFar: some lane has a ball's far window (WalkLanes::farLanes); without, the step is the one
// before far windows, none of their terms worked out.
template <bool kFar>
void StepLanes(const WalkSheet& sheet, WalkLanes& w, uint64_t* counts) {
  const WalkTag d;
  using V = hn::Vec<WalkTag>;
  const size_t lanes = hn::Lanes(d);
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0);
  const V state = hn::Load(d, w.state);
  const auto stepping = hn::Eq(state, one);                 // at q, f not known
  const auto bracketing = hn::Eq(state, hn::Set(d, 4.0));  // f(q) >= 0 known: f(q - 1) wanted
  const auto walking = hn::Or(stepping, bracketing);
  if (hn::AllFalse(d, walking)) return;
  const V q = hn::Load(d, w.q), h8 = hn::Load(d, w.h8);
  const V qe = hn::IfThenElse(bracketing, hn::Sub(q, one), q);  // the point evaluated
  const V ox = hn::Load(d, w.ox), oy = hn::Load(d, w.oy), oz = hn::Load(d, w.oz);
  const V dx = hn::Load(d, w.dx), dy = hn::Load(d, w.dy), dz = hn::Load(d, w.dz);
  // The point: origin + (q h8) dir (Walk::at()).
  const V t = hn::Mul(qe, h8);
  const V px = hn::Add(ox, hn::Mul(t, dx)), py = hn::Add(oy, hn::Mul(t, dy)), pz = hn::Add(oz, hn::Mul(t, dz));
  // Inside the field's domain (HeightField::contains()); elsewhere the ray walks alone.
  const Box2& dom = sheet.domain;
  const auto inField = hn::And(hn::And(hn::Ge(px, hn::Set(d, dom.x0)), hn::Ge(py, hn::Set(d, dom.y0))),
                               hn::And(hn::Le(px, hn::Set(d, dom.x1)), hn::Le(py, hn::Set(d, dom.y1))));

  // D there: HeightField::value() (a lane outside the field reads a clamped cell, unused).
  const SampleLattice& l = sheet.lattice;
  const V s = hn::Set(d, l.s);
  const V fx = hn::Mul(hn::Sub(px, hn::Set(d, l.x0)), hn::Set(d, l.invS));
  const V fy = hn::Mul(hn::Sub(py, hn::Set(d, l.y0)), hn::Set(d, l.invS));
  V u, v;
  HWY_ALIGN int32_t first[kMaxWalkLanes];
  Cells(d, fx, fy, l.nx, l.ny, u, v, first);
  // The four corners' samples (00, 10, 01, 11), four floats each, read lane by lane.
  const hn::Rebind<float, WalkTag> df;
  HWY_ALIGN float c[16][kMaxWalkLanes];
  ReadCorners(l, first, lanes, c);
  auto at = [&](int m) { return hn::PromoteTo(d, hn::Load(df, c[m])); };
  V D;
  {
    const V d00 = at(0), x00 = at(1), y00 = at(2), t00 = at(3);
    const V d10 = at(4), x10 = at(5), y10 = at(6), t10 = at(7);
    const V d01 = at(8), x01 = at(9), y01 = at(10), t01 = at(11);
    const V d11 = at(12), x11 = at(13), y11 = at(14), t11 = at(15);
    V buH0, buH1, buG0, buG1, bvH0, bvH1, bvG0, bvG1;
    Basis(u, buH0, buH1, buG0, buG1), Basis(v, bvH0, bvH1, bvG0, bvG1);
    const V a0 = Row(buH0, buH1, buG0, buG1, s, d00, d10, x00, x10);
    const V a1 = Row(buH0, buH1, buG0, buG1, s, d01, d11, x01, x11);
    const V b0 = Row(buH0, buH1, buG0, buG1, s, y00, y10, t00, t10);
    const V b1 = Row(buH0, buH1, buG0, buG1, s, y01, y11, t01, t11);
    D = Row(bvH0, bvH1, bvG0, bvG1, s, a0, a1, b0, b1);
  }
  // f: the workpiece at (x, y, z - D) (workpieces.h, its eval()), and the value its Lipschitz
  // bound holds for (lb).
  const V zp = hn::Sub(pz, D);
  const V W = hn::Set(d, sheet.w), T = hn::Set(d, sheet.d);
  V f, lb;
  auto eval = hn::And(walking, inField);
  if (sheet.kind == 4) {
    // Renderer::fieldValue(): the slab where it is at most the column's lo, the column's hi where
    // that is negative (no set operation's support is near a lane), else the outline's program:
    // the ray's own walk's.
    const V slab = hn::Sub(T, hn::Abs(hn::Sub(pz, D)));
    const WalkSheet::Columns& c = sheet.columns;
    HWY_ALIGN double xs[kMaxWalkLanes], ys[kMaxWalkLanes], colLo[kMaxWalkLanes], colHi[kMaxWalkLanes];
    hn::Store(px, d, xs), hn::Store(py, d, ys);
    for (size_t k = 0; k < lanes; ++k) {
      const WalkSheet::Columns::Bounds b = c.at(xs[k], ys[k]);  // (the scalar walk's own lookup)
      colLo[k] = b.lo, colHi[k] = b.hi;
    }
    const V lo = hn::Load(d, colLo), hi = hn::Load(d, colHi);
    const auto isSlab = hn::Le(slab, lo), isHi = hn::AndNot(isSlab, hn::Lt(hi, zero));
    f = hn::IfThenElse(isSlab, slab, hi);
    lb = slab;
    eval = hn::And(eval, hn::Or(isSlab, isHi));
  } else {
    const V faces = MinOf(hn::Add(zp, T), hn::Sub(T, zp));
    if (sheet.kind == 1) {
      const V H = hn::Set(d, sheet.h);
      f = MinOf(MinOf(MinOf(hn::Add(px, W), hn::Sub(W, px)), MinOf(hn::Add(py, H), hn::Sub(H, py))), faces);
    } else {
      f = MinOf(hn::Sub(W, hn::Sqrt(hn::Add(hn::Mul(px, px), hn::Mul(py, py)))), faces);
    }
    lb = f;
  }
  counts[1] += hn::CountTrue(d, eval);

  // Where f < 0 the walk steps; at f >= 0 (a hit) the point before is evaluated next (when the
  // walk did not come from there, nor start here: Renderer::endWalk()'s bracket).
  // (An outline sheet's lane with f < 0 but its slab >= 0 stops: the ray's own walk searches
  // that cell with the columns' bounds.)
  // In a ball's far window the step is shortened by its raise, and f is not W's: the lane steps
  // only where W < -raise (then f < 0), and never brackets (endWalk(): room = -l - raise).
  const auto plainGo = hn::And(hn::And(hn::And(eval, stepping), hn::Lt(f, zero)), hn::Lt(lb, zero));
  auto inFar = hn::FirstN(d, 0);
  V room = hn::Neg(lb);
  auto go = plainGo;
  if constexpr (kFar) {
    inFar = hn::And(hn::Ge(q, hn::Load(d, w.farLo)), hn::Le(q, hn::Load(d, w.farHi)));
    room = hn::Sub(room, hn::IfThenElseZero(inFar, hn::Load(d, w.farRaise)));
    go = hn::Or(hn::And(inFar, hn::And(hn::And(eval, stepping), hn::Gt(room, zero))), hn::AndNot(inFar, plainGo));
  }
  V n = zero;
  if (!hn::AllFalse(d, go)) {
    const V cap = hn::Set(d, 1e15), negF = room;
    // The stretch the step can reach when the ray's slope bound is at least kStepRate.
    const V reachQ =
        MinOf(hn::Load(d, w.q1), hn::Add(hn::Add(q, hn::Trunc(MinOf(hn::Mul(negF, hn::Load(d, w.invStep)), cap))), one));
    const V tr = hn::Mul(reachQ, h8);
    const V rx = hn::Add(ox, hn::Mul(tr, dx)), ry = hn::Add(oy, hn::Mul(tr, dy));
    const V bx0 = MaxOf(MinOf(px, rx), hn::Set(d, dom.x0)), by0 = MaxOf(MinOf(py, ry), hn::Set(d, dom.y0));
    const V bx1 = MinOf(MaxOf(px, rx), hn::Set(d, dom.x1)), by1 = MinOf(MaxOf(py, ry), hn::Set(d, dom.y1));
    // D's slopes over the stretch (HeightField::bound()): a box inside one leaf of the pyramid
    // reads that leaf, here; any other box the pyramid, a lane at a time.
    const hn::Rebind<int32_t, WalkTag> di;
    auto leaf = [&](V x, double origin, int samples) {
      const auto cell = hn::DemoteTo(di, hn::Mul(hn::Sub(x, hn::Set(d, origin)), hn::Set(d, l.invS)));
      return hn::ShiftRight<3>(hn::Min(hn::Max(cell, hn::Zero(di)), hn::Set(di, samples - 2)));
    };
    const auto i0 = leaf(bx0, l.x0, l.nx), i1 = leaf(bx1, l.x0, l.nx);
    const auto j0 = leaf(by0, l.y0, l.ny), j1 = leaf(by1, l.y0, l.ny);
    int leafWidth = 0;
    const float* const leaves = sheet.field->leaves(leafWidth);
    HWY_ALIGN int32_t oneLeaf[kMaxWalkLanes];  // the leaf holding the box, or -1
    hn::Store(hn::IfThenElse(hn::And(hn::Eq(i0, i1), hn::Eq(j0, j1)), hn::Add(hn::Mul(j0, hn::Set(di, leafWidth)), i0),
                             hn::Set(di, -1)),
              di, oneLeaf);
    HWY_ALIGN double box[4][kMaxWalkLanes], goes[kMaxWalkLanes];
    hn::Store(bx0, d, box[0]), hn::Store(by0, d, box[1]), hn::Store(bx1, d, box[2]), hn::Store(by1, d, box[3]);
    hn::Store(hn::IfThenElseZero(go, one), d, goes);
    HWY_ALIGN double g[4][kMaxWalkLanes];
    for (size_t k = 0; k < lanes; ++k) {
      if (goes[k] == 0.0) {
        g[0][k] = g[1][k] = g[2][k] = g[3][k] = 0.0;
      } else if (oneLeaf[k] >= 0) {
        const float* node = leaves + static_cast<size_t>(oneLeaf[k]) * 6;  // lo, hi, gxlo, gxhi, gylo, gyhi
        g[0][k] = node[2], g[1][k] = node[3], g[2][k] = node[4], g[3][k] = node[5];
      } else {
        const HeightField::Bound b = sheet.field->bound(Box2{box[0][k], box[1][k], box[2][k], box[3][k]});
        g[0][k] = b.gxlo, g[1][k] = b.gxhi, g[2][k] = b.gylo, g[3][k] = b.gyhi;
      }
    }
    // lipschitzAlong() (renderer_internal.h).
    const V gxlo = hn::Load(d, g[0]), gxhi = hn::Load(d, g[1]), gylo = hn::Load(d, g[2]), gyhi = hn::Load(d, g[3]);
    const V ax = hn::Load(d, w.ax), bx = hn::Load(d, w.bx), ay = hn::Load(d, w.ay), by = hn::Load(d, w.by);
    const V slo = hn::Add(hn::Add(hn::Add(hn::Mul(gxlo, ax), hn::Mul(gxhi, bx)), hn::Mul(gylo, ay)), hn::Mul(gyhi, by));
    const V shi = hn::Add(hn::Add(hn::Add(hn::Mul(gxhi, ax), hn::Mul(gxlo, bx)), hn::Mul(gyhi, ay)), hn::Mul(gylo, by));
    const V dzBound = MaxOf(hn::Abs(hn::Sub(dz, slo)), hn::Abs(hn::Sub(dz, shi)));
    const V lf = hn::Add(hn::Mul(MaxOf(hn::Load(d, w.side), dzBound), hn::Set(d, 1.0 + 1e-9)), hn::Set(d, 1e-12));
    // The step: as far as the stretch's bound, at least as far as the ray's, never into a window.
    const V num = hn::Sub(negF, hn::Set(d, 1e-7));  // kPruneEps
    const V n1 = MinOf(hn::Trunc(MinOf(hn::Div(num, hn::Mul(lf, h8)), cap)), hn::Sub(hn::Sub(reachQ, q), one));
    const V n2 = hn::Trunc(MinOf(hn::Mul(num, hn::Load(d, w.invRay)), cap));
    const V nextWindow =
        MaxOf(hn::Add(q, one), kFar ? hn::IfThenElse(inFar, hn::Load(d, w.after), hn::Load(d, w.window)) : hn::Load(d, w.window));
    n = MaxOf(zero, MinOf(MaxOf(n1, n2), hn::Sub(hn::Sub(nextWindow, q), one)));
  }
  // Six short steps in a row: the ray's own walk searches a cell instead.
  const V shortSteps = hn::Load(d, w.shortSteps);
  const V shortNew = hn::IfThenElse(hn::Lt(n, hn::Set(d, 2.0)), hn::Add(shortSteps, one), zero);  // kSubdivisions / 8
  const auto creep = hn::And(go, hn::Ge(shortNew, hn::Set(d, 6.0)));
  const auto step = hn::AndNot(creep, go);
  const V qNew = hn::Add(hn::Add(q, n), one);
  // The bracket's point before the hit: the walk's last point.
  const auto bracketed = hn::And(bracketing, eval);
  const V prevQ = hn::Load(d, w.prevQ);
  hn::Store(hn::IfThenElse(step, qNew, q), d, w.q);
  hn::Store(hn::IfThenElse(step, q, hn::IfThenElse(bracketed, qe, prevQ)), d, w.prevQ);
  hn::Store(hn::IfThenElse(hn::Or(step, bracketed), f, hn::Load(d, w.prevF)), d, w.prevF);
  hn::Store(hn::IfThenElse(step, shortNew, shortSteps), d, w.shortSteps);
  counts[0] += hn::CountTrue(d, step);
  if constexpr (kFar) counts[2] += hn::CountTrue(d, hn::And(step, inFar));
  // A hit (f >= 0) to bracket; stopped with f at q (a hit bracketed or not to be, f neither below
  // nor above zero, creeping), or without (off the field, or at a window, a skip or the clip's end).
  // (In a far window: no hit is bracketed, and a lane that stops there stops without f.)
  const auto found = hn::AndNot(inFar, hn::And(hn::And(eval, stepping), hn::Ge(f, zero)));
  const auto toBracket =
      hn::AndNot(hn::Or(hn::Eq(q, hn::Load(d, w.q0)), hn::Eq(prevQ, hn::Sub(q, one))), found);
  const auto stopsHere = hn::Or(hn::AndNot(go, hn::And(eval, stepping)), creep);
  const auto withF = hn::Or(hn::AndNot(inFar, stopsHere), bracketing);
  const auto without = hn::Or(hn::Or(hn::AndNot(eval, stepping), hn::And(step, hn::Ge(qNew, hn::Load(d, w.end)))),
                              hn::And(inFar, stopsHere));
  hn::Store(hn::IfThenElse(hn::And(eval, stepping), f, hn::Load(d, w.f)), d, w.f);
  hn::Store(hn::IfThenElse(hn::And(eval, stepping), lb, hn::Load(d, w.l)), d, w.l);
  hn::Store(hn::IfThenElse(toBracket, hn::Set(d, 4.0),
                           hn::IfThenElse(withF, hn::Set(d, 3.0), hn::IfThenElse(without, hn::Set(d, 2.0), state))),
            d, w.state);
}

void WalkLanesStep(const WalkSheet& sheet, WalkLanes& w, uint64_t* counts) {
  if (w.farLanes > 0) StepLanes<true>(sheet, w, counts);
  else StepLanes<false>(sheet, w, counts);
}

// The gradient's min: a.v <= b.v ? a : b (grad.h), value and slopes together.
template <class M, class V>
HWY_INLINE void MinGrad(V av, V ax, V ay, V az, V bv, V bx, V by, V bz, V& v, V& x, V& y, V& z) {
  const M a = hn::Le(av, bv);
  v = hn::IfThenElse(a, av, bv), x = hn::IfThenElse(a, ax, bx), y = hn::IfThenElse(a, ay, by), z = hn::IfThenElse(a, az, bz);
}

int SheetNormalLanes(const WalkSheet& sheet, const double* xs, const double* ys, const double* zs, const double* dv,
                     const double* dgx, const double* dgy, int n, double* nx, double* ny, double* nz) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  using M = hn::Mask<decltype(d)>;
  const int lanes = static_cast<int>(hn::Lanes(d));
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), W = hn::Set(d, sheet.w), T = hn::Set(d, sheet.d);
  int k = 0;
  for (; k + lanes <= n; k += lanes) {
    const V x = hn::LoadU(d, xs + k), y = hn::LoadU(d, ys + k), z = hn::LoadU(d, zs + k);
    // z' = z - D as Grads: (z, 0, 0, 1) - (D, dD/dx, dD/dy, 0).
    const V zv = hn::Sub(z, hn::LoadU(d, dv + k)), zx = hn::Sub(zero, hn::LoadU(d, dgx + k));
    const V zy = hn::Sub(zero, hn::LoadU(d, dgy + k)), zz = hn::Sub(one, zero);
    // The faces: min(z' + d, d - z').
    V fv, fx, fy, fz;
    MinGrad<M>(hn::Add(zv, T), hn::Add(zx, zero), hn::Add(zy, zero), hn::Add(zz, zero), hn::Sub(T, zv), hn::Sub(zero, zx),
               hn::Sub(zero, zy), hn::Sub(zero, zz), fv, fx, fy, fz);
    V gv, gx, gy, gz;
    if (sheet.kind == 4) {
      // An outline sheet where W is the slab: d - abs(z'), abs(a) = a.v < 0 ? -a : a.
      const M below = hn::Lt(zv, zero);
      const V av = hn::IfThenElse(below, hn::Neg(zv), zv), ax = hn::IfThenElse(below, hn::Neg(zx), zx);
      const V ay = hn::IfThenElse(below, hn::Neg(zy), zy), az = hn::IfThenElse(below, hn::Neg(zz), zz);
      gv = hn::Sub(T, av), gx = hn::Sub(zero, ax), gy = hn::Sub(zero, ay), gz = hn::Sub(zero, az);
    } else if (sheet.kind == 1) {
      // min(min(min(x + w, w - x), min(y + h, h - y)), faces), x = (x, 1, 0, 0), y = (y, 0, 1, 0).
      const V H = hn::Set(d, sheet.h), minus = hn::Sub(zero, one);
      V av, ax, ay, az, bv, bx, by, bz, cv, cx, cy, cz;
      MinGrad<M>(hn::Add(x, W), hn::Add(one, zero), hn::Add(zero, zero), hn::Add(zero, zero), hn::Sub(W, x), minus,
                 hn::Sub(zero, zero), hn::Sub(zero, zero), av, ax, ay, az);
      MinGrad<M>(hn::Add(y, H), hn::Add(zero, zero), hn::Add(one, zero), hn::Add(zero, zero), hn::Sub(H, y),
                 hn::Sub(zero, zero), minus, hn::Sub(zero, zero), bv, bx, by, bz);
      MinGrad<M>(av, ax, ay, az, bv, bx, by, bz, cv, cx, cy, cz);
      MinGrad<M>(cv, cx, cy, cz, fv, fx, fy, fz, gv, gx, gy, gz);
    } else {
      // min(r - sqrt(sqr(x) + sqr(y)), faces): sqr(a) = (a^2, 2a a'), sqrt(a) = (s, a' 0.5 / s).
      const V two = hn::Set(d, 2.0);
      const V sxv = hn::Mul(x, x), sxx = hn::Mul(hn::Mul(two, x), one), sxy = hn::Mul(hn::Mul(two, x), zero);
      const V syv = hn::Mul(y, y), syx = hn::Mul(hn::Mul(two, y), zero), syy = hn::Mul(hn::Mul(two, y), one);
      const V sxz = hn::Mul(hn::Mul(two, x), zero), syz = hn::Mul(hn::Mul(two, y), zero);
      const V qv = hn::Add(sxv, syv), qx = hn::Add(sxx, syx), qy = hn::Add(sxy, syy), qz = hn::Add(sxz, syz);
      const V root = hn::Sqrt(hn::Max(qv, zero));
      const V dr = hn::IfThenElse(hn::Gt(root, zero), hn::Div(hn::Set(d, 0.5), root), zero);
      const V rv = hn::Sub(W, root), rx = hn::Sub(zero, hn::Mul(dr, qx)), ry = hn::Sub(zero, hn::Mul(dr, qy));
      const V rz = hn::Sub(zero, hn::Mul(dr, qz));
      MinGrad<M>(rv, rx, ry, rz, fv, fx, fy, fz, gv, gx, gy, gz);
    }
    // The unit normal -grad f / |grad f| (glm::length, glm's division), (0, 0, 1) where it is zero.
    const V mx = hn::Neg(gx), my = hn::Neg(gy), mz = hn::Neg(gz);
    const V len = hn::Sqrt(hn::Add(hn::Add(hn::Mul(mx, mx), hn::Mul(my, my)), hn::Mul(mz, mz)));
    const M some = hn::Gt(len, zero);
    hn::StoreU(hn::IfThenElse(some, hn::Div(mx, len), zero), d, nx + k);
    hn::StoreU(hn::IfThenElse(some, hn::Div(my, len), zero), d, ny + k);
    hn::StoreU(hn::IfThenElse(some, hn::Div(mz, len), one), d, nz + k);
  }
  return k;
}

// NOLINTNEXTLINE(google-readability-namespace-comments)
}  // namespace HWY_NAMESPACE
}  // namespace emboss
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace emboss {

HWY_EXPORT(WalkLaneCount);
HWY_EXPORT(WalkLanesStep);

HWY_EXPORT(SheetNormalLanes);

int walkLaneCount() { return HWY_DYNAMIC_DISPATCH(WalkLaneCount)(); }

int sheetNormalLanes(const WalkSheet& sheet, const double* x, const double* y, const double* z, const double* dv,
                     const double* dgx, const double* dgy, int n, double* nx, double* ny, double* nz) {
  return HWY_DYNAMIC_DISPATCH(SheetNormalLanes)(sheet, x, y, z, dv, dgx, dgy, n, nx, ny, nz);
}

void walkLanes(const WalkSheet& sheet, WalkLanes& lanes, std::uint64_t& steps, std::uint64_t& evaluations,
               std::uint64_t& farSteps) {
  uint64_t counts[3] = {0, 0, 0};
  HWY_DYNAMIC_DISPATCH(WalkLanesStep)(sheet, lanes, counts);
  steps += counts[0], evaluations += counts[1], farSteps += counts[2];
}

}  // namespace emboss
#endif  // HWY_ONCE
