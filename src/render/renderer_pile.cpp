// The pile of set operations bounded from above, column by column (renderer.h, PileTops;
// docs/rendering.md, "The pile's tops"): a ray inside a window of set operations skips the stretch
// above the tops of the columns it crosses before the window's own steps and interval tests, which
// near a pile of flat tools beating the relief down fail as often as not.
#include <cmath>
#include <limits>

#include "render/renderer_internal.h"
#include "util/portable_math.h"

namespace emboss {

using namespace render_internal;

namespace {

// The squares' side: four times the field's spacing (0.5 mm at its finest), a few pixels of the
// kiosk's view, and at most kMaxPileSquares of them over the field's domain.
constexpr double kPileSquareSamples = 4.0;
constexpr long kMaxPileSquares = 4L << 20;
// A column's top is searched down from the highest point anything there can reach in slabs of
// these heights in turn (mm): each level refines the last one's first slab that is not proven empty.
constexpr double kPileSlabs[] = {4.0, 1.0, 0.25, 0.0625};
// The margin kept above a column's top for the rounding of the rays' points.
constexpr double kPileMargin = 1e-6;

}  // namespace

void Renderer::refreshPileTops(bool all, const std::vector<Box2>& changed) {
  if (setOps_.empty() || !fieldReady_ || (workpieceKind_ != 1 && workpieceKind_ != 2) || frontThickness_ < 0.0) {
    pileTops_ = {};
    return;
  }
  const Box2 dom = field_.domain();
  double size = kPileSquareSamples * field_.spacing();
  auto count = [&](double extent) { return static_cast<long>(std::ceil(extent / size)); };
  while (count(dom.x1 - dom.x0) * count(dom.y1 - dom.y0) > kMaxPileSquares) size *= 2.0;
  const int nx = static_cast<int>(count(dom.x1 - dom.x0)), ny = static_cast<int>(count(dom.y1 - dom.y0));
  PileTops& g = pileTops_;
  if (!g.top || g.nx != nx || g.ny != ny || g.x0 != dom.x0 || g.y0 != dom.y0 || g.size != size) {
    g.x0 = dom.x0, g.y0 = dom.y0, g.size = size, g.inv = 1.0 / size, g.nx = nx, g.ny = ny;
    g.top = std::make_unique<std::atomic<float>[]>(static_cast<size_t>(nx) * static_cast<size_t>(ny));
    all = true;
  }
  const float unknown = std::numeric_limits<float>::quiet_NaN();
  if (all) {
    for (size_t k = 0; k < static_cast<size_t>(nx) * static_cast<size_t>(ny); ++k) g.top[k].store(unknown, std::memory_order_relaxed);
    return;
  }
  // A change of D or of a shift moves the bounds of the field's patches up to two samples round
  // it (their twists read their neighbours); a square's own hair and one more square for rounding.
  const double grow = 3.0 * field_.spacing() + size;
  for (const Box2& c : changed) {
    const int i0 = std::max(0, floorToInt((c.x0 - grow - g.x0) * g.inv)), i1 = std::min(nx - 1, floorToInt((c.x1 + grow - g.x0) * g.inv));
    const int j0 = std::max(0, floorToInt((c.y0 - grow - g.y0) * g.inv)), j1 = std::min(ny - 1, floorToInt((c.y1 + grow - g.y0) * g.inv));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) g.top[static_cast<size_t>(j) * nx + i].store(unknown, std::memory_order_relaxed);
  }
}

float Renderer::pileTop(int i, int j) const {
  const PileTops& g = pileTops_;
  std::atomic<float>& slot = g.top[static_cast<size_t>(j) * g.nx + i];
  const float kept = slot.load(std::memory_order_relaxed);
  if (!std::isnan(kept)) return kept;
  // The square, grown by a hair past the rounding of the points of the rays that read it.
  const double x0 = g.x0 + i * g.size, y0 = g.y0 + j * g.size;
  const double hair = 1e-6 * (1.0 + std::max({std::abs(x0), std::abs(y0), std::abs(x0 + g.size), std::abs(y0 + g.size)}));
  const Box2 xy{x0 - hair, y0 - hair, x0 + g.size + hair, y0 + g.size + hair};
  double top = std::numeric_limits<double>::infinity();  // nothing proven
  if (field_.containsBox(xy)) {
    // Above the front face's highest point and every set operation's box there f < 0 (as the
    // ray's own skip above the face, beginWalkFrom()); below, slabs proven empty by intervals
    // (fieldExcluded()'s, on a box rather than a ray's stretch).
    thread_local std::vector<const SetOp*> ops;
    ops.clear();
    const HeightField::Bound d = field_.bound(xy);
    double zHi = d.hi + frontThickness_, zLo = d.lo - frontThickness_;
    setOpSupports_.meeting(xy, [&](std::uint32_t k) {
      ops.push_back(&setOps_[k]);
      zHi = std::max(zHi, setOps_[k].zhi), zLo = std::min(zLo, setOps_[k].zlo);
    });
    RenderStats st;  // (not the ray's: the square's top is found once, by whichever ray asks first)
    const Interval dz(d.lo, d.hi), x(xy.x0, xy.x1), y(xy.y0, xy.y1);
    const auto empty = [&](double za, double zb) {
      const P3<Interval> box{x, y, Interval(za, zb)};
      const Interval w = workpieceValue(P3<Interval>{x, y, box.z - dz});
      return setOpsExclude(ops.data(), static_cast<int>(ops.size()), box, xy, w.hi, st);
    };
    top = zHi + kPileMargin;
    for (const double slab : kPileSlabs)
      while (top - slab >= zLo && empty(top - slab, top)) top -= slab;
  }
  // Rounded up to a float.
  float f = static_cast<float>(top);
  if (static_cast<double>(f) < top) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  slot.store(f, std::memory_order_relaxed);
  return f;
}

long Renderer::pileSkip(const Ray& ray, double h8, long q, long qEnd) const {
  const PileTops& g = pileTops_;
  if (!g.top || !(ray.dir.z < 0.0) || qEnd < q) return q - 1;
  const double t0 = static_cast<double>(q) * h8, tEnd = static_cast<double>(qEnd) * h8;
  const double iz = 1.0 / ray.dir.z;
  // Each turn: the ray's stretch over one square from t, above its top: proven outside up to where
  // it goes under the top or leaves the square (its closed side: the squares' hair holds the
  // points rounded across it).
  SquareWalk squares(ray, t0, g.x0, g.y0, g.size, g.inv);
  double t = t0;
  for (int guard = 0; guard < 256 && t < tEnd; ++guard) {
    if (squares.i < 0 || squares.j < 0 || squares.i >= g.nx || squares.j >= g.ny) break;
    const double top = static_cast<double>(pileTop(squares.i, squares.j)) + kPileMargin;
    const double tDown = (top - ray.origin.z) * iz;  // (z falls along the ray: above the top before it)
    if (!(tDown > t)) break;
    if (tDown <= squares.exit()) {
      t = tDown;
      break;
    }
    t = std::max(t, squares.next());
  }
  // The grid points before t are proven outside (t itself may be on the top; a point within
  // rounding of t lies within the margin above the top, or the hair of the square it left).
  if (t == t0) return q - 1;
  const long last = static_cast<long>(std::ceil(std::min(t, tEnd + h8) / h8)) - 1;
  return std::min(last, qEnd);
}

}  // namespace emboss
