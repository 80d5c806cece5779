// The field tracer: the sheet model's values along its rays -- f, the displacement field with its
// pyramid bounding the steps, the bounds that skip stretches, the normals (renderer.h). The walk
// that reads them is renderer_walk.cpp's.
#include "render/renderer_internal.h"
#include "util/portable_math.h"

namespace emboss {

using namespace render_internal;

// ---------------------------------------------------------------- the field tracer

template <class T>
T Renderer::exactDisplacement(const P3<T>& p, std::span<const std::uint32_t> candidates, RenderStats& st) const {
  const auto& ops = model_->operations();
  T total(0.0);
  for (std::uint32_t i : candidates) {
    const PreparedOp& op = ops[i];
    if (!op.op().isOffset()) continue;
    total += op.offset(p, Deformation::Sheet);
    ++st.opsVisited;
  }
  return total;
}

double Renderer::displacementAt(double x, double y) const {
  if (fieldReady_ && field_.contains(x, y)) return field_.value(x, y);
  RenderStats st;
  std::vector<std::uint32_t> scratch;
  return exactDisplacement(P3<double>{x, y, 0.0}, grid_.at(x, y, scratch), st);
}

// f at p, a function of p alone: the field's D inside its domain, the exact sum outside it; the
// set operations whose support holds (x, y), each at the point moved by the offsets after it.
// For an outline sheet W is the slab d - |z'| (bit for bit) where the slab is below the column's
// bound of O and, in outside columns away from set operations, where only its sign can matter,
// an upper bound of it (< 0).
// *lipschitzValue gets the value the Lipschitz bounds work from: f itself, or the slab.
double Renderer::fieldValue(const RayContext& rc, const glm::dvec3& p, RenderStats& st,
                            std::vector<std::uint32_t>& scratch, double* lipschitzValue) const {
  ++st.evaluations;
  // The point on the field's lattice, which the shift fields share: its cell and basis found once.
  const HeightField::LatticePoint lp = field_.latticePoint(p.x, p.y);
  double d;
  if (field_.contains(p.x, p.y)) {
    d = field_.value(lp);
    ++st.fieldEvaluations;
  } else {
    d = exactDisplacement(P3<double>{p.x, p.y, p.z}, grid_.at(p.x, p.y, scratch), st);
  }
  const int n = rc.setOpCount;
  double v;
  if (workpieceKind_ == 4) {
    const double slab = columns_.halfThickness - std::abs(p.z - d);
    if (lipschitzValue) *lipschitzValue = slab;
    const ColumnMap::Column col = columns_.at(p.x, p.y);
    bool underSet = false;
    for (int k = 0; k < n && !underSet; ++k)
      underSet = rc.setOps[k]->support.contains(p.x, p.y);
    if (slab <= col.lo)
      v = slab;
    else if (col.hi < 0.0f && !underSet)
      v = col.hi;
    else
      v = workpieceValue(P3<double>{p.x, p.y, p.z - d});
  } else {
    v = model_->workpiece().value(P3<double>{p.x, p.y, p.z - d});
    if (lipschitzValue) *lipschitzValue = v;
  }
  // A run's set operations hold the same shift at p (SetOp::shift): it is read once a run.
  std::uint32_t run = ~0u;
  double shift = 0.0;
  for (int k = 0; k < n; ++k) {
    const SetOp& s = *rc.setOps[k];
    if (!s.support.contains(p.x, p.y)) continue;  // combine() is exactly the identity there
    if (s.run != run) run = s.run, shift = s.shift->value(lp);
    const double z = p.z - shift;
    if (z < s.toolZlo || z > s.toolZhi) continue;  // combine() is exactly the identity there too
    v = model_->operations()[s.index].combine(v, P3<double>{p.x, p.y, z});
    ++st.opsVisited;
  }
  return v;
}

// The function the Lipschitz bounds hold for, with D from the field: W(x, y, z - D), or for an
// outline sheet the slab d - |z - D| (which bounds W from above).
double Renderer::sheetValue(const glm::dvec3& p) const {
  const double zp = p.z - field_.value(p.x, p.y);
  if (workpieceKind_ == 4) return columns_.halfThickness - std::abs(zp);
  return model_->workpiece().value(P3<double>{p.x, p.y, zp});
}

// Whether f < 0 is proven over the segment a-b. f without the set operations is bounded from its
// value at the middle and the ray's Lipschitz constant when there is one, else by intervals over
// the segment's box (the field's pyramid for D); the set operations then by intervals.
bool Renderer::fieldExcluded(const RayContext& rc, const glm::dvec3& a, const glm::dvec3& b, RenderStats& st,
                             std::vector<std::uint32_t>& scratch) const {
  ++st.evaluations;
  const P3<Interval> box = boxOf(a, b);
  const Box2 xy{box.x.lo, box.y.lo, box.x.hi, box.y.hi};
  Interval v;
  // Outline sheets: the columns under the box decide which bound applies.
  bool columnsOk = true;
  double outsideUpper = -std::numeric_limits<double>::infinity();
  bool anyInside = false, anyOutside = false;
  float insideLo = std::numeric_limits<float>::infinity();  // the inside blocks' lowest bound of min(O, d)
  if (workpieceKind_ == 4) {
    const ColumnMap& c = columns_;
    const auto [i0, j0, i1, j1] = c.under(xy);
    if ((i1 - i0 + 1) * (j1 - j0 + 1) > 16) {
      columnsOk = false;
    } else {
      auto take = [&](const ColumnMap::Column& b) {
        if (b.hi < 0.0f)
          anyOutside = true, outsideUpper = std::max(outsideUpper, static_cast<double>(b.hi));
        else
          anyInside = true, insideLo = std::min(insideLo, b.lo);
      };
      // A block with sub-cells: those under the box (the ones Columns::at() finds for its points).
      constexpr int kSub = WalkSheet::Columns::kSub;
      const double u0 = (xy.x0 - c.x0) * c.inv, u1 = (xy.x1 - c.x0) * c.inv;
      const double v0 = (xy.y0 - c.y0) * c.inv, v1 = (xy.y1 - c.y0) * c.inv;
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
          const std::int32_t s = c.subCellsOf(i, j);
          if (s < 0) {
            take(c.block(i, j));
            continue;
          }
          const int si0 = i == i0 ? WalkSheet::Columns::subCell(u0, i) : 0, si1 = i == i1 ? WalkSheet::Columns::subCell(u1, i) : kSub - 1;
          const int sj0 = j == j0 ? WalkSheet::Columns::subCell(v0, j) : 0, sj1 = j == j1 ? WalkSheet::Columns::subCell(v1, j) : kSub - 1;
          for (int sj = sj0; sj <= sj1; ++sj)
            for (int si = si0; si <= si1; ++si) {
              const size_t k = WalkSheet::Columns::subIndex(s, si, sj);
              take(ColumnMap::Column{c.subLo[k], c.subHi[k]});
            }
        }
    }
  }
  const int nSet = rc.setOpCount;
  const auto acts = [&](const SetOp& s) { return s.support.overlaps(xy) && box.z.hi >= s.zlo && box.z.lo <= s.zhi; };
  bool setOpHere = false;  // (read for outline sheets alone)
  for (int k = 0; workpieceKind_ == 4 && k < nSet && !setOpHere; ++k) setOpHere = acts(*rc.setOps[k]);
  if (workpieceKind_ == 4 && columnsOk && !anyInside && !setOpHere) return true;  // all outside
  // Every block under the box inside: W is the slab wherever the slab is below their bounds.
  const bool slabIsW = workpieceKind_ == 4 && columnsOk && !anyOutside;
  if (workpieceKind_ == 4 && anyOutside && setOpHere) columnsOk = false;
  bool slabBound = rc.lipschitz && field_.containsBox(xy);
  if (workpieceKind_ == 4 && columnsOk && slabBound) {
    // f <= max(slab, the outside columns' bounds): enough when that is negative.
    const double fm = sheetValue(0.5 * (a + b));
    const double len = glm::length(b - a);
    const double r = 0.5 * lipschitzAlong((b - a) / len, field_.bound(xy), workpieceKind_) * len + kPruneEps;
    if (std::max(fm + r, outsideUpper) >= -kPruneEps || setOpHere) slabBound = false, columnsOk = false;
    else return ++st.fieldEvaluations, true;  // (no set operation here: the bound below would be this one)
  }
  if (slabBound && !(workpieceKind_ == 4 && !columnsOk)) {
    const double fm = sheetValue(0.5 * (a + b));
    const double len = glm::length(b - a);
    const double r = 0.5 * lipschitzAlong((b - a) / len, field_.bound(xy), workpieceKind_) * len + kPruneEps;
    v = Interval(fm - r, fm + r);
    if (anyOutside) v = Interval(std::min(v.lo, outsideUpper), std::max(v.hi, outsideUpper));
    ++st.fieldEvaluations;
  } else {
    Interval d;
    if (field_.containsBox(xy)) {
      const HeightField::Bound r = field_.bound(xy);
      d = Interval(r.lo, r.hi);
      ++st.fieldEvaluations;
    } else {
      d = exactDisplacement(box, grid_.in(xy, scratch), st);
    }
    const Interval slab = slabIsW ? Interval(columns_.halfThickness) - abs(box.z - d) : Interval();
    if (slabIsW && slab.hi <= insideLo)
      v = slab;  // O >= the blocks' bounds >= the slab's top: W = min(O, slab) is the slab
    else
      v = workpieceValue(P3<Interval>{box.x, box.y, box.z - d});
  }
  return setOpsExclude(rc.setOps, nSet, box, xy, v.hi, st);
}

