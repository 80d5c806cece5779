// The ray tracers: the field tracer (sheet model) and the exact tracer (offset model, --naive).
#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <mutex>
#include <limits>
#include <numeric>
#include <type_traits>

#include "frep/kernels.h"
#include "frep/vm_model.h"
#include "frep/workpieces.h"
#include "render/set_op_bounds.h"
#include "render/srgb8.h"

namespace emboss {

namespace {

// Exact tracer.
constexpr int kSpanSteps = 8;
constexpr int kBisections = 40;
constexpr int kThinSplits = 3;

// Field tracer.
constexpr double kFieldSpacing = 0.125;    // mm between displacement samples
constexpr double kMaxFieldSamples = 32e6;  // beyond this the spacing grows (a huge workpiece)
constexpr double kFieldMargin = 2.0;       // mm of field beyond the workpiece's bounds
constexpr int kSubdivisions = 64;          // a cell is searched down to h / 64 (as the exact tracer)
constexpr int kRefinements = 1;            // regula falsi (Illinois) steps inside the final h / 64
constexpr double kPruneEps = 1e-7;         // mm: a bound must clear zero by this much to skip
constexpr int kRecomputeTile = 64;         // samples per side of a field tile recomputed in parallel

P3<Interval> boxOf(const glm::dvec3& a, const glm::dvec3& b) {
  return {Interval(std::min(a.x, b.x), std::max(a.x, b.x)), Interval(std::min(a.y, b.y), std::max(a.y, b.y)),
          Interval(std::min(a.z, b.z), std::max(a.z, b.z))};
}

// The parameter range [t0, t1] (t0 >= 0) where the ray is inside the box (slabs, one division a
// component).
bool clipRay(const Ray& ray, const Box3& b, double& t0, double& t1) {
  t0 = 0.0, t1 = 1e30;
  const double lo[3] = {b.x0, b.y0, b.z0}, hi[3] = {b.x1, b.y1, b.z1};
  for (int k = 0; k < 3; ++k) {
    const double o = ray.origin[k], d = ray.dir[k];
    if (std::abs(d) < 1e-15) {
      if (o < lo[k] || o > hi[k]) return false;
      continue;
    }
    const double inv = 1.0 / d;
    double ta = (lo[k] - o) * inv, tb = (hi[k] - o) * inv;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta), t1 = std::min(t1, tb);
    if (!(t0 < t1)) return false;
  }
  return t0 < t1;
}

double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// A Lipschitz constant along the unit direction d of f = W(x, y, z - D(x, y)), where D's slopes
// are bounded by b and W is one of the built-in workpieces: each is the min of terms whose rates
// along d are bounded by |dx|, |dy| (the plate's sides), |(dx, dy)| (a round rim), |dz'| (the
// faces; z' = z - D, dz'/dt = dz - grad D . (dx, dy)) or |(dx, dy, dz')| (the bowl's shell), and a
// min changes no faster than its fastest term. Kind 4 (outline sheets) bounds the slab d - |z'|.
double lipschitzAlong(const glm::dvec3& d, const HeightField::Bound& b, int workpieceKind) {
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

Box2 xyBox(const glm::dvec3& a, const glm::dvec3& b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::max(a.x, b.x), std::max(a.y, b.y)};
}

Box3 unite(const Box3& a, const Box3& b) {
  return {std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::min(a.z0, b.z0),
          std::max(a.x1, b.x1), std::max(a.y1, b.y1), std::max(a.z1, b.z1)};
}

}  // namespace

// Per ray: the set operations its cells can meet, the windows of the ray where they can act,
// and the Lipschitz constant of f outside those windows when there is one.
struct Renderer::RayContext {
  static constexpr int kMaxSetOps = 32;
  const SetOp* setOps[kMaxSetOps];
  int setOpCount = 0;
  bool allSetOps = false;  // more than kMaxSetOps: test every one
  // Lipschitz: W is 1-Lipschitz and D comes from the field along the whole ray, so outside the
  // windows |df/dt| <= lf; inside them (and everywhere without it) intervals bound f.
  bool lipschitz = false;
  double lf = 0.0;
  static constexpr int kMaxWindows = 8;
  long winLo[kMaxWindows], winHi[kMaxWindows];  // ascending, disjoint, in grid units
  int windows = 0;
  bool inWindow(long qa, long qb) const {
    for (int i = 0; i < windows; ++i)
      if (winLo[i] <= qb && qa <= winHi[i]) return true;
    return false;
  }
  // Stretches proven outside (outline sheets: the ray over columns where W < 0).
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
  // Adds a window [lo, hi], merging overlaps; too many windows become one up to `last`.
  void addWindow(long lo, long hi, long last) {
    int i = 0;
    while (i < windows && winHi[i] < lo) ++i;
    int j = i;
    while (j < windows && winLo[j] <= hi) lo = std::min(lo, winLo[j]), hi = std::max(hi, winHi[j]), ++j;
    if (windows - (j - i) + 1 > kMaxWindows) {
      lo = std::min(lo, winLo[0]);
      winLo[0] = lo, winHi[0] = last, windows = 1;
      return;
    }
    const int tail = windows - j;
    std::move(winLo + j, winLo + j + tail, winLo + i + 1);
    std::move(winHi + j, winHi + j + tail, winHi + i + 1);
    winLo[i] = lo, winHi[i] = hi;
    windows = i + 1 + tail;
  }
  // The first grid point >= q inside a window (or `none`).
  long nextWindow(long q, long none) const {
    for (int i = 0; i < windows; ++i)
      if (winHi[i] >= q) return std::max(q, winLo[i]);
    return none;
  }
};

// ---------------------------------------------------------------- sync

void Renderer::sync(const Model& model) {
  // Another model is followed from scratch (its operation ids are its own).
  if (model_ != &model) fieldReady_ = false;
  model_ = &model;
  grid_.sync(model);
  bounds_ = model.bounds();
  // The step: a quarter of the sheet's thickness, at most 0.25 mm: a sheet can never slip between
  // two samples, and the thin-feature splits go down to h / 64. Depends on the workpiece only.
  step_ = std::min(0.25, 0.5 * model.workpiece().halfThickness());
  all_.resize(model.activeCount());
  std::iota(all_.begin(), all_.end(), 0u);
  lastSync_ = {};
  fieldChanges_.clear();
  if (model.deformation() == Deformation::Sheet) {
    syncField(model);
  } else {
    field_.clear();
    fieldReady_ = false;
    fieldWorkpiece_ = nullptr;
    fieldIds_.clear();
    fieldSupports_.clear();
  }
  syncSetOps(model);
}

