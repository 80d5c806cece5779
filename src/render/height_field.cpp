// The displacement field: lattice, incremental updates, Hermite interpolation and the bound pyramid.
#include "render/height_field.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "render/field_lanes.h"
#include "render/leaf_bounds.h"
#include "render/shading.h"

namespace emboss {

namespace {

// Cubic Hermite basis on [0, 1]: h0, h1 weigh the end values, g0, g1 the end slopes (times the
// cell length); d* are their derivatives.
struct Basis {
  double h0, h1, g0, g1;
};
inline Basis basis(double u) {
  const double u2 = u * u;
  return {(2.0 * u - 3.0) * u2 + 1.0, (3.0 - 2.0 * u) * u2, ((u - 2.0) * u + 1.0) * u, (u - 1.0) * u2};
}
inline Basis basisDerivative(double u) {
  const double d0 = 6.0 * u * (u - 1.0);
  return {d0, -d0, (3.0 * u - 4.0) * u + 1.0, (3.0 * u - 2.0) * u};
}

float roundDown(double v) {
  const float f = static_cast<float>(v);
  return std::nextafter(f, -std::numeric_limits<float>::infinity());
}
float roundUp(double v) {
  const float f = static_cast<float>(v);
  return std::nextafter(f, std::numeric_limits<float>::infinity());
}

}  // namespace

void HeightField::configure(const Box2& domain, double spacing, bool cavity) {
  s_ = spacing;
  invS_ = 1.0 / spacing;
  x0_ = domain.x0;
  y0_ = domain.y0;
  gx0_ = x0_, gy0_ = y0_, gi_ = 0, gj_ = 0;
  nx_ = std::max(2, static_cast<int>(std::ceil((domain.x1 - domain.x0) * invS_)) + 1);
  ny_ = std::max(2, static_cast<int>(std::ceil((domain.y1 - domain.y0) * invS_)) + 1);
  xMax_ = x0_ + (nx_ - 1) * s_;
  yMax_ = y0_ + (ny_ - 1) * s_;
  samples_.assign(static_cast<size_t>(nx_) * ny_, Sample{});
  cavity_.clear();
  taps_.clear();
  tapWeights_.clear();
  cavityReach_ = 0;
  if (cavity) {
    cavity_.assign(samples_.size(), 0.0f);
    // A ring point k lies at a fixed offset in samples from every sample: its bilinear weights
    // are the same everywhere (taps of zero weight dropped).
    for (const auto& u : kCavityRing) {
      const double ox = kCavityReach * u[0] * invS_, oy = kCavityReach * u[1] * invS_;
      const int di = static_cast<int>(std::floor(ox)), dj = static_cast<int>(std::floor(oy));
      const double fx = ox - di, fy = oy - dj;
      const double w[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
      for (int t = 0; t < 4; ++t)
        if (w[t] > 0.0) taps_.push_back({di + (t & 1), dj + (t >> 1), static_cast<float>(w[t] / 6.0)});
      cavityReach_ = std::max({cavityReach_, std::abs(di) + 1, std::abs(dj) + 1});
    }
  }
  tapLo_[0] = tapLo_[1] = tapHi_[0] = tapHi_[1] = 0;
  for (const Tap& t : taps_) {
    tapWeights_.push_back(t.w);
    tapLo_[0] = std::min(tapLo_[0], t.di), tapHi_[0] = std::max(tapHi_[0], t.di);
    tapLo_[1] = std::min(tapLo_[1], t.dj), tapHi_[1] = std::max(tapHi_[1], t.dj);
  }
  levels_.clear();
  int w = (nx_ - 1 + kBlock - 1) / kBlock, h = (ny_ - 1 + kBlock - 1) / kBlock;
  for (;;) {
    Level l;
    l.w = w, l.h = h;
    l.nodes.assign(static_cast<size_t>(w) * h, Node{0, 0, 0, 0, 0, 0});
    levels_.push_back(std::move(l));
    if (w == 1 && h == 1) break;
    w = (w + 1) / 2, h = (h + 1) / 2;
  }
}

void HeightField::configureOn(const HeightField& lattice, const Box2& domain) {
  const double s = lattice.s_, inv = lattice.invS_;
  const int gi = static_cast<int>(std::floor((domain.x0 - lattice.gx0_) * inv));
  const int gj = static_cast<int>(std::floor((domain.y0 - lattice.gy0_) * inv));
  configure(Box2{lattice.gx0_ + gi * s, lattice.gy0_ + gj * s, domain.x1, domain.y1}, s);
  invS_ = inv;
  gx0_ = lattice.gx0_, gy0_ = lattice.gy0_, gi_ = gi, gj_ = gj;
}

void HeightField::clear() {
  nx_ = ny_ = 0;
  samples_.clear();
  samples_.shrink_to_fit();
  cavity_.clear();
  cavity_.shrink_to_fit();
  levels_.clear();
}

size_t HeightField::memoryBytes() const {
  size_t n = samples_.size() * sizeof(Sample) + cavity_.size() * sizeof(float);
  for (const auto& l : levels_) n += l.nodes.size() * sizeof(Node);
  return n;
}

HeightField::SampleRect HeightField::samplesIn(const Box2& b) const {
  if (b.empty() || !configured()) return {};
  // (In the lattice's indices, then this field's: the same samples as the lattice's own rule.)
  const double fi0 = std::ceil((b.x0 - gx0_) * invS_) - gi_, fi1 = std::floor((b.x1 - gx0_) * invS_) - gi_;
  const double fj0 = std::ceil((b.y0 - gy0_) * invS_) - gj_, fj1 = std::floor((b.y1 - gy0_) * invS_) - gj_;
  if (fi1 < 0 || fj1 < 0 || fi0 > nx_ - 1 || fj0 > ny_ - 1) return {};
  SampleRect r;
  r.i0 = static_cast<int>(std::max(fi0, 0.0));
  r.j0 = static_cast<int>(std::max(fj0, 0.0));
  r.i1 = static_cast<int>(std::min(fi1, static_cast<double>(nx_ - 1)));
  r.j1 = static_cast<int>(std::min(fj1, static_cast<double>(ny_ - 1)));
  return r;
}

HeightField::SampleRect HeightField::intersect(const SampleRect& a, const SampleRect& b) {
  return {std::max(a.i0, b.i0), std::max(a.j0, b.j0), std::min(a.i1, b.i1), std::min(a.j1, b.j1)};
}

HeightField::SampleRect HeightField::grow(const SampleRect& r, int n) {
  return {r.i0 - n, r.j0 - n, r.i1 + n, r.j1 + n};
}

HeightField::SampleRect HeightField::unite(const SampleRect& a, const SampleRect& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  return {std::min(a.i0, b.i0), std::min(a.j0, b.j0), std::max(a.i1, b.i1), std::max(a.j1, b.j1)};
}

HeightField::SampleRect HeightField::clamp(const SampleRect& r) const { return intersect(r, all()); }

namespace {
// A sample's sum continued by one offset (the same arithmetic wherever the offset was found).
inline void addOffset(HeightField::Sample& s, const Grad& o) {
  s.d = static_cast<float>(static_cast<double>(s.d) + o.v);
  s.dx = static_cast<float>(static_cast<double>(s.dx) + o.dx);
  s.dy = static_cast<float>(static_cast<double>(s.dy) + o.dy);
}
}  // namespace

void HeightField::addTo(const PreparedOp& op, const SampleRect& r, OffsetValues* keep) {
  // A row at a time (the sheet's offsets do not depend on z): a path's nearest segments are found
  // for the whole row in SIMD lanes. Per thread: bands run on the pool.
  thread_local std::vector<double> xs;
  thread_local std::vector<Grad> g;
  const int n = r.i1 - r.i0 + 1;
  xs.resize(static_cast<size_t>(n));
  g.resize(static_cast<size_t>(n));
  for (int i = r.i0; i <= r.i1; ++i) xs[static_cast<size_t>(i - r.i0)] = sampleX(i);
  for (int j = r.j0; j <= r.j1; ++j) {
    op.offsetRow(sampleY(j), xs.data(), n, g.data());
    Sample* row = &samples_[static_cast<size_t>(j) * nx_];
    for (int i = r.i0; i <= r.i1; ++i) addOffset(row[i], g[static_cast<size_t>(i - r.i0)]);
    if (keep) {
      const size_t w = static_cast<size_t>(keep->r.i1 - keep->r.i0 + 1);
      std::copy_n(g.data(), n, &keep->g[static_cast<size_t>(j + gj_ - keep->r.j0) * w + static_cast<size_t>(r.i0 + gi_ - keep->r.i0)]);
    }
  }
}

namespace {
// Runs f over bands of rows of r, on the pool when it is worth it (r holds minCount items or
// more: samples, or leaves of 64 samples).
template <class F>
void forBands(const HeightField::SampleRect& r, ThreadPool* pool, int minRows, F f, long minCount = 4096) {
  const int rows = r.j1 - r.j0 + 1;
  if (!pool || pool->size() < 2 || rows < 2 * minRows || r.count() < minCount) {
    f(r);
    return;
  }
  const int band = std::max(minRows, rows / (4 * pool->size()));
  pool->parallelFor2D(Rect{0, r.j0, 1, rows}, band, [&](const Rect& t) {
    f(HeightField::SampleRect{r.i0, t.y, r.i1, t.y + t.h - 1});
  });
}
}  // namespace

void HeightField::add(const PreparedOp& op, ThreadPool* pool) { add(op, all(), pool); }

void HeightField::add(const PreparedOp& op, const SampleRect& rows, ThreadPool* pool, OffsetValues* keep) {
  if (!op.op().isOffset()) return;
  const SampleRect r = intersect(samplesIn(op.support()), rows);
  if (r.empty()) return;
  if (keep) {
    const SampleRect l = toLattice(r);
    const bool next = !keep->g.empty() && keep->x0 == gx0_ && keep->y0 == gy0_ && keep->s == s_ && keep->r.i0 == l.i0 &&
                      keep->r.i1 == l.i1 && keep->r.j1 + 1 == l.j0;
    if (next) {
      keep->r.j1 = l.j1;
    } else {
      keep->x0 = gx0_, keep->y0 = gy0_, keep->s = s_;
      keep->r = l;
    }
    keep->g.resize(static_cast<size_t>(keep->r.count()));
  }
  forBands(r, pool, 4, [&](const SampleRect& b) { addTo(op, b, keep); });
}

bool HeightField::add(const PreparedOp& op, const OffsetValues& values, const SampleRect& rows) {
  if (!op.op().isOffset()) return true;
  const SampleRect r = intersect(samplesIn(op.support()), rows);
  if (r.empty()) return true;
  const SampleRect v = values.r, l = toLattice(r);
  if (values.x0 != gx0_ || values.y0 != gy0_ || values.s != s_) return false;
  if (l.i0 < v.i0 || l.i1 > v.i1 || l.j0 < v.j0 || l.j1 > v.j1) return false;
  const size_t w = static_cast<size_t>(v.i1 - v.i0 + 1);
  for (int j = r.j0; j <= r.j1; ++j) {
    const Grad* g = &values.g[static_cast<size_t>(j + gj_ - v.j0) * w + static_cast<size_t>(r.i0 + gi_ - v.i0)];
    Sample* row = &samples_[static_cast<size_t>(j) * nx_];
    for (int i = r.i0; i <= r.i1; ++i) addOffset(row[i], g[i - r.i0]);
  }
  return true;
}

void HeightField::recompute(const SampleRect& rIn, std::span<const PreparedOp* const> ops) {
  const SampleRect r = clamp(rIn);
  if (r.empty()) return;
  for (int j = r.j0; j <= r.j1; ++j)
    for (int i = r.i0; i <= r.i1; ++i) at(i, j) = Sample{};
  for (const PreparedOp* op : ops) {
    if (!op->op().isOffset()) continue;
    const SampleRect s = intersect(samplesIn(op->support()), r);
    if (!s.empty()) addTo(*op, s);
  }
}

void HeightField::updateTwist(const SampleRect& r) {
  thread_local std::vector<float> twists;
  auto one = [&](int i, int j) {
    const int jm = std::max(j - 1, 0), jp = std::min(j + 1, ny_ - 1);
    const int im = std::max(i - 1, 0), ip = std::min(i + 1, nx_ - 1);
    const double dxy = (static_cast<double>(at(i, jp).dx) - at(i, jm).dx) / ((jp - jm) * s_);
    const double dyx = (static_cast<double>(at(ip, j).dy) - at(im, j).dy) / ((ip - im) * s_);
    at(i, j).dxy = static_cast<float>(0.5 * (dxy + dyx));
  };
  for (int j = r.j0; j <= r.j1; ++j) {
    if (j == 0 || j == ny_ - 1) {  // a one-sided difference across the rows
      for (int i = r.i0; i <= r.i1; ++i) one(i, j);
      continue;
    }
    // Inside the lattice both differences are central: a row at a time in SIMD lanes (only the
    // twists are written; the slopes the lanes read stay as they are).
    const int a = std::max(r.i0, 1), b = std::min(r.i1, nx_ - 2);
    if (r.i0 < a) one(r.i0, j);
    if (a <= b) {
      twists.resize(static_cast<size_t>(b - a + 1));
      twistRow(&at(a, j - 1).d, &at(a, j).d, &at(a, j + 1).d, b - a + 1, 2 * s_, twists.data());
      for (int i = a; i <= b; ++i) at(i, j).dxy = twists[static_cast<size_t>(i - a)];
    }
    if (r.i1 > b && r.i1 >= a) one(r.i1, j);
  }
}

void HeightField::updateLeaves(int la0, int lb0, int la1, int lb1) {
  Level& l = levels_[0];
  const double s = s_;
  LeafSamples net;
  for (int lb = lb0; lb <= lb1; ++lb)
    for (int la = la0; la <= la1; ++la) {
      const int i0 = la * kBlock, i1 = std::min(i0 + kBlock, nx_ - 1);
      const int j0 = lb * kBlock, j1 = std::min(j0 + kBlock, ny_ - 1);
      // Per sample, once (not once per patch it is a corner of): its value, a third of its scaled
      // slopes and a ninth of its scaled twist. A corner's signs only negate them (exactly), so the
      // nets leafNetBounds works out are those of the patches' own arithmetic, bit for bit.
      static_assert(sizeof(Sample) == 4 * sizeof(float), "samples are four floats, packed");
      loadLeafSamples(&at(i0, j0).d, 4L * nx_, i1 - i0 + 1, j1 - j0 + 1, s, net);
      const LeafNetBounds b = leafNetBounds(net, i1 - i0, j1 - j0);
      l.nodes[static_cast<size_t>(lb) * l.w + la] = leafNode(b.lo, b.hi, b.uLo, b.uHi, b.vLo, b.vHi);
    }
}

HeightField::Node HeightField::leafNode(double lo, double hi, double uLo, double uHi, double vLo, double vHi) const {
  // The patch and its derivatives lie in the convex hulls of their Bezier nets; a small margin
  // covers the rounding of the evaluation.
  const double m = 1e-7 * (1.0 + std::max(std::abs(lo), std::abs(hi)));
  const double gm = 1e-6 * (1.0 + std::max({std::abs(uLo), std::abs(uHi), std::abs(vLo), std::abs(vHi)}));
  return {roundDown(lo - m), roundUp(hi + m), roundDown((uLo - gm) * invS_), roundUp((uHi + gm) * invS_),
          roundDown((vLo - gm) * invS_), roundUp((vHi + gm) * invS_)};
}

void HeightField::finishFlat() {
  // Every sample is zero (configure()): every patch is zero, so every leaf is the leaf of a zero
  // net, and every level above is the same node.
  const Node zero = leafNode(0, 0, 0, 0, 0, 0);
  for (Level& l : levels_) std::fill(l.nodes.begin(), l.nodes.end(), zero);
  std::fill(cavity_.begin(), cavity_.end(), 0.0f);  // a flat sheet has no cavity
}

void HeightField::updateCavity(const SampleRect& r) {
  // Away from the lattice's edges a sample's depth is its taps' weighted sum less its own D, in
  // float, in the taps' order (in lanes: tapSumsLanes()); near them the ring is read through
  // valueBilinear() (clamped to the domain). Either way a function of the sample's position and
  // the D around it alone, so an update over part of the lattice gives the bits a full one does.
  const int tiLo = tapLo_[0], tiHi = tapHi_[0], tjLo = tapLo_[1], tjHi = tapHi_[1];
  auto edge = [&](int i, int j) {
    const double ring = cavityRingMean(sampleX(i), sampleY(j), [&](double x, double y) { return valueBilinear(x, y); });
    cavity_[static_cast<size_t>(j) * nx_ + i] = static_cast<float>(ring - at(i, j).d);
  };
  // D of the samples the rect's taps read, row by row without the other three floats of a sample:
  // each tap's row is then read in lanes.
  thread_local std::vector<float> plane;
  thread_local std::vector<const float*> rows;
  const int pi0 = std::max(0, r.i0 + tiLo), pi1 = std::min(nx_ - 1, r.i1 + tiHi);
  const int pj0 = std::max(0, r.j0 + tjLo), pj1 = std::min(ny_ - 1, r.j1 + tjHi);
  const int pw = pi1 - pi0 + 1;
  if (pw <= 0 || pj1 < pj0) return;
  plane.resize(static_cast<size_t>(pw) * static_cast<size_t>(pj1 - pj0 + 1));
  for (int j = pj0; j <= pj1; ++j) {
    const Sample* src = &at(pi0, j);
    float* dst = &plane[static_cast<size_t>(j - pj0) * pw];
    for (int k = 0; k < pw; ++k) dst[k] = src[k].d;
  }
  auto inPlane = [&](int i, int j) { return &plane[static_cast<size_t>(j - pj0) * pw + static_cast<size_t>(i - pi0)]; };
  rows.resize(taps_.size());
  for (int j = r.j0; j <= r.j1; ++j) {
    const bool rowInside = j + tjLo >= 0 && j + tjHi <= ny_ - 1;
    const int a = rowInside ? std::max(r.i0, -tiLo) : r.i1 + 1, b = rowInside ? std::min(r.i1, nx_ - 1 - tiHi) : r.i1;
    for (int i = r.i0; i < std::min(a, r.i1 + 1); ++i) edge(i, j);
    if (a <= b) {
      for (size_t t = 0; t < taps_.size(); ++t) rows[t] = inPlane(a + taps_[t].di, j + taps_[t].dj);
      tapSumsLanes(rows.data(), tapWeights_.data(), static_cast<int>(taps_.size()), inPlane(a, j), b - a + 1,
                   &cavity_[static_cast<size_t>(j) * nx_ + a]);
    }
    for (int i = std::max(b + 1, a); i <= r.i1; ++i) edge(i, j);
  }
}

double HeightField::cavityDepth(double x, double y) const {
  if (cavity_.empty()) return 0.0;
  return bilinear(x, y, [&](size_t k) { return cavity_[k]; });
}

void HeightField::valuesAndGradients(const double* x, const double* y, int n, double* v, double* gx, double* gy) const {
  static_assert(sizeof(Sample) == 4 * sizeof(float));
  if (samples_.empty()) {  // not configured: D is 0 everywhere
    std::fill_n(v, n, 0.0), std::fill_n(gx, n, 0.0), std::fill_n(gy, n, 0.0);
    return;
  }
  const int done = hermiteLanes(lattice(), x, y, n, v, gx, gy);
  for (int k = done; k < n; ++k) valueAndGradient(x[k], y[k], v[k], gx[k], gy[k]);
}

void HeightField::cavityDepths(const double* x, const double* y, int n, double* out) const {
  int done = 0;
  if (!cavity_.empty()) done = bilinearLanes(FloatLattice{x0_, y0_, invS_, nx_, ny_, cavity_.data()}, x, y, n, out);
  for (int k = done; k < n; ++k) out[k] = cavityDepth(x[k], y[k]);
}

void HeightField::updateLevels(int la0, int lb0, int la1, int lb1) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  for (size_t k = 1; k < levels_.size(); ++k) {
    la0 >>= 1, lb0 >>= 1, la1 >>= 1, lb1 >>= 1;
    const Level& c = levels_[k - 1];
    Level& l = levels_[k];
    for (int b = lb0; b <= lb1; ++b)
      for (int a = la0; a <= la1; ++a) {
        Node n{inf, -inf, inf, -inf, inf, -inf};
        for (int cb = 2 * b; cb <= std::min(2 * b + 1, c.h - 1); ++cb)
          for (int ca = 2 * a; ca <= std::min(2 * a + 1, c.w - 1); ++ca) {
            const Node& m = c.nodes[static_cast<size_t>(cb) * c.w + ca];
            n.lo = std::min(n.lo, m.lo), n.hi = std::max(n.hi, m.hi);
            n.gxlo = std::min(n.gxlo, m.gxlo), n.gxhi = std::max(n.gxhi, m.gxhi);
            n.gylo = std::min(n.gylo, m.gylo), n.gyhi = std::max(n.gyhi, m.gyhi);
          }
        l.nodes[static_cast<size_t>(b) * l.w + a] = n;
      }
  }
}

void HeightField::finish(const SampleRect& rIn, ThreadPool* pool) {
  const SampleRect r = clamp(rIn);
  if (r.empty()) return;
  // Twists use the slopes one sample away; a leaf's bounds read the samples on its edges.
  const SampleRect t = clamp(grow(r, 1));
  forBands(t, pool, 4, [&](const SampleRect& b) { updateTwist(b); });
  const Level& l = levels_[0];
  const int la0 = std::max(0, (t.i0 - 1) / kBlock), lb0 = std::max(0, (t.j0 - 1) / kBlock);
  const int la1 = std::min(l.w - 1, t.i1 / kBlock), lb1 = std::min(l.h - 1, t.j1 / kBlock);
  // Leaves by rows of leaves (disjoint nodes).
  forBands(SampleRect{la0, lb0, la1, lb1}, pool, 1, [&](const SampleRect& b) { updateLeaves(b.i0, b.j0, b.i1, b.j1); }, 64);
  updateLevels(la0, lb0, la1, lb1);
  if (!cavity_.empty()) {
    const SampleRect c = clamp(grow(r, cavityReach_));
    forBands(c, pool, 4, [&](const SampleRect& b) { updateCavity(b); });
  }
}

namespace {

// The lattice's cell (ci, cj) of the point fx, fy cells from its origin, unclamped: floor().
inline void latticeCell(double fx, double fy, int& ci, int& cj) {
  ci = static_cast<int>(fx), cj = static_cast<int>(fy);
  ci -= fx < ci, cj -= fy < cj;
}

// The Hermite patch of the cell whose first sample is r0 (the row above it nx on), at the place the
// bases bu, bv were found for. Scalar on purpose: four-lane vector types (GCC/Clang vector
// extensions) measured no faster here -- the patch is 16 values and the cost is in the loads
// (docs/performance.md).
inline double patchValue(const HeightField::Sample* r0, int nx, double s, const Basis& bu, const Basis& bv) {
  const HeightField::Sample* r1 = r0 + nx;
  const double a0 = bu.h0 * r0[0].d + bu.h1 * r0[1].d + s * (bu.g0 * r0[0].dx + bu.g1 * r0[1].dx);
  const double a1 = bu.h0 * r1[0].d + bu.h1 * r1[1].d + s * (bu.g0 * r1[0].dx + bu.g1 * r1[1].dx);
  const double b0 = bu.h0 * r0[0].dy + bu.h1 * r0[1].dy + s * (bu.g0 * r0[0].dxy + bu.g1 * r0[1].dxy);
  const double b1 = bu.h0 * r1[0].dy + bu.h1 * r1[1].dy + s * (bu.g0 * r1[0].dxy + bu.g1 * r1[1].dxy);
  return bv.h0 * a0 + bv.h1 * a1 + s * (bv.g0 * b0 + bv.g1 * b1);
}

}  // namespace

// The cell of (x, y) and where in it, in the lattice's coordinates: every field on a lattice finds
// the same (u, v) at a point inside its cells (a field's own origin would round differently).
inline void HeightField::cellOf(double x, double y, int& i, int& j, double& u, double& v) const {
  const double fx = (x - gx0_) * invS_, fy = (y - gy0_) * invS_;
  int ci, cj;
  latticeCell(fx, fy, ci, cj);
  i = std::clamp(ci - gi_, 0, nx_ - 2), j = std::clamp(cj - gj_, 0, ny_ - 2);
  u = fx - (i + gi_), v = fy - (j + gj_);
}

double HeightField::value(double x, double y) const {
  int i, j;
  double u, v;
  cellOf(x, y, i, j, u, v);
  return patchValue(&samples_[static_cast<size_t>(j) * nx_ + i], nx_, s_, basis(u), basis(v));
}

HeightField::LatticePoint HeightField::latticePoint(double x, double y) const {
  LatticePoint p;
  p.x = x, p.y = y;
  const double fx = (x - gx0_) * invS_, fy = (y - gy0_) * invS_;  // (as cellOf())
  latticeCell(fx, fy, p.ci, p.cj);
  const Basis bu = basis(fx - p.ci), bv = basis(fy - p.cj);
  p.bu[0] = bu.h0, p.bu[1] = bu.h1, p.bu[2] = bu.g0, p.bu[3] = bu.g1;
  p.bv[0] = bv.h0, p.bv[1] = bv.h1, p.bv[2] = bv.g0, p.bv[3] = bv.g1;
  return p;
}

double HeightField::value(const LatticePoint& p) const {
  // value() finds this cell, and u = fx - ci, wherever the cell is not clamped to the lattice.
  const int i = p.ci - gi_, j = p.cj - gj_;
  if (i < 0 || j < 0 || i > nx_ - 2 || j > ny_ - 2) return value(p.x, p.y);
  return patchValue(&samples_[static_cast<size_t>(j) * nx_ + i], nx_, s_, Basis{p.bu[0], p.bu[1], p.bu[2], p.bu[3]},
                    Basis{p.bv[0], p.bv[1], p.bv[2], p.bv[3]});
}

template <class Get>
double HeightField::bilinear(double x, double y, const Get& get) const {
  const double fx = std::clamp((x - x0_) * invS_, 0.0, nx_ - 1.0), fy = std::clamp((y - y0_) * invS_, 0.0, ny_ - 1.0);
  const int i = std::min(static_cast<int>(fx), nx_ - 2), j = std::min(static_cast<int>(fy), ny_ - 2);
  const double u = fx - i, v = fy - j;
  const size_t k0 = static_cast<size_t>(j) * nx_ + i, k1 = k0 + static_cast<size_t>(nx_);
  const double a = get(k0) + u * (get(k0 + 1) - get(k0)), b = get(k1) + u * (get(k1 + 1) - get(k1));
  return a + v * (b - a);
}

double HeightField::valueBilinear(double x, double y) const {
  return bilinear(x, y, [&](size_t k) { return samples_[k].d; });
}

void HeightField::valueAndGradient(double x, double y, double& v, double& gx, double& gy) const {
  int i, j;
  double cu, cv;
  cellOf(x, y, i, j, cu, cv);
  const Basis bu = basis(cu), bv = basis(cv);
  const Basis du = basisDerivative(cu), dv = basisDerivative(cv);
  const Sample* r0 = &samples_[static_cast<size_t>(j) * nx_ + i];
  const Sample* r1 = r0 + nx_;
  const double s = s_;
  auto rowD = [&](const Basis& b, const Sample* r) { return b.h0 * r[0].d + b.h1 * r[1].d + s * (b.g0 * r[0].dx + b.g1 * r[1].dx); };
  auto rowY = [&](const Basis& b, const Sample* r) { return b.h0 * r[0].dy + b.h1 * r[1].dy + s * (b.g0 * r[0].dxy + b.g1 * r[1].dxy); };
  const double a0 = rowD(bu, r0), a1 = rowD(bu, r1), b0 = rowY(bu, r0), b1 = rowY(bu, r1);
  v = bv.h0 * a0 + bv.h1 * a1 + s * (bv.g0 * b0 + bv.g1 * b1);
  gy = (dv.h0 * a0 + dv.h1 * a1 + s * (dv.g0 * b0 + dv.g1 * b1)) * invS_;
  const double c0 = rowD(du, r0), c1 = rowD(du, r1), e0 = rowY(du, r0), e1 = rowY(du, r1);
  gx = (bv.h0 * c0 + bv.h1 * c1 + s * (bv.g0 * e0 + bv.g1 * e1)) * invS_;
}

inline void HeightField::leavesUnder(const Box2& b, int& a0, int& a1, int& b0, int& b1) const {
  static_assert(kBlock == 8, "leaf indices are cell indices shifted by 3");
  a0 = std::clamp(static_cast<int>((b.x0 - x0_) * invS_), 0, nx_ - 2) >> 3;
  a1 = std::clamp(static_cast<int>((b.x1 - x0_) * invS_), 0, nx_ - 2) >> 3;
  b0 = std::clamp(static_cast<int>((b.y0 - y0_) * invS_), 0, ny_ - 2) >> 3;
  b1 = std::clamp(static_cast<int>((b.y1 - y0_) * invS_), 0, ny_ - 2) >> 3;
}

HeightField::Bound HeightField::bound(const Box2& b) const {
  int a0, a1, b0, b1;
  leavesUnder(b, a0, a1, b0, b1);
  if (a0 == a1 && b0 == b1) {  // one leaf (most of a walk's steps near the surface)
    const Level& l = levels_[0];
    const Node& n = l.nodes[static_cast<size_t>(b0) * l.w + a0];
    return {n.lo, n.hi, n.gxlo, n.gxhi, n.gylo, n.gyhi};
  }
  size_t k = 0;
  while ((a1 - a0 > 1 || b1 - b0 > 1) && k + 1 < levels_.size()) {
    a0 >>= 1, a1 >>= 1, b0 >>= 1, b1 >>= 1;
    ++k;
  }
  const Level& l = levels_[k];
  // At most 2 x 2 nodes; a missing second column or row repeats the first.
  const Node& n00 = l.nodes[static_cast<size_t>(b0) * l.w + a0];
  const Node& n10 = l.nodes[static_cast<size_t>(b0) * l.w + a1];
  const Node& n01 = l.nodes[static_cast<size_t>(b1) * l.w + a0];
  const Node& n11 = l.nodes[static_cast<size_t>(b1) * l.w + a1];
  auto mn = [](float p, float q, float r, float t) { return std::min(std::min(p, q), std::min(r, t)); };
  auto mx = [](float p, float q, float r, float t) { return std::max(std::max(p, q), std::max(r, t)); };
  return {mn(n00.lo, n10.lo, n01.lo, n11.lo),       mx(n00.hi, n10.hi, n01.hi, n11.hi),
          mn(n00.gxlo, n10.gxlo, n01.gxlo, n11.gxlo), mx(n00.gxhi, n10.gxhi, n01.gxhi, n11.gxhi),
          mn(n00.gylo, n10.gylo, n01.gylo, n11.gylo), mx(n00.gyhi, n10.gyhi, n01.gyhi, n11.gyhi)};
}

HeightField::Bound HeightField::leafBound(const Box2& b) const {
  int a0, a1, b0, b1;
  leavesUnder(b, a0, a1, b0, b1);
  const Level& l = levels_[0];
  float lo = std::numeric_limits<float>::infinity(), hi = -lo, gxlo = lo, gxhi = hi, gylo = lo, gyhi = hi;
  for (int j = b0; j <= b1; ++j)
    for (int i = a0; i <= a1; ++i) {
      const Node& n = l.nodes[static_cast<size_t>(j) * l.w + i];
      lo = std::min(lo, n.lo), hi = std::max(hi, n.hi);
      gxlo = std::min(gxlo, n.gxlo), gxhi = std::max(gxhi, n.gxhi);
      gylo = std::min(gylo, n.gylo), gyhi = std::max(gyhi, n.gyhi);
    }
  return {lo, hi, gxlo, gxhi, gylo, gyhi};
}

HeightField::Bound HeightField::rootBound() const {
  const Node& n = levels_.back().nodes[0];
  return {n.lo, n.hi, n.gxlo, n.gxhi, n.gylo, n.gyhi};
}

void HeightField::save(const SampleRect& rIn, Saved& out) const {
  const SampleRect r = clamp(rIn);
  out.r = r;
  out.samples.clear();
  if (r.empty()) return;
  out.samples.reserve(static_cast<size_t>(r.count()));
  for (int j = r.j0; j <= r.j1; ++j) {
    const Sample* row = &samples_[static_cast<size_t>(j) * nx_];
    out.samples.insert(out.samples.end(), row + r.i0, row + r.i1 + 1);
  }
}

void HeightField::restore(const Saved& saved) {
  const SampleRect& r = saved.r;
  if (r.empty() || saved.samples.size() != static_cast<size_t>(r.count())) return;
  const int w = r.i1 - r.i0 + 1;
  for (int j = r.j0; j <= r.j1; ++j)
    std::copy_n(&saved.samples[static_cast<size_t>(j - r.j0) * w], w, &at(r.i0, j));
}

}  // namespace emboss
