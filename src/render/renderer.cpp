// The ray tracers: the field tracer (sheet model; renderer_field.cpp and renderer_walk.cpp, its
// inputs renderer_sync.cpp) and the exact tracer (offset model, --naive); frames. Dirty regions:
// renderer_dirty.cpp.
#include "render/renderer_internal.h"
#include "render/shade_lanes.h"

namespace emboss {

using namespace render_internal;

// ---------------------------------------------------------------- the exact tracer

std::optional<Renderer::Hit> Renderer::traceExact(double sx, double sy, RenderStats& st, std::vector<std::uint32_t>& scratch) const {
  const Ray ray = camera_->rayAt(sx, sy);
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

namespace {

// An edge: the sheet against the backdrop, or a crease (neighbours' normals more than ~30 degrees
// apart: a groove's lip, a rim, a punch's shoulder). Smooth shading (the dimples, a highlight
// across a dome) is no edge: extra rays there cost the frame far more than a visitor sees (with a
// brightness criterion as well, 8 to 11 % of the pixels took them and the frame doubled).
constexpr float kCreaseCos = 0.87f;

// `r` grown by n pixels each way and clipped to a w x h image.
Rect grownWithin(const Rect& r, int n, int w, int h) {
  const int x0 = std::max(0, r.x - n), y0 = std::max(0, r.y - n);
  return {x0, y0, std::min(w, r.x + r.w + n) - x0, std::min(h, r.y + r.h + n) - y0};
}

}  // namespace

bool Renderer::missesSurely(double sx, double sy, bool field, const Rect& reach) const {
  return sx < reach.x || sy < reach.y || sx > reach.x + reach.w || sy > reach.y + reach.h ||
         (field && !outlineMask_.empty() && outlineMaskMisses(sx, sy));
}

std::optional<Renderer::Hit> Renderer::findHit(double sx, double sy, bool field, const Rect& reach, RenderStats& st,
                                               std::vector<std::uint32_t>& scratch, double* kept, bool reuse,
                                               bool normal) const {
  if (kept && reuse && !std::isnan(*kept)) {
    // The hit the ray found before, which no change since can have moved: the same point (the
    // same t on the same ray), its normal from the field as the trace gives it.
    ++st.reshaded;
    if (std::isinf(*kept)) return std::nullopt;
    const Ray ray = camera_->rayAt(sx, sy);
    const glm::dvec3 p = ray.origin + *kept * ray.dir;
    return Hit{p, normal ? fieldNormal(p, st, scratch) : glm::dvec3(0.0), ray.dir, *kept};
  }
  // Outside the projection of every surface the ray misses for certain: not even set up.
  if (missesSurely(sx, sy, field, reach)) {
    ++st.rays;
    if (kept) *kept = std::numeric_limits<double>::infinity();
    return std::nullopt;
  }
  std::optional<Hit> hit = field ? traceField(sx, sy, st, scratch, normal) : traceExact(sx, sy, st, scratch);
  if (kept) *kept = hit ? hit->t : std::numeric_limits<double>::infinity();
  return hit;
}

bool Renderer::render(Image& image, const Rect& rectIn, RenderStats* stats, const std::atomic_bool* cancel) {
  return render(image, PixelSpans::of(grownWithin(rectIn, 0, camera_->width(), camera_->height())), stats, cancel);
}

bool Renderer::render(Image& image, const PixelSpans& spans, RenderStats* stats, const std::atomic_bool* cancel) {
  return render(image, spans, stats, cancel, options_.reuseHits);
}

bool Renderer::render(Image& image, const PixelSpans& spansIn, RenderStats* stats, const std::atomic_bool* cancel,
                      bool reuse) {
  const int w = camera_->width(), h = camera_->height();
  if (image.width != w || image.height != h) image = Image(w, h);
  const PixelSpans spans = spansIn.grown(0, w, h);  // clipped to the image
  if (spans.empty()) return true;
  const Rect rect = spans.box;
  const bool field = usesField();
  // The pile's tops serve a frame that crosses much of the pile; a dirty update crosses few of its
  // columns, and after a stroke there it would find theirs again each time (renderer.h, PileTops).
  pileTopsNow_ = !reuse;
  // Two passes. The first traces one ray through the centre of every pixel of the spans and of
  // the ring of pixels around them; the second writes the spans' pixels, each from its own
  // centre sample, or, where it differs from a neighbour's (an edge: the sheet against the
  // backdrop, a crease), from two more rays inside it. A pixel's bytes so depend on its own and
  // its four neighbours' rays only: dirtySpans() grows by one pixel for it.
  const bool antialias = antialias_;
  const PixelSpans ringSpans = spans.grown(antialias ? 1 : 0, w, h);
  const Rect ring = ringSpans.box;
  // Per pixel of the ring's box: the centre sample's linear colour and its normal (zero: no hit),
  // written by the first pass for every pixel it traces; the second reads a colour and a normal
  // only where `hits` says the ray hit, so only `hits` starts cleared.
  const size_t ringPixels = static_cast<size_t>(ring.w) * ring.h;
  if (centre_.size() < ringPixels) centre_.resize(ringPixels), normal_.resize(ringPixels), hits_.resize(ringPixels);
  glm::vec3* const centre = centre_.data();
  glm::vec3* const normal = normal_.data();
  // Whether the centre ray hit (derivable from the normal, but a byte the second pass reads four
  // times a pixel is cheaper than three float comparisons: about 4 ms a frame on one thread).
  std::uint8_t* const hits = hits_.data();
  std::fill_n(hits, ringPixels, std::uint8_t{0});
  auto at = [&](int x, int y) { return static_cast<size_t>(y - ring.y) * ring.w + (x - ring.x); };
  // Small rectangles (dirty updates) in smaller tiles, so that every thread gets a share; the
  // tiles change no pixel.
  int tileSize = options_.tileSize;
  while (tileSize > 8 && static_cast<long>(rect.w / tileSize + 1) * (rect.h / tileSize + 1) < 6L * pool_.size()) tileSize /= 2;
  std::mutex statsMutex;
  std::atomic_bool aborted{false};
  const std::optional<std::chrono::steady_clock::time_point> deadline = deadline_;
  // One pass: `rowOf(y, x0, x1, ...)` over each tile's stretch of each row of `area` on the pool,
  // its wall time per tile summed into the stats' `seconds`. A superseded frame stops within a row.
  // `tileDone(st, scratch, aborted)` after each tile's rows (or when it stops early).
  auto pass = [&](const PixelSpans& area, double RenderStats::*seconds, const auto& rowOf, const auto& tileDone) {
    using Clock = std::chrono::steady_clock;
    return pool_.parallelFor2D(area.box, tileSize, [&](const Rect& tile) {
      thread_local std::vector<std::uint32_t> scratch;
      RenderStats st;
      const auto start = Clock::now();
      for (int y = tile.y; y < tile.y + tile.h; ++y) {
        if ((cancel && cancel->load(std::memory_order_relaxed)) || (deadline && Clock::now() > *deadline)) {
          aborted = true;
          tileDone(st, scratch, true);
          return;
        }
        const PixelSpans::Span row = area.row(y);
        const int x0 = std::max(tile.x, row.x0), x1 = std::min(tile.x + tile.w, row.x1);
        if (x0 < x1) rowOf(y, x0, x1, st, scratch);
      }
      tileDone(st, scratch, false);
      st.*seconds = std::chrono::duration<double>(Clock::now() - start).count();
      std::lock_guard lock(statsMutex);
      if (stats) *stats += st;
    }, cancel) && !aborted.load();
  };
  // Rays through image points outside `reach` miss every surface: the projection of the box that
  // holds them (projectBox() is conservative by a pixel).
  const Rect reach = options_.cullOutsideClip ? projectBox(field ? fieldClip_ : bounds_) : Rect{0, 0, w, h};
  if (field) updateOutlineMask();
  // A miss's centre colour (the backdrop) is only needed on an edge: found there.
  // The field tracer keeps every centre ray's hit (hitCaches_), and with `reuse` shades a kept one
  // again instead of tracing.
  HitCache& cache = hitCaches_[0];
  double* const kept = field && cache.t.size() == static_cast<size_t>(w) * h ? cache.t.data() : nullptr;
  // The edges' samples' kept hits, set up (none known) by the first anti-aliased frame after
  // setCamera() or forgetMovedHits() dropped them.
  if (kept && antialias && cache.sampled.size() != cache.t.size()) {
    cache.samples.resize(2 * cache.t.size());  // (read only where `sampled` says)
    cache.sampled.assign(cache.t.size(), 0);
  }
  double* const keptSamples = kept && antialias ? cache.samples.data() : nullptr;
  std::uint8_t* const sampled = kept && antialias ? cache.sampled.data() : nullptr;
  if (kept && cache.blank) {
    cache.blank = false;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    pool_.parallelFor2D(Rect{0, 0, 1, h}, 64, [&](const Rect& band) {
      std::fill(kept + static_cast<size_t>(band.y) * w, kept + static_cast<size_t>(band.y + band.h) * w, nan);
    });
  }
  // Both passes shade their hits a batch at a time: found, their normals and their cavities in
  // SIMD lanes, then the metal in lanes too (the same bits as one at a time:
  // shadeMetal(const ShadingParams&, ShadeBatch&)), or under a patina one hit at a time.
  // The field tracer's rays found a row (or a row's edge samples) at a time, their walks in SIMD
  // lanes (findFieldHits()).
  const bool inLanes = field && walksInLanes();
  // Finishes a batch of hits: the field tracer's get their normals here (D's slopes at them read
  // in lanes too: HeightField::valuesAndGradients) and their cavities (cavityDepths); then the
  // metal. normalOf(j, n) gets a field hit's normal, colourOf(j, c) every hit's colour.
  auto finish = [&](ShadeBatch& batch, RenderStats& st, std::vector<std::uint32_t>& scratch, const auto& normalOf,
                    const auto& colourOf) {
    thread_local std::array<double, ShadeBatch::kCapacity> dv, dgx, dgy, lx, ly, lz;
    thread_local std::array<bool, ShadeBatch::kCapacity> inLanes;
    if (field) {
      field_.valuesAndGradients(batch.px, batch.py, batch.n, dv.data(), dgx.data(), dgy.data());
      sheetNormals(batch.px, batch.py, batch.pz, dv.data(), dgx.data(), dgy.data(), batch.n, lx.data(), ly.data(),
                   lz.data(), inLanes.data(), st);
      for (int j = 0; j < batch.n; ++j) {
        const auto jj = static_cast<size_t>(j);
        const Grad d(dv[jj], dgx[jj], dgy[jj], 0.0);
        const glm::dvec3 n = inLanes[jj] ? glm::dvec3(lx[jj], ly[jj], lz[jj])
                                         : fieldNormal(glm::dvec3(batch.px[j], batch.py[j], batch.pz[j]), st, scratch, &d);
        normalOf(j, n);
        batch.nx[j] = n.x, batch.ny[j] = n.y, batch.nz[j] = n.z;
      }
      field_.cavityDepths(batch.px, batch.py, batch.n, batch.cavity);
      for (int j = 0; j < batch.n; ++j) batch.cavity[j] = cavityOfDepth(batch.cavity[j]);
    } else {
      std::fill_n(batch.cavity, batch.n, 0.0);
    }
    // Every hit in lanes; those under a patina tinted after (shadeMetal() with the patina, bit for
    // bit: its colour without it times patinaTint()).
    shadeMetal(shading_, batch);
    for (int j = 0; j < batch.n; ++j) {
      const Patina patina = hasPatina_ ? patinaAt(batch.px[j], batch.py[j], scratch) : Patina{};
      if (!patina.any()) {
        colourOf(j, glm::dvec3(batch.r[j], batch.g[j], batch.b[j]));
        continue;
      }
      colourOf(j, glm::dvec3(batch.r[j], batch.g[j], batch.b[j]) * patinaTint(shading_, batch.pz[j], batch.cavity[j], patina));
    }
    batch.n = 0;
  };
  // A hit into the batch (its normal too when the exact tracer found it).
  auto add = [](ShadeBatch& batch, const Hit& hit) {
    const int j = batch.n++;
    batch.px[j] = hit.p.x, batch.py[j] = hit.p.y, batch.pz[j] = hit.p.z;
    batch.nx[j] = hit.n.x, batch.ny[j] = hit.n.y, batch.nz[j] = hit.n.z;
    batch.vx[j] = hit.dir.x, batch.vy[j] = hit.dir.y, batch.vz[j] = hit.dir.z;
    return j;
  };
  const bool traced = pass(ringSpans, &RenderStats::traceSeconds, [&](int y, int x0, int x1, RenderStats& st, std::vector<std::uint32_t>& scratch) {
    thread_local ShadeBatch batch;
    thread_local std::array<size_t, ShadeBatch::kCapacity> slots;
    const auto flush = [&] {
      finish(batch, st, scratch, [&](int j, const glm::dvec3& n) { normal[slots[static_cast<size_t>(j)]] = glm::vec3(n); },
             [&](int j, const glm::dvec3& c) { centre[slots[static_cast<size_t>(j)]] = glm::vec3(c); });
    };
    batch.n = 0;
    thread_local std::vector<std::optional<Hit>> found;
    thread_local std::vector<double> xs, ys;
    if (inLanes) {
      const auto n = static_cast<size_t>(x1 - x0);
      found.resize(n), xs.resize(n), ys.resize(n);
      for (int x = x0; x < x1; ++x) xs[static_cast<size_t>(x - x0)] = x + 0.5, ys[static_cast<size_t>(x - x0)] = y + 0.5;
      findFieldHits(xs.data(), ys.data(), x1 - x0, reach, st, scratch,
                    kept ? kept + static_cast<size_t>(y) * w + x0 : nullptr, reuse, found.data());
    }
    for (int x = x0; x < x1; ++x) {
      const size_t i = at(x, y);
      double* const k = kept ? kept + static_cast<size_t>(y) * w + x : nullptr;
      const std::optional<Hit> hit =
          inLanes ? found[static_cast<size_t>(x - x0)] : findHit(x + 0.5, y + 0.5, field, reach, st, scratch, k, reuse, !field);
      if (!hit) continue;  // (a miss's normal is never read: `hits` says it missed)
      hits[i] = 1;
      if (!field) normal[i] = glm::vec3(hit->n);
      slots[static_cast<size_t>(add(batch, *hit))] = i;
      if (batch.full()) flush();
    }
    if (batch.n > 0) flush();
  }, [](RenderStats&, std::vector<std::uint32_t>&, bool) {});
  if (!traced) return false;
  // Whether pixel i = (x, y) is an edge: it differs from a neighbour in hitting, or its normal
  // from a neighbour's by more than the crease angle.
  auto edgeAt = [&](int x, int y, size_t i, bool hit) {
    if (!antialias) return false;  // (one ray a pixel: no neighbour read)
    if (x > ring.x && y > ring.y && x + 1 < ring.x + ring.w && y + 1 < ring.y + ring.h) {
      // All four neighbours in the ring (nearly every pixel): the same test, unrolled.
      const size_t l = i - 1, r = i + 1, u = i - static_cast<size_t>(ring.w), d = i + static_cast<size_t>(ring.w);
      if (!hit) return (hits[l] | hits[r] | hits[u] | hits[d]) != 0;
      if ((hits[l] & hits[r] & hits[u] & hits[d]) == 0) return true;
      const glm::vec3 n = normal[i];
      return glm::dot(n, normal[l]) < kCreaseCos || glm::dot(n, normal[r]) < kCreaseCos ||
             glm::dot(n, normal[u]) < kCreaseCos || glm::dot(n, normal[d]) < kCreaseCos;
    }
    bool edge = false;
    for (const auto& [dx, dy] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
      const int nx = x + dx, ny = y + dy;
      if (nx < ring.x || ny < ring.y || nx >= ring.x + ring.w || ny >= ring.y + ring.h) continue;
      const size_t j = at(nx, ny);
      if ((hits[j] != 0) != hit || (hit && glm::dot(normal[i], normal[j]) < kCreaseCos)) edge = true;
    }
    return edge;
  };
  // A row's shaded pixels are written together: their colours' bytes found in lanes
  // (toSrgb8Channels()) when the row is done.
  struct RowColours {
    std::vector<int> xs;
    std::vector<double> linear;  // r, g, b a pixel
    std::vector<std::uint8_t> bytes;
  };
  thread_local RowColours row;
  auto put = [&](int x, const glm::dvec3& c) {  // (the row is writeRow()'s)
    row.xs.push_back(x);
    row.linear.insert(row.linear.end(), {c.r, c.g, c.b});
  };
  auto writeRow = [&](int y) {
    const size_t n = row.xs.size();
    row.bytes.resize(3 * n);
    toSrgb8Channels(row.linear.data(), static_cast<int>(3 * n), row.bytes.data());
    for (size_t k = 0; k < n; ++k) {
      std::uint8_t* px = image.pixel(row.xs[k], y);
      px[0] = row.bytes[3 * k], px[1] = row.bytes[3 * k + 1], px[2] = row.bytes[3 * k + 2], px[3] = 255;
    }
    row.xs.clear(), row.linear.clear();
  };
  // The second pass: a pixel from its centre sample, or on an edge from that and two more rays
  // inside it (their hits shaded together, in lanes: the field tracer's a tile's edges at once,
  // after the tile's other pixels are written; so a few edges a row still fill the lanes).
  struct EdgePixel {
    int x, y;
    glm::dvec3 c, samples[2];
  };
  // Edge pixel (x, y)'s sample k's kept hit (NaN: not known; a stopped frame leaves it so).
  const auto sampleSlot = [&](int x, int y, int k) -> double* {
    if (!keptSamples) return nullptr;
    const size_t i = static_cast<size_t>(y) * w + x;
    if (!sampled[i]) {
      keptSamples[2 * i] = keptSamples[2 * i + 1] = std::numeric_limits<double>::quiet_NaN();
      sampled[i] = 1;
    }
    return keptSamples + 2 * i + k;
  };
  thread_local std::vector<EdgePixel> edges;
  thread_local ShadeBatch batch;
  thread_local std::array<int, ShadeBatch::kCapacity> slots;  // 2 e + k: edge e's sample k
  // The field tracer's edge samples: their image points, found together (findFieldHits()), and
  // their kept hits (gathered from the cache and put back).
  thread_local std::vector<double> xs, ys, ks;
  thread_local std::vector<std::optional<Hit>> found;
  const auto flush = [&](RenderStats& st, std::vector<std::uint32_t>& scratch) {
    finish(batch, st, scratch, [](int, const glm::dvec3&) {}, [&](int j, const glm::dvec3& c) {
      const int slot = slots[static_cast<size_t>(j)];
      edges[static_cast<size_t>(slot / 2)].samples[slot % 2] = c;
    });
  };
  // The edges' pixels from their three samples each, a row's (x, y) in turn.
  auto writeEdges = [&] {
    int y = -1;
    for (const EdgePixel& p : edges) {
      if (p.y != y && y >= 0) writeRow(y);
      y = p.y;
      glm::dvec3 sum = p.c;
      sum += p.samples[0];
      sum += p.samples[1];
      put(p.x, sum / 3.0);
    }
    if (y >= 0) writeRow(y);
    edges.clear();
  };
  // The tile's edge samples traced and shaded, and its edges written.
  const auto edgesDone = [&](RenderStats& st, std::vector<std::uint32_t>& scratch, bool stopped) {
    if (stopped || !inLanes) {
      edges.clear(), xs.clear(), ys.clear(), ks.clear(), batch.n = 0;
      return;
    }
    if (!xs.empty()) {
      found.resize(xs.size());
      findFieldHits(xs.data(), ys.data(), static_cast<int>(xs.size()), reach, st, scratch, keptSamples ? ks.data() : nullptr,
                    reuse, found.data());
      if (keptSamples)
        for (size_t j = 0; j < ks.size(); ++j) *sampleSlot(edges[j / 2].x, edges[j / 2].y, static_cast<int>(j % 2)) = ks[j];
      for (size_t j = 0; j < found.size(); ++j) {
        const std::optional<Hit>& sh = found[j];
        if (!sh) {  // as sample() gives it
          edges[j / 2].samples[j % 2] = backdrop(static_cast<int>(std::floor(xs[j])), static_cast<int>(std::floor(ys[j])), w, h);
          continue;
        }
        slots[static_cast<size_t>(add(batch, *sh))] = static_cast<int>(j);
        if (batch.full()) flush(st, scratch);
      }
    }
    if (batch.n > 0) flush(st, scratch);
    xs.clear(), ys.clear(), ks.clear();
    writeEdges();
  };
  return pass(spans, &RenderStats::shadeSeconds, [&](int y, int x0, int x1, RenderStats& st, std::vector<std::uint32_t>& scratch) {
    row.xs.clear(), row.linear.clear();
    if (!inLanes) edges.clear(), batch.n = 0;
    for (int x = x0; x < x1; ++x) {
      const size_t i = at(x, y);
      const bool hit = hits[i] != 0;
      const bool edge = edgeAt(x, y, i, hit);
      if (!edge && !hit) {
        std::uint8_t* px = image.pixel(x, y);
        const std::uint8_t* bd = &backdrops_[0].bytes[(static_cast<size_t>(y) * w + x) * 3];
        px[0] = bd[0], px[1] = bd[1], px[2] = bd[2], px[3] = 255;
        continue;
      }
      const glm::dvec3 c = hit ? glm::dvec3(centre[i]) : glm::dvec3(glm::vec3(backdrop(x, y, w, h)));
      if (!edge) {
        put(x, c);
        continue;
      }
      ++st.edgePixels;
      const int e = static_cast<int>(edges.size());
      edges.push_back(EdgePixel{x, y, c, {}});
      for (int k = 0; k < 2; ++k) {
        const double sx = x + 0.5 + kEdgeSamples[k][0], sy = y + 0.5 + kEdgeSamples[k][1];
        double* const slot = sampleSlot(x, y, k);
        if (inLanes) {
          xs.push_back(sx), ys.push_back(sy);
          if (slot) ks.push_back(*slot);
          continue;
        }
        const std::optional<Hit> sh = findHit(sx, sy, field, reach, st, scratch, slot, reuse, !field);
        if (!sh) {  // as sample() gives it
          edges.back().samples[k] = backdrop(static_cast<int>(std::floor(sx)), static_cast<int>(std::floor(sy)), w, h);
          continue;
        }
        slots[static_cast<size_t>(add(batch, *sh))] = 2 * e + k;
        if (batch.full()) flush(st, scratch);
      }
    }
    writeRow(y);
    if (!inLanes) {
      if (batch.n > 0) flush(st, scratch);
      writeEdges();
    }
  }, edgesDone);
}

bool Renderer::renderFull(Image& image, RenderStats* stats, const std::atomic_bool* cancel) {
  return render(image, PixelSpans::of(Rect{0, 0, camera_->width(), camera_->height()}), stats, cancel, false);
}

}  // namespace emboss