void Renderer::rebuildField(const Model& model) {
  const Box3 wb = model.workpiece().bounds();
  const Box2 domain = wb.xy().grown(kFieldMargin);
  const double area = (domain.x1 - domain.x0) * (domain.y1 - domain.y0);
  const double spacing = std::max(kFieldSpacing, std::sqrt(area / kMaxFieldSamples));
  field_.configure(domain, spacing);
  fieldWorkpiece_ = model.workpiecePtr();
  const Workpiece* w = fieldWorkpiece_.get();
  workpieceKind_ = dynamic_cast<const Plate*>(w) ? 1 : dynamic_cast<const Disc*>(w) ? 2 : dynamic_cast<const Bowl*>(w) ? 3 : 0;
  const auto* vm = dynamic_cast<const VmWorkpiece*>(w);
  if (vm && vm->isPlate()) workpieceKind_ = 4;
  if (workpieceKind_ == 4) buildColumns();
  bool anyOffset = false;
  for (size_t i = 0; i < model.activeCount() && !anyOffset; ++i) anyOffset = model.operations()[i].op().isOffset();
  if (anyOffset) {
    recomputeField(model, field_.all());
    field_.finish(field_.all(), &pool_);
  } else {
    field_.finishFlat();  // a bare sheet (a new attract piece, a new visitor): nothing to visit
  }
  fieldReady_ = true;
  lastSync_.rebuilt = true;
  lastSync_.samplesUpdated += field_.all().count();
  const size_t active = model.activeCount();
  fieldIds_.assign(model.operationIds().begin(), model.operationIds().begin() + static_cast<std::ptrdiff_t>(active));
  fieldSupports_.clear();
  for (size_t i = 0; i < active; ++i) fieldSupports_.push_back(model.operations()[i].support());
}

Renderer::ColumnMap::Column Renderer::ColumnMap::block(int i, int j) const {
  // Beyond the workpiece's bounds W < 0.
  if (i < 0 || j < 0 || i >= nx || j >= ny) return {-std::numeric_limits<float>::infinity(), -1.0f};
  const size_t k = static_cast<size_t>(j) * nx + i;
  return {lo[k], hi[k]};
}

Renderer::ColumnMap::Column Renderer::ColumnMap::at(double x, double y) const {
  return block(static_cast<int>(std::floor((x - x0) * inv)), static_cast<int>(std::floor((y - y0) * inv)));
}

// The documented form of a 2D vm workpiece is W = min(O(x, y), d - |z|), so W over a column box
// at z = 0 bounds min(O, d): proven outside where its high end is negative, the slab where the
// slab is below its low end.
void Renderer::buildColumns() {
  const Workpiece& w = *fieldWorkpiece_;
  ColumnMap& c = columns_;
  const Box2 dom = field_.domain();
  c.size = 2.0 * field_.spacing();
  c.inv = 1.0 / c.size;
  c.x0 = dom.x0, c.y0 = dom.y0;
  c.nx = static_cast<int>(std::ceil((dom.x1 - dom.x0) * c.inv));
  c.ny = static_cast<int>(std::ceil((dom.y1 - dom.y0) * c.inv));
  c.halfThickness = w.halfThickness();
  c.lo.assign(static_cast<size_t>(c.nx) * c.ny, 0.0f);
  c.hi.assign(c.lo.size(), 0.0f);
  const double d = c.halfThickness;
  constexpr float inf = std::numeric_limits<float>::infinity();
  auto bounds = [&](int i0, int j0, int i1, int j1) {
    const Interval v = w.value(P3<Interval>{Interval(c.x0 + i0 * c.size, c.x0 + i1 * c.size),
                                            Interval(c.y0 + j0 * c.size, c.y0 + j1 * c.size), Interval(0.0)});
    const double m = 1e-9 * (1.0 + std::abs(v.lo) + std::abs(v.hi));
    float lo = std::nextafter(static_cast<float>(v.lo - m), -inf);
    float hi = std::nextafter(static_cast<float>(v.hi + m), inf);
    if (hi < 0.0f) lo = -inf;                          // outside: the slab never applies
    if (v.lo >= d + m) lo = static_cast<float>(2 * d);  // inside: the slab always applies
    return ColumnMap::Column{lo, hi};
  };
  // 2 mm leaves, then the undecided ones block by block (finer blocks cost more at load than
  // they save in frames: measured in docs/performance.md).
  auto decided = [&](const ColumnMap::Column& b) { return b.hi < 0.0f || b.lo >= static_cast<float>(d); };
  auto fill = [&](int i0, int j0, int i1, int j1, const ColumnMap::Column& b) {
    for (int j = j0; j < j1; ++j)
      for (int i = i0; i < i1; ++i) {
        const size_t k = static_cast<size_t>(j) * c.nx + i;
        c.lo[k] = b.lo, c.hi[k] = b.hi;
      }
  };
  auto refine = [&](auto& self, int i0, int j0, int i1, int j1, int size) -> void {
    const ColumnMap::Column b = bounds(i0, j0, i1, j1);
    if (size == 1 || decided(b)) {
      fill(i0, j0, i1, j1, b);
      return;
    }
    const int sub = 1;
    for (int j = j0; j < j1; j += sub)
      for (int i = i0; i < i1; i += sub) self(self, i, j, std::min(i + sub, i1), std::min(j + sub, j1), sub);
  };
  constexpr int kLeaf = 8;
  const Rect leaves{0, 0, (c.nx + kLeaf - 1) / kLeaf, (c.ny + kLeaf - 1) / kLeaf};
  pool_.parallelFor2D(leaves, 4, [&](const Rect& t) {
    for (int lb = t.y; lb < t.y + t.h; ++lb)
      for (int la = t.x; la < t.x + t.w; ++la) {
        const int i0 = la * kLeaf, j0 = lb * kLeaf;
        refine(refine, i0, j0, std::min(i0 + kLeaf, c.nx), std::min(j0 + kLeaf, c.ny), kLeaf);
      }
  });
}