bool Renderer::setOpsExclude(const SetOp* const* ops, int n, const P3<Interval>& box, const Box2& xy, double fHi,
                             RenderStats& st) const {
  const auto acts = [&](const SetOp& s) { return s.support.overlaps(xy) && box.z.hi >= s.zlo && box.z.lo <= s.zhi; };
  // Only f's upper end decides. First with the subtractions' tools anywhere (no shapes, no
  // shifts: a subtraction raises f by its bump at most), which proves most cells well clear of a
  // pile of them; then with every tool where it is.
  // A run's shift over the same box (both supports hold it): bounded once (SetOp::shift).
  std::uint32_t run = ~0u;
  Box2 shiftIn;
  Interval shift;
  const auto withTool = [&](const SetOp& s, double hi) {
    const Box2 in = xy.intersected(s.support);
    if (s.run != run || in != shiftIn) {
      const HeightField::Bound sb = s.shift->bound(in);
      run = s.run, shiftIn = in, shift = Interval(sb.lo, sb.hi);
    }
    ++st.opsVisited;
    return s.upper.over(hi, P3<Interval>{box.x, box.y, box.z - shift});
  };
  bool anywhere = false;  // a subtraction's tool was taken as anywhere
  double hi = fHi;
  int k = 0;
  for (; k < n && hi < -kPruneEps; ++k) {
    const SetOp& s = *ops[k];
    if (!acts(s)) continue;
    if (s.upper.kind == OpKind::BlendUnion) {
      hi = withTool(s, hi);
    } else {
      hi = s.upper.anywhere(hi), anywhere = true;
      ++st.opsVisited;
    }
  }
  // (Every bound there is at least the f it is given: past zero the first pass stays past it.)
  if (hi < -kPruneEps) return true;
  if (!anywhere && k == n) return false;  // the second pass would be the first
  hi = fHi;
  for (k = 0; k < n && hi < -kPruneEps; ++k)  // (no bound lowers f: past zero is the end)
    if (const SetOp& s = *ops[k]; acts(s)) hi = withTool(s, hi);
  return hi < -kPruneEps;
}