void Renderer::recomputeField(const Model& model, const HeightField::SampleRect& rIn) {
  const HeightField::SampleRect r = field_.clamp(rIn);
  if (r.empty()) return;
  const auto& ops = model.operations();
  auto work = [&](const Rect& t) {
    const HeightField::SampleRect tr{t.x, t.y, t.x + t.w - 1, t.y + t.h - 1};
    thread_local std::vector<std::uint32_t> scratch;
    thread_local std::vector<const PreparedOp*> list;
    const Box2 box{field_.sampleX(tr.i0), field_.sampleY(tr.j0), field_.sampleX(tr.i1), field_.sampleY(tr.j1)};
    list.clear();
    for (std::uint32_t i : grid_.in(box, scratch))
      if (ops[i].op().isOffset()) list.push_back(&ops[i]);
    field_.recompute(tr, list);
  };
  const Rect whole{r.i0, r.j0, r.i1 - r.i0 + 1, r.j1 - r.j0 + 1};
  if (whole.w <= kRecomputeTile && whole.h <= kRecomputeTile)
    work(whole);
  else
    pool_.parallelFor2D(whole, kRecomputeTile, work);
}

void Renderer::syncField(const Model& model) {
  if (!fieldReady_ || fieldWorkpiece_.get() != &model.workpiece()) {
    rebuildField(model);
    return;
  }
  const auto& ops = model.operations();
  const auto& ids = model.operationIds();
  const size_t active = model.activeCount();
  size_t p = 0;
  while (p < fieldIds_.size() && p < active && fieldIds_[p] == ids[p]) ++p;
  if (p == fieldIds_.size()) {
    // Appends only (a new stroke, a redo): each adds its kernel to the samples under its support,
    // continuing every sample's sum in index order.
    for (size_t i = p; i < active; ++i) {
      const PreparedOp& op = ops[i];
      if (op.op().isOffset()) {
        const HeightField::SampleRect r = field_.samplesIn(op.support());
        field_.add(op, &pool_);
        field_.finish(r, &pool_);
        lastSync_.samplesUpdated += r.count();
        fieldChanges_.push_back({true, static_cast<std::uint32_t>(i), op.support()});
      }
      fieldIds_.push_back(ids[i]);
      fieldSupports_.push_back(op.support());
    }
    return;
  }
  // Operations removed (undo) or replaced: the samples under them are summed again from 0.0 over
  // the active offsets, in index order, as a full build does.
  std::vector<HeightField::SampleRect> regions;
  long total = 0;
  auto note = [&](const Box2& support) {
    fieldChanges_.push_back({false, 0, support});
    const HeightField::SampleRect r = field_.samplesIn(support);
    if (r.empty()) return;
    regions.push_back(r);
    total += r.count();
  };
  for (size_t i = p; i < fieldIds_.size(); ++i) note(fieldSupports_[i]);
  for (size_t i = p; i < active; ++i)
    if (ops[i].op().isOffset()) note(ops[i].support());
  if (total > field_.all().count() / 4) {
    rebuildField(model);
    return;
  }
  for (const auto& r : regions) {
    recomputeField(model, r);
    field_.finish(r, &pool_);
    lastSync_.samplesUpdated += r.count();
  }
  fieldIds_.assign(ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(active));
  fieldSupports_.resize(p);
  for (size_t i = p; i < active; ++i) fieldSupports_.push_back(ops[i].support());
}

double Renderer::peakOf(const Operation& o) const {
  switch (o.kind) {
    case OpKind::Trace: return o.a;
    case OpKind::Punch: return std::abs(o.p) * o.a;
    case OpKind::Press: return std::abs(o.p) * o.a * 17.0;
    case OpKind::Region: return std::abs(o.height);
    default: return 0.0;
  }
}

void Renderer::syncSetOps(const Model& model) {
  std::vector<SetOp> old;
  old.swap(setOps_);
  size_t reuse = 0;
  const auto& ops = model.operations();
  const auto& ids = model.operationIds();
  const size_t active = model.activeCount();
  std::vector<std::uint32_t> scratch;
  std::vector<const PreparedOp*> list;
  // The offsets after set operation i that may reach `box`, ascending.
  auto offsetsAfter = [&](size_t i, const Box2& box) {
    list.clear();
    for (std::uint32_t j : grid_.in(box, scratch))
      if (j > i && ops[j].op().isOffset()) list.push_back(&ops[j]);
    return std::span<const PreparedOp* const>(list);
  };
  for (size_t i = 0; i < active; ++i) {
    const PreparedOp& op = ops[i];
    if (op.op().isOffset()) continue;
    SetOp s;
    s.index = static_cast<std::uint32_t>(i);
    s.id = ids[i];
    s.support = op.support();
    while (reuse < old.size() && old[reuse].id != s.id) ++reuse;
    if (fieldReady_ && reuse < old.size() && old[reuse].shift && !lastSync_.rebuilt) {
      // Follow the field's changes: appended offsets add, recomputed regions are summed again.
      s.shift = std::move(old[reuse].shift);
      HeightField& f = *s.shift;
      for (const FieldChange& c : fieldChanges_) {
        if (!c.region.overlaps(s.support)) continue;
        const HeightField::SampleRect r = f.samplesIn(c.region);
        if (r.empty()) continue;
        if (c.append) {
          if (c.index <= i) continue;
          f.add(ops[c.index]);
        } else {
          f.recompute(r, offsetsAfter(i, c.region));
        }
        f.finish(r);
      }
    } else if (fieldReady_) {
      s.shift = std::make_shared<HeightField>();
      s.shift->configure(s.support, field_.spacing());
      s.shift->recompute(s.shift->all(), offsetsAfter(i, s.support));
      s.shift->finish(s.shift->all());
    }
    const HeightField::Bound shift = s.shift ? s.shift->rootBound() : HeightField::Bound{};
    const Box3 tb = op.op().tool.bounds();
    const double reach = kernels::kSupportSpan * op.op().tool.size();
    s.zlo = tb.z0 - reach + shift.lo;
    s.zhi = tb.z1 + reach + shift.hi;
    setOps_.push_back(std::move(s));
  }
  if (!fieldReady_) return;
  // Every surface of the field tracer's function: the workpiece moved by the field's range, and
  // the set operations' boxes.
  const Box3 wb = model.workpiece().bounds();
  const HeightField::Bound r = field_.rootBound();
  Box3 clip{wb.x0, wb.y0, wb.z0 + r.lo, wb.x1, wb.y1, wb.z1 + r.hi};
  for (const SetOp& s : setOps_) clip = unite(clip, Box3{s.support.x0, s.support.y0, s.zlo, s.support.x1, s.support.y1, s.zhi});
  const double m = 1e-6 * (1.0 + std::max({std::abs(clip.x0), std::abs(clip.x1), std::abs(clip.y0), std::abs(clip.y1)}));
  fieldClip_ = {clip.x0 - m, clip.y0 - m, clip.z0 - m, clip.x1 + m, clip.y1 + m, clip.z1 + m};
}