glm::dvec3 Renderer::fieldNormal(const glm::dvec3& p, RenderStats& st, std::vector<std::uint32_t>& scratch,
                                  const Grad* fieldD) const {
  ++st.evaluations;
  const P3<Grad> q{Grad(p.x, 1, 0, 0), Grad(p.y, 0, 1, 0), Grad(p.z, 0, 0, 1)};
  Grad d;
  if (field_.contains(p.x, p.y)) {
    if (fieldD) {
      d = *fieldD;
    } else {
      double v, gx, gy;
      field_.valueAndGradient(p.x, p.y, v, gx, gy);
      d = Grad(v, gx, gy, 0.0);
    }
    ++st.fieldEvaluations;
  } else {
    d = exactDisplacement(q, grid_.at(p.x, p.y, scratch), st);
  }
  Grad f;
  if (workpieceKind_ == 4 && columns_.halfThickness - std::abs(p.z - d.v) <= columns_.at(p.x, p.y).lo)
    f = Grad(columns_.halfThickness) - abs(q.z - d);  // W there
  else
    f = workpieceValue(P3<Grad>{q.x, q.y, q.z - d});
  std::uint32_t run = ~0u;  // read once a run, as in fieldValue()
  Grad shift;
  setOpSupports_.holding(p.x, p.y, [&](std::uint32_t k) {
    const SetOp& s = setOps_[k];
    if (s.run != run) {
      double sv, sx, sy;
      run = s.run;
      s.shift->valueAndGradient(p.x, p.y, sv, sx, sy);
      shift = Grad(sv, sx, sy, 0.0);
    }
    const Grad z = q.z - shift;
    if (z.v < s.toolZlo || z.v > s.toolZhi) return;  // (as in fieldValue())
    f = model_->operations()[s.index].combine(f, P3<Grad>{q.x, q.y, z});
    ++st.opsVisited;
  });
  glm::dvec3 n(-f.dx, -f.dy, -f.dz);
  const double len = glm::length(n);
  return len > 0 ? n / len : glm::dvec3(0, 0, 1);
}

template double Renderer::exactDisplacement(const P3<double>&, std::span<const std::uint32_t>, RenderStats&) const;

}  // namespace emboss