void Renderer::setCamera(const Camera& camera) {
  const bool sameSize = camera_ && camera_->width() == camera.width() && camera_->height() == camera.height();
  camera_ = camera;
  if (sameSize && !backdrop_.empty()) return;
  // The backdrop depends on the pixel and the picture's size alone: computed once per camera.
  const int w = camera.width(), h = camera.height();
  backdrop_.assign(static_cast<size_t>(w) * h * 3, 0);
  pool_.parallelFor2D(Rect{0, 0, w, h}, 64, [&](const Rect& t) {
    for (int y = t.y; y < t.y + t.h; ++y)
      for (int x = t.x; x < t.x + t.w; ++x) {
        const auto rgb = toSrgb8Fast(backdrop(x, y, w, h));
        std::copy(rgb.begin(), rgb.end(), &backdrop_[(static_cast<size_t>(y) * w + x) * 3]);
      }
  });
}

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
  double d;
  if (field_.contains(p.x, p.y)) {
    d = field_.value(p.x, p.y);
    ++st.fieldEvaluations;
  } else {
    d = exactDisplacement(P3<double>{p.x, p.y, p.z}, grid_.at(p.x, p.y, scratch), st);
  }
  const int n = rc.allSetOps ? static_cast<int>(setOps_.size()) : rc.setOpCount;
  double v;
  if (workpieceKind_ == 4) {
    const double slab = columns_.halfThickness - std::abs(p.z - d);
    if (lipschitzValue) *lipschitzValue = slab;
    const ColumnMap::Column col = columns_.at(p.x, p.y);
    bool underSet = false;
    for (int k = 0; k < n && !underSet; ++k)
      underSet = (rc.allSetOps ? setOps_[static_cast<size_t>(k)] : *rc.setOps[k]).support.contains(p.x, p.y);
    if (slab <= col.lo)
      v = slab;
    else if (col.hi < 0.0f && !underSet)
      v = col.hi;
    else
      v = model_->workpiece().value(P3<double>{p.x, p.y, p.z - d});
  } else {
    v = model_->workpiece().value(P3<double>{p.x, p.y, p.z - d});
    if (lipschitzValue) *lipschitzValue = v;
  }
  for (int k = 0; k < n; ++k) {
    const SetOp& s = rc.allSetOps ? setOps_[static_cast<size_t>(k)] : *rc.setOps[k];
    if (!s.support.contains(p.x, p.y)) continue;  // combine() is exactly the identity there
    const double shift = s.shift->value(p.x, p.y);
    v = model_->operations()[s.index].combine(v, P3<double>{p.x, p.y, p.z - shift});
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
  if (workpieceKind_ == 4) {
    const ColumnMap& c = columns_;
    const int i0 = static_cast<int>(std::floor((xy.x0 - c.x0) * c.inv)), i1 = static_cast<int>(std::floor((xy.x1 - c.x0) * c.inv));
    const int j0 = static_cast<int>(std::floor((xy.y0 - c.y0) * c.inv)), j1 = static_cast<int>(std::floor((xy.y1 - c.y0) * c.inv));
    if ((i1 - i0 + 1) * (j1 - j0 + 1) > 16) {
      columnsOk = false;
    } else {
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
          const ColumnMap::Column b = c.block(i, j);
          if (b.hi < 0.0f)
            anyOutside = true, outsideUpper = std::max(outsideUpper, static_cast<double>(b.hi));
          else
            anyInside = true;
        }
    }
  }
  const int nSet = rc.allSetOps ? static_cast<int>(setOps_.size()) : rc.setOpCount;
  bool setOpHere = false;
  for (int k = 0; k < nSet && !setOpHere; ++k) {
    const SetOp& s = rc.allSetOps ? setOps_[static_cast<size_t>(k)] : *rc.setOps[k];
    setOpHere = s.support.overlaps(xy) && box.z.hi >= s.zlo && box.z.lo <= s.zhi;
  }
  if (workpieceKind_ == 4 && columnsOk && !anyInside && !setOpHere) return true;  // all outside
  if (workpieceKind_ == 4 && anyOutside && setOpHere) columnsOk = false;
  bool slabBound = rc.lipschitz && field_.containsBox(xy);
  if (workpieceKind_ == 4 && columnsOk && slabBound) {
    // f <= max(slab, the outside columns' bounds): enough when that is negative.
    const double fm = sheetValue(0.5 * (a + b));
    const double len = glm::length(b - a);
    const double r = 0.5 * lipschitzAlong((b - a) / len, field_.bound(xy), workpieceKind_) * len + kPruneEps;
    if (std::max(fm + r, outsideUpper) >= -kPruneEps || setOpHere) slabBound = false, columnsOk = false;
  }
  if (workpieceKind_ == 4 && !columnsOk) {
    Interval d;
    if (field_.containsBox(xy)) {
      const HeightField::Bound r = field_.bound(xy);
      d = Interval(r.lo, r.hi);
      ++st.fieldEvaluations;
    } else {
      d = exactDisplacement(box, grid_.in(xy, scratch), st);
    }
    v = model_->workpiece().value(P3<Interval>{box.x, box.y, box.z - d});
  } else if (slabBound) {
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
    v = model_->workpiece().value(P3<Interval>{box.x, box.y, box.z - d});
  }
  for (int k = 0; k < nSet; ++k) {
    const SetOp& s = rc.allSetOps ? setOps_[static_cast<size_t>(k)] : *rc.setOps[k];
    if (!s.support.overlaps(xy) || box.z.hi < s.zlo || box.z.lo > s.zhi) continue;
    const Box2 in{std::max(xy.x0, s.support.x0), std::max(xy.y0, s.support.y0), std::min(xy.x1, s.support.x1),
                  std::min(xy.y1, s.support.y1)};
    const HeightField::Bound sb = s.shift->bound(in);
    const Interval shift(sb.lo, sb.hi);
    v = combineBound(model_->operations()[s.index], v, P3<Interval>{box.x, box.y, box.z - shift});
    ++st.opsVisited;
  }
  return v.hi < -kPruneEps;
}

glm::dvec3 Renderer::fieldNormal(const glm::dvec3& p, RenderStats& st, std::vector<std::uint32_t>& scratch) const {
  ++st.evaluations;
  const P3<Grad> q{Grad(p.x, 1, 0, 0), Grad(p.y, 0, 1, 0), Grad(p.z, 0, 0, 1)};
  Grad d;
  if (field_.contains(p.x, p.y)) {
    double v, gx, gy;
    field_.valueAndGradient(p.x, p.y, v, gx, gy);
    d = Grad(v, gx, gy, 0.0);
    ++st.fieldEvaluations;
  } else {
    d = exactDisplacement(q, grid_.at(p.x, p.y, scratch), st);
  }
  Grad f;
  if (workpieceKind_ == 4 && columns_.halfThickness - std::abs(p.z - d.v) <= columns_.at(p.x, p.y).lo)
    f = Grad(columns_.halfThickness) - abs(q.z - d);  // W there
  else
    f = model_->workpiece().value(P3<Grad>{q.x, q.y, q.z - d});
  for (const SetOp& s : setOps_) {
    if (!s.support.contains(p.x, p.y)) continue;
    double sv, sx, sy;
    s.shift->valueAndGradient(p.x, p.y, sv, sx, sy);
    const Grad shift(sv, sx, sy, 0.0);
    f = model_->operations()[s.index].combine(f, P3<Grad>{q.x, q.y, q.z - shift});
    ++st.opsVisited;
  }
  glm::dvec3 n(-f.dx, -f.dy, -f.dz);
  const double len = glm::length(n);
  return len > 0 ? n / len : glm::dvec3(0, 0, 1);
}

std::optional<Renderer::Hit> Renderer::traceField(int px, int py, RenderStats& st,
                                                  std::vector<std::uint32_t>& scratch) const {
  const Ray ray = camera_->ray(px, py);
  ++st.rays;
  double t0, t1;
  if (!clipRay(ray, fieldClip_, t0, t1)) return std::nullopt;
  const double h = step_, h8 = h / kSubdivisions;
  // Points of the ray are t = q h / 64 for integers q: the same points whatever the clip.
  const long q0 = kSubdivisions * static_cast<long>(std::floor(t0 / h));
  const long q1 = kSubdivisions * static_cast<long>(std::ceil(t1 / h));
  auto at = [&](long q) { return ray.origin + (static_cast<double>(q) * h8) * ray.dir; };

  RayContext rc;
  const glm::dvec3 pa = at(q0), pb = at(q1);
  const Box2 reach{std::min(pa.x, pb.x), std::min(pa.y, pb.y), std::max(pa.x, pb.x), std::max(pa.y, pb.y)};
  for (const SetOp& s : setOps_) {
    if (!s.support.overlaps(reach)) continue;
    if (rc.setOpCount == RayContext::kMaxSetOps) {
      rc.allSetOps = true;
      break;
    }
    rc.setOps[rc.setOpCount++] = &s;
  }
  const Box2 dom = field_.domain();
  double tda = 0, tdb = 0;
  const bool reachInDomain = field_.containsBox(reach);
  if (reachInDomain) tda = static_cast<double>(q0) * h8 - 1.0, tdb = static_cast<double>(q1) * h8 + 1.0;
  if (workpieceKind_ != 0 && (reachInDomain || clipRay(ray, Box3{dom.x0, dom.y0, -1e30, dom.x1, dom.y1, 1e30}, tda, tdb))) {
    // W(x, y, z - D) with a known Lipschitz bound for W (see lipschitzAlong()), D's slopes from
    // the field. Beyond the field's domain (the workpiece's bounds and a margin) W < 0: skipped.
    rc.lipschitz = true;
    const Box2 r{std::max(reach.x0, dom.x0), std::max(reach.y0, dom.y0), std::min(reach.x1, dom.x1), std::min(reach.y1, dom.y1)};
    rc.lf = lipschitzAlong(ray.dir, field_.bound(r), workpieceKind_);
    const long qa = static_cast<long>(std::ceil(tda / h8)) - 2, qb = static_cast<long>(std::floor(tdb / h8)) + 2;
    if (qa >= q0) rc.skipLo[rc.skips] = q0, rc.skipHi[rc.skips] = qa, ++rc.skips;
    if (qb <= q1) rc.skipLo[rc.skips] = qb, rc.skipHi[rc.skips] = q1, ++rc.skips;
    // The windows where a set operation can act: the ray inside its box.
    if (rc.allSetOps) {
      rc.winLo[0] = q0, rc.winHi[0] = q1, rc.windows = 1;
    } else {
      for (int k = 0; k < rc.setOpCount; ++k) {
        const SetOp& s = *rc.setOps[k];
        double ta, tb;
        if (!clipRay(ray, Box3{s.support.x0, s.support.y0, s.zlo, s.support.x1, s.support.y1, s.zhi}, ta, tb)) continue;
        rc.addWindow(static_cast<long>(std::floor(ta / h8)) - 1, static_cast<long>(std::ceil(tb / h8)) + 1, q1);
      }
    }
    if (workpieceKind_ == 4) {
      // Outline sheets: follow the ray over the column blocks (a 2D DDA); stretches over outside
      // columns are skipped.
      const ColumnMap& c = columns_;
      const double tStart = static_cast<double>(q0) * h8, tEnd = static_cast<double>(q1) * h8;
      const glm::dvec3 p0 = ray.origin + tStart * ray.dir;
      int i = static_cast<int>(std::floor((p0.x - c.x0) * c.inv)), j = static_cast<int>(std::floor((p0.y - c.y0) * c.inv));
      const int si = ray.dir.x > 0 ? 1 : -1, sj = ray.dir.y > 0 ? 1 : -1;
      const double inf = std::numeric_limits<double>::infinity();
      auto crossing = [&](int k, int sk, double o, double d, double base) {
        if (std::abs(d) < 1e-15) return inf;
        return (base + (k + (sk > 0 ? 1 : 0)) * c.size - o) / d;
      };
      double tx = crossing(i, si, ray.origin.x, ray.dir.x, c.x0), ty = crossing(j, sj, ray.origin.y, ray.dir.y, c.y0);
      const double dtx = std::abs(ray.dir.x) < 1e-15 ? inf : c.size / std::abs(ray.dir.x);
      const double dty = std::abs(ray.dir.y) < 1e-15 ? inf : c.size / std::abs(ray.dir.y);
      double t = tStart, runStart = tStart;
      int runClass = -1;
      auto endRun = [&](double tb) {
        // Boundary columns need no window: W <= the slab there, whose Lipschitz bound holds.
        if (runClass == 0 && rc.skips < RayContext::kMaxWindows) {
          const long lo = static_cast<long>(std::ceil(runStart / h8)) + 1, hi = static_cast<long>(std::floor(tb / h8)) - 1;
          if (lo <= hi) rc.skipLo[rc.skips] = lo, rc.skipHi[rc.skips] = hi, ++rc.skips;
        }
      };
      for (int guard = 0; t < tEnd; ++guard) {
        const int k = c.block(i, j).hi < 0.0f ? 0 : 1;  // 0: outside
        if (k != runClass) {
          endRun(t);
          runClass = k, runStart = t;
        }
        if (guard > 4096) break;  // a very long path: the rest is not skipped
        if (tx < ty)
          t = tx, tx += dtx, i += si;
        else
          t = ty, ty += dty, j += sj;
      }
      endRun(std::min(t, tEnd));
    }
  } else {
    rc.winLo[0] = q0, rc.winHi[0] = q1, rc.windows = 1;
  }

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
  // The first q in (qa, qb] with f(q) >= 0, given f(qa) < 0: sets the bracket [q - 1, q].
  long bq = 0;
  double bfa = 0, bfb = 0;
  auto search = [&](auto& self, long qa, const Val& a, long qb, const Val& b, bool checked) -> bool {
    ++st.steps;
    if (b.f < 0.0 && !checked && empty(qa, a, qb, b)) return false;
    if (qb - qa == 1) {
      if (b.f < 0.0) return false;
      bq = qb, bfa = a.f, bfb = b.f;
      return true;
    }
    const long qm = qa + (qb - qa) / 2;
    const Val m = value(qm);
    if (self(self, qa, a, qm, m, false)) return true;
    return self(self, qm, m, qb, b, false);
  };

  std::optional<double> tHit;
  bool bracketed = false;
  constexpr long kCell = kSubdivisions;
  constexpr long kSpan = 8 * kSubdivisions;  // interval spans of 8 cells
  long q = q0;
  bool known = false;  // fa = f(q)
  Val fa{0, 0};
  long prevQ = q0 - 2;  // the last point evaluated before q, and its value
  double prevF = -1.0;
  int shortSteps = 0;
  long failedUntil[2] = {q0 - 1, q0 - 1};
  while (q < q1) {
    ++st.steps;
    bool cellChecked = false;  // the interval test of [q, q + kCell] ran (and failed)
    if (!rc.inWindow(q, q)) {
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
        shortSteps = 5;
      } else if (fa.l < 0.0) {
        const long reachQ = std::min(q1, q + static_cast<long>(std::min(-fa.l / h8, 1e15)) + 1);
        const Box2 step = xyBox(pq, at(reachQ));
        const Box2 inDomain{std::max(step.x0, dom.x0), std::max(step.y0, dom.y0), std::min(step.x1, dom.x1), std::min(step.y1, dom.y1)};
        const double lf = lipschitzAlong(ray.dir, field_.bound(inDomain), workpieceKind_);
        n = static_cast<long>(std::min((-fa.l - kPruneEps) / (lf * h8), 1e15));
        n = std::max(0L, std::min(n, rc.nextWindow(q + 1, q1 + 1) - q - 1));
      }
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
      // stretch is not tried again until it is passed).
      bool skipped = false;
      for (int level = 0; level < 3 && !skipped; ++level) {
        const long len = level == 0 ? 4 * kSpan : level == 1 ? kSpan : kCell;
        if (level < 2 && q < failedUntil[level]) continue;
        if (empty(q, unknown, q + len, unknown)) {
          q += len;
          skipped = true;
        } else if (level < 2) {
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
    const Val fb = value(q + kCell);
    if (search(search, q, fa, q + kCell, fb, cellChecked)) {
      bracketed = true;
      break;
    }
    prevQ = q0 - 2;  // f(q + kCell - 1) is not known
    q += kCell, fa = fb;
  }
  if (bracketed) {
    // Regula falsi with the Illinois modification inside [bq - 1, bq]: a function of
    // f on that sixty-fourth of a cell alone.
    double a = static_cast<double>(bq - 1) * h8, b = static_cast<double>(bq) * h8, fa = bfa, fb = bfb;
    int side = 0;
    for (int i = 0; i < kRefinements; ++i) {
      const double t = b - fb * (b - a) / (fb - fa);
      if (!(t > a && t < b)) break;
      const double ft = fieldValue(rc, ray.origin + t * ray.dir, st, scratch);
      if (ft >= 0.0) {
        b = t, fb = ft;
        if (side == 1) fa *= 0.5;
        side = 1;
      } else {
        a = t, fa = ft;
        if (side == -1) fb *= 0.5;
        side = -1;
      }
      if (std::abs(ft) < 1e-12) break;
    }
    tHit = std::clamp(b - fb * (b - a) / (fb - fa), a, b);
  }
  if (!tHit) return std::nullopt;
  ++st.hits;
  const glm::dvec3 p = ray.origin + *tHit * ray.dir;
  return Hit{p, fieldNormal(p, st, scratch), ray.dir};
}

// ---------------------------------------------------------------- the exact tracer

std::optional<Renderer::Hit> Renderer::traceExact(int px, int py, RenderStats& st, std::vector<std::uint32_t>& scratch) const {
  const Ray ray = camera_->ray(px, py);
  ++st.rays;
  double t0, t1;
  if (!clipRay(ray, bounds_, t0, t1)) return std::nullopt;

  const Model& m = *model_;
  const bool naive = options_.naive;
  auto candidatesAt = [&](double x, double y) -> std::span<const std::uint32_t> {
    return naive ? std::span<const std::uint32_t>(all_) : grid_.at(x, y, scratch);
  };
  auto value = [&](double t) {
    const glm::dvec3 p = ray.origin + t * ray.dir;
    const auto c = candidatesAt(p.x, p.y);
    ++st.evaluations, st.opsVisited += c.size();
    return m.evaluate(P3<double>{p.x, p.y, p.z}, c);
  };
  auto bound = [&](double ta, double tb) {
    const glm::dvec3 a = ray.origin + ta * ray.dir, b = ray.origin + tb * ray.dir;
    const P3<Interval> box = boxOf(a, b);
    const auto c = naive ? std::span<const std::uint32_t>(all_)
                         : grid_.in(Box2{box.x.lo, box.y.lo, box.x.hi, box.y.hi}, scratch);
    ++st.evaluations, st.opsVisited += c.size();
    return m.evaluate(box, c);
  };

  const double h = step_;
  // Steps are aligned to multiples of h along the ray, spans to multiples of 8 h.
  long k = static_cast<long>(std::floor(t0 / (h * kSpanSteps))) * kSpanSteps;
  const long kEnd = static_cast<long>(std::ceil(t1 / h));
  std::optional<double> hitT;

  auto refine = [&](double ta, double fa, double tb, double fb) {
    for (int i = 0; i < kBisections; ++i) {
      const double tm = 0.5 * (ta + tb);
      const double fm = value(tm);
      if (fm >= 0)
        tb = tm, fb = fm;
      else
        ta = tm, fa = fm;
    }
    return 0.5 * (ta + tb);
  };
  std::function<std::optional<double>(double, double, double, int)> search;
  search = [&](double ta, double fa, double tb, int depth) -> std::optional<double> {
    ++st.steps;
    const Interval b = bound(ta, tb);
    if (b.hi < 0.0) return std::nullopt;
    const double fb = value(tb);
    if (fa < 0.0 && fb >= 0.0) return refine(ta, fa, tb, fb);
    if (fa >= 0.0) return ta;  // started inside (camera inside the piece)
    if (depth >= kThinSplits) return std::nullopt;
    // Both ends outside but the bound allows a surface: a thin feature may pass between them.
    const double q = (tb - ta) * 0.25;
    double prevT = ta, prevF = fa;
    for (int i = 1; i <= 4; ++i) {
      const double tn = i == 4 ? tb : ta + q * i;
      if (auto r = search(prevT, prevF, tn, depth + 1)) return r;
      prevT = tn;
      prevF = i == 4 ? fb : value(tn);
    }
    return std::nullopt;
  };

  double fPrev = value(k * h);
  for (; k < kEnd && !hitT; k += kSpanSteps) {
    const double ta = k * h, tb = (k + kSpanSteps) * h;
    ++st.steps;
    const Interval span = bound(ta, tb);
    if (span.hi < 0.0) {
      fPrev = value(tb);
      continue;
    }
    double tPrev = ta;
    for (int j = 1; j <= kSpanSteps && !hitT; ++j) {
      const double tn = (k + j) * h;
      hitT = search(tPrev, fPrev, tn, 0);
      tPrev = tn;
      fPrev = value(tn);
    }
  }
  if (!hitT) return std::nullopt;
  ++st.hits;
  const glm::dvec3 p = ray.origin + *hitT * ray.dir;
  const auto c = candidatesAt(p.x, p.y);
  ++st.evaluations, st.opsVisited += c.size();
  const Grad g = m.evaluate(P3<Grad>{Grad(p.x, 1, 0, 0), Grad(p.y, 0, 1, 0), Grad(p.z, 0, 0, 1)}, c);
  glm::dvec3 n(-g.dx, -g.dy, -g.dz);
  const double len = glm::length(n);
  n = len > 0 ? n / len : glm::dvec3(0, 0, 1);
  return Hit{p, n, ray.dir};
}

// ---------------------------------------------------------------- frames

bool Renderer::render(Image& image, const Rect& rectIn, RenderStats* stats, const std::atomic_bool* cancel) {
  const int w = camera_->width(), h = camera_->height();
  if (image.width != w || image.height != h) image = Image(w, h);
  Rect rect{std::max(0, rectIn.x), std::max(0, rectIn.y), 0, 0};
  rect.w = std::min(w, rectIn.x + rectIn.w) - rect.x;
  rect.h = std::min(h, rectIn.y + rectIn.h) - rect.y;
  if (rect.empty()) return true;
  const bool field = usesField();
  // Small rectangles (dirty updates) in smaller tiles, so that every thread gets a share; the
  // tiles change no pixel.
  int tileSize = options_.tileSize;
  while (tileSize > 8 && static_cast<long>(rect.w / tileSize + 1) * (rect.h / tileSize + 1) < 6L * pool_.size()) tileSize /= 2;
  std::mutex statsMutex;
  std::atomic_bool aborted{false};
  const bool done = pool_.parallelFor2D(rect, tileSize, [&](const Rect& tile) {
    using Clock = std::chrono::steady_clock;
    thread_local std::vector<std::uint32_t> scratch;
    thread_local std::vector<std::optional<Hit>> hits;
    RenderStats st;
    const auto start = Clock::now();
    hits.resize(static_cast<size_t>(tile.w) * tile.h);
    for (int y = tile.y; y < tile.y + tile.h; ++y) {
      // A superseded frame stops within a row.
      if (cancel && cancel->load(std::memory_order_relaxed)) {
        aborted = true;
        return;
      }
      for (int x = tile.x; x < tile.x + tile.w; ++x)
        hits[static_cast<size_t>(y - tile.y) * tile.w + (x - tile.x)] =
            field ? traceField(x, y, st, scratch) : traceExact(x, y, st, scratch);
    }
    const auto traced = Clock::now();
    for (int y = tile.y; y < tile.y + tile.h; ++y)
      for (int x = tile.x; x < tile.x + tile.w; ++x) {
        const auto& hit = hits[static_cast<size_t>(y - tile.y) * tile.w + (x - tile.x)];
        std::uint8_t* px = image.pixel(x, y);
        if (hit) {
          const auto rgb = toSrgb8Fast(shadeMetal(shading_, hit->p, hit->n, hit->dir));
          px[0] = rgb[0], px[1] = rgb[1], px[2] = rgb[2];
        } else {
          const std::uint8_t* b = &backdrop_[(static_cast<size_t>(y) * w + x) * 3];
          px[0] = b[0], px[1] = b[1], px[2] = b[2];
        }
        px[3] = 255;
      }
    st.traceSeconds = std::chrono::duration<double>(traced - start).count();
    st.shadeSeconds = secondsSince(traced);
    if (stats) {
      std::lock_guard lock(statsMutex);
      *stats += st;
    }
  }, cancel);
  return done && !aborted.load();
}

bool Renderer::renderFull(Image& image, RenderStats* stats, const std::atomic_bool* cancel) {
  return render(image, Rect{0, 0, camera_->width(), camera_->height()}, stats, cancel);
}

// ---------------------------------------------------------------- dirty regions

Rect Renderer::projectBox(const Box3& b) const {
  double x0 = 1e30, y0 = 1e30, x1 = -1e30, y1 = -1e30;
  for (double x : {b.x0, b.x1})
    for (double y : {b.y0, b.y1})
      for (double z : {b.z0, b.z1}) {
        const auto q = camera_->project({x, y, z});
        if (!q) return {0, 0, camera_->width(), camera_->height()};
        x0 = std::min(x0, q->x), y0 = std::min(y0, q->y), x1 = std::max(x1, q->x), y1 = std::max(y1, q->y);
      }
  // A ray meets the box only if its pixel centre projects inside the corners' hull.
  const int w = camera_->width(), h = camera_->height();
  const double lim = 1e6;
  const int cx0 = std::clamp(static_cast<int>(std::floor(std::max(x0, -lim))) - 1, 0, w);
  const int cy0 = std::clamp(static_cast<int>(std::floor(std::max(y0, -lim))) - 1, 0, h);
  const int cx1 = std::clamp(static_cast<int>(std::ceil(std::min(x1, lim))) + 1, 0, w);
  const int cy1 = std::clamp(static_cast<int>(std::ceil(std::min(y1, lim))) + 1, 0, h);
  return {cx0, cy0, cx1 - cx0, cy1 - cy0};
}

Rect Renderer::dirtyRect(const Model& model, size_t index) const {
  if (index >= model.operations().size()) return {};
  const auto& ops = model.operations();
  const PreparedOp& op = ops[index];
  const Box3 wb = model.workpiece().bounds();
  std::vector<std::uint32_t> scratch;

  if (!usesField()) {
    // The exact tracer: f changes in the support's column; a surface can be anywhere the model's
    // bounds allow, counted with the operation even when it was just undone. Interval spans
    // reach 8 steps from the ray.
    const double g = kSpanSteps * step_;
    double reach = 0.0;
    const size_t n = std::max(model.activeCount(), index + 1);
    for (size_t i = 0; i < n; ++i) reach += peakOf(ops[i].op());
    Box3 box{0, 0, wb.z0 - reach - g, 0, 0, wb.z1 + reach + g};
    for (size_t i = 0; i < n; ++i) {
      const Operation& o = ops[i].op();
      if (o.isOffset()) continue;
      const Box3 t = o.tool.bounds();
      const double r = kernels::kSupportSpan * o.tool.size() + reach + g;
      box.z0 = std::min(box.z0, t.z0 - r), box.z1 = std::max(box.z1, t.z1 + r);
    }
    const Box2 s = op.support().grown(g);
    box.x0 = s.x0, box.y0 = s.y0, box.x1 = s.x1, box.y1 = s.y1;
    return projectBox(box);
  }

  // The field tracer. A pixel's result depends on the signs of f at its ray's grid points, on f
  // within the cell of its hit, and on the field's stencil and the set operations at the hit.
  const double cell = step_ + 1e-6;
  if (!op.op().isOffset()) {
    // A set operation changes f only within its 3D support, moved by the offsets after it.
    double shift = 0.0;
    for (std::uint32_t j : grid_.in(op.support(), scratch))
      if (j > index && j < model.activeCount() && ops[j].op().isOffset()) shift += peakOf(ops[j].op());
    const Box3 t = op.op().tool.bounds();
    const double r = kernels::kSupportSpan * op.op().tool.size() + shift + cell;
    const Box2 s = op.support().grown(cell);
    return projectBox({s.x0, s.y0, t.z0 - r, s.x1, s.y1, t.z1 + r});
  }
  // An offset changes the samples under its support, and through the Hermite stencil (the
  // twists read the neighbours' slopes) the patches up to two samples further.
  const Box2 s = op.support().grown(2.0 * field_.spacing() + cell);
  const double peak = peakOf(op.op());
  HeightField::Bound d = field_.rootBound();
  const Box2 dom = field_.domain();
  const Box2 q{std::max(s.x0, dom.x0), std::max(s.y0, dom.y0), std::min(s.x1, dom.x1), std::min(s.y1, dom.y1)};
  if (!q.empty()) d = field_.bound(q);
  // Before and after differ by at most the operation's peak.
  Box3 box{s.x0, s.y0, wb.z0 + d.lo - peak - cell, s.x1, s.y1, wb.z1 + d.hi + peak + cell};
  for (const SetOp& so : setOps_)
    if (so.support.overlaps(s)) box.z0 = std::min(box.z0, so.zlo - peak - cell), box.z1 = std::max(box.z1, so.zhi + peak + cell);
  return projectBox(box);
}

template double Renderer::exactDisplacement(const P3<double>&, std::span<const std::uint32_t>, RenderStats&) const;

}  // namespace emboss
