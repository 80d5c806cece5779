// Scheduling the ray tracer for the kiosk: dirty rectangles first, previews and refinement bands after.
#include "app/frame_composer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <tuple>

namespace emboss {

namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// The time `ms` milliseconds after t.
std::chrono::steady_clock::time_point msAfter(std::chrono::steady_clock::time_point t, double ms) {
  return t + std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double, std::milli>(ms));
}

std::string cameraKey(const CameraSpec& c) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%d %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g", static_cast<int>(c.type),
                c.eye.x, c.eye.y, c.eye.z, c.target.x, c.target.y, c.target.z, c.up.x, c.up.y, c.up.z, c.fovDeg,
                c.height);
  return buf;
}

}  // namespace

namespace {

// Pairs merged while their union holds at most a quarter more pixels than the two: rectangles or
// spans (united by `unite`, counted by `area`); empty ones dropped.
template <class T, class Unite>
std::vector<T> mergeWhereCheap(std::vector<T> items, Unite unite) {
  items.erase(std::remove_if(items.begin(), items.end(), [](const T& r) { return r.empty(); }), items.end());
  bool merged = true;
  while (merged) {
    merged = false;
    for (size_t i = 0; i < items.size() && !merged; ++i)
      for (size_t j = i + 1; j < items.size() && !merged; ++j) {
        T u = unite(items[i], items[j]);
        if (static_cast<double>(u.area()) <= 1.25 * static_cast<double>(items[i].area() + items[j].area())) {
          items[i] = std::move(u);
          items.erase(items.begin() + static_cast<std::ptrdiff_t>(j));
          merged = true;
        }
      }
  }
  return items;
}

}  // namespace

std::vector<Rect> mergeRects(std::vector<Rect> rects) {
  return mergeWhereCheap(std::move(rects), [](const Rect& a, const Rect& b) { return unite(a, b); });
}

std::vector<PixelSpans> mergeSpans(std::vector<PixelSpans> spans) {
  return mergeWhereCheap(std::move(spans), [](const PixelSpans& a, const PixelSpans& b) { return a.united(b); });
}

FrameComposer::FrameComposer(ThreadPool& pool, int width, int height)
    : pool_(pool), w_(width), h_(height), frame_(width, height), rowMs_(static_cast<size_t>(std::max(height, 0)), 0.0f) {
  for (Slot& s : slots_) s.renderer = std::make_unique<Renderer>(pool_);
  setFieldBandMs(kFieldBandMs);
  slot_ = &slots_[0];
  renderer_ = slot_->renderer.get();
  for (size_t i = 3; i < frame_.rgba.size(); i += 4) frame_.rgba[i] = 255;
  nextBand_ = h_;
}

void FrameComposer::setFieldBandMs(double ms) {
  RenderOptions options;
  options.fieldBandMs = ms;
  fieldBandMs_ = ms;
  for (Slot& s : slots_) s.renderer->setOptions(options);
}

FrameComposer::BlankKey FrameComposer::blankKey() const {
  return {model_ ? &model_->workpiece() : nullptr, cameraKey(camera_), shadingKey_};
}

FrameComposer::Slot& FrameComposer::slotFor(const Model& model) {
  Slot* best = &slots_[0];
  for (Slot& s : slots_) {
    if (s.model == &model) return s;
    if (s.lastUse < best->lastUse) best = &s;
  }
  return *best;  // the one used longest ago follows the new model (from scratch)
}

void FrameComposer::release(const Model& model) {
  for (Slot& s : slots_)
    if (s.model == &model) {
      s.renderer->sync(model);
      if (&s == slot_) revision_ = model.revision();
    }
}

size_t FrameComposer::memoryBytes() const {
  size_t n = 0;
  for (const Slot& s : slots_) n += s.renderer->memoryBytes();
  return n;
}

void FrameComposer::show(const Model& model, const CameraSpec& camera, const ShadingParams& shading,
                         const ViewChanges& changes, bool moving) {
  bool full = changes.full || &model != model_;
  if (&model != model_) {
    slot_ = &slotFor(model);
    renderer_ = slot_->renderer.get();
  }
  slot_->lastUse = ++uses_;
  const std::string sk = std::string(shading.metal.name) + "/" + std::string(shading.tinge.name) + "/" +
                         std::to_string(shading.frontZ);
  if (sk != shadingKey_) {
    shadingKey_ = sk;
    shading_ = shading;
    full = true;
  }
  if (slot_->shadingKey != sk) {
    slot_->shadingKey = sk;
    renderer_->setShading(shading);
  }
  // (The cameras compared as they are: a camera in motion is shown at every turn of the loop, and
  // printing them into keys was a tenth of the kiosk's time in attract mode's swing.)
  if (!cameraSet_ || changes.camera || !(camera == camera_)) {
    if (!cameraSet_ || !(camera == camera_)) full = true;
    camera_ = camera;
    cameraSet_ = true;
  }
  if (!slot_->camera || !(*slot_->camera == camera)) {
    slot_->camera = camera;
    renderer_->setCamera(Camera(camera_, w_, h_));
  }
  if (&model != model_ || slot_->model != &model || model.revision() != revision_) {
    model_ = &model;
    slot_->model = &model;
    revision_ = model.revision();
    renderer_->sync(model);
    counters_.fieldRebuilds += renderer_->lastSync().rebuilt;
    // A big region still being added when the model changed: its other rows were added now.
    if (!full)
      if (PixelSpans r = renderer_->pendingSpans(); !r.empty()) urgent_.push_back(std::move(r));
  }
  if (full) {
    urgent_.clear();
    coarse_.clear();
    bandMsPerPx_ = 0;
    const auto it = model.activeCount() == 0 ? blanks_.find(blankKey()) : blanks_.end();
    if (it != blanks_.end()) {
      frame_ = it->second;
      needPreview_ = false;
      nextBand_ = h_;
      ++counters_.blankReuses;
      blankCopied_ = true;
    } else {
      needPreview_ = true;
      nextBand_ = moving ? h_ : 0;
    }
    refineAfterMove_ = moving && it == blanks_.end();
    return;
  }
  if (!moving && refineAfterMove_) {
    refineAfterMove_ = false;
    nextBand_ = 0;
  }
  for (size_t i : changes.ops) {
    PixelSpans r = renderer_->dirtySpans(model, i);
    if (!r.empty()) urgent_.push_back(std::move(r));
  }
}

double FrameComposer::renderRect(const Rect& r, std::vector<Rect>& changed, bool onPiece) {
  return renderSpans(PixelSpans::of(r), changed, onPiece);
}

double FrameComposer::renderSpans(const PixelSpans& s, std::vector<Rect>& changed, bool onPiece,
                                  std::optional<std::chrono::steady_clock::time_point> deadline, bool* stopped) {
  RenderStats st;
  const auto t0 = std::chrono::steady_clock::now();
  renderer_->setDeadline(deadline);
  const bool done = renderer_->render(frame_, s, &st);
  renderer_->setDeadline(std::nullopt);
  const double ms = msSince(t0);
  counters_.render += st;
  changed.push_back(s.box);  // (some of its pixels even when it stopped)
  if (stopped) *stopped = !done;
  if (!done) return ms;
  // The dirty budget's speed is measured on what strokes change (the piece); a band's rows of
  // backdrop cost a small fraction of a row across the piece.
  const double area = static_cast<double>(s.area());
  if (onPiece && ms > 0.5 && area > 0) {
    const double speed = area / ms;
    pxPerMs_ = pxPerMs_ <= 0 ? speed : 0.8 * pxPerMs_ + 0.2 * speed;
  }
  return ms;
}

int FrameComposer::bandRows(double leftMs) const {
  // Rows from nextBand_ while their cost fits in what is left: each row's cost as measured last
  // time it was traced in a band; a row not measured yet costs the dearest row measured, or a
  // row of piece at the dirty rectangles' speed, whichever is more.
  double unknown = maxRowMs_;
  if (pxPerMs_ > 0) unknown = std::max(unknown, w_ / pxPerMs_);
  if (unknown <= 0) return bandRows_;
  double sum = 0;
  int rows = 0;
  while (nextBand_ + rows < h_) {
    const float m = rowMs_[static_cast<size_t>(nextBand_ + rows)];
    const double c = m > 0 ? m : unknown;
    if (rows >= 4 && sum + c > leftMs) break;
    sum += c;
    ++rows;
  }
  return rows;
}

// Bilinear enlargement into the frame, in 8-bit fixed point (weights 0..256): the columns'
// sources and weights once, then a row at a time.
void FrameComposer::enlarge(int lw, int lh, const PixelSpans& spans) {
  const Rect r = spans.box;
  if (r.empty()) return;
  struct Tap {
    int x0, x1, t;
  };
  const auto tap = [](int i, int n, int from) {
    const double f = std::clamp((i + 0.5) * from / n - 0.5, 0.0, from - 1.0);
    const int i0 = static_cast<int>(f);
    return Tap{i0, std::min(i0 + 1, from - 1), static_cast<int>(std::lround((f - i0) * 256.0))};
  };
  std::vector<Tap> taps(static_cast<size_t>(r.w));
  for (int x = 0; x < r.w; ++x) taps[static_cast<size_t>(x)] = tap(r.x + x, w_, lw);
  // Separable, in two passes over the pool: the low rows the box reads, each enlarged across once
  // (a * (256 - t) + b * t, unrounded: at most 65280), then each frame row blended from two of
  // them. The same bits as blending the four taps per pixel, at a third of the arithmetic (the
  // whole frame's enlargement took 10 to 35 ms on the main thread, most of a preview).
  const int low0 = tap(r.y, h_, lh).x0, low1 = tap(r.y + r.h - 1, h_, lh).x1;
  const size_t stride = static_cast<size_t>(r.w) * 3;
  across_.resize(static_cast<size_t>(low1 - low0 + 1) * stride);
  pool_.parallelFor2D(Rect{0, low0, 1, low1 - low0 + 1}, 16, [&](const Rect& band) {
    for (int ly = band.y; ly < band.y + band.h; ++ly) {
      const std::uint8_t* src = low_.pixel(0, ly);
      std::uint16_t* out = &across_[static_cast<size_t>(ly - low0) * stride];
      for (int x = 0; x < r.w; ++x, out += 3) {
        const Tap& tx = taps[static_cast<size_t>(x)];
        const std::uint8_t *a = src + 4 * tx.x0, *b = src + 4 * tx.x1;
        for (int k = 0; k < 3; ++k) out[k] = static_cast<std::uint16_t>(a[k] * (256 - tx.t) + b[k] * tx.t);
      }
    }
  });
  pool_.parallelFor2D(Rect{0, r.y, 1, r.h}, 32, [&](const Rect& band) {
    for (int y = band.y; y < band.y + band.h; ++y) {
      const PixelSpans::Span row = spans.row(y);
      if (row.empty()) continue;
      const Tap ty = tap(y, h_, lh);
      const std::uint16_t* top = &across_[static_cast<size_t>(ty.x0 - low0) * stride + static_cast<size_t>(row.x0 - r.x) * 3];
      const std::uint16_t* bottom = &across_[static_cast<size_t>(ty.x1 - low0) * stride + static_cast<size_t>(row.x0 - r.x) * 3];
      std::uint8_t* d = frame_.pixel(row.x0, y);
      const int wt = 256 - ty.t, wb = ty.t;
      for (int x = row.x0; x < row.x1; ++x, d += 4, top += 3, bottom += 3) {
        for (int k = 0; k < 3; ++k) d[k] = static_cast<std::uint8_t>((top[k] * wt + bottom[k] * wb + 32768) >> 16);
        d[3] = 255;
      }
    }
  });
}

void FrameComposer::traceCoarse(const PixelSpans& spans, std::vector<Rect>& changed, double budgetMs) {
  const Rect r = spans.box;
  // The low pixels the enlargement of r reads at a scale: its taps' span, one more each side.
  const auto lowSpan = [](int a, int b, int n, int from) {
    const int lo = static_cast<int>(std::floor((a + 0.5) * from / n - 0.5)) - 1;
    const int hi = static_cast<int>(std::ceil((b - 0.5) * from / n - 0.5)) + 1;
    return std::pair{std::clamp(lo, 0, from - 1), std::clamp(hi, 0, from - 1)};
  };
  const auto lowRect = [&](int scale) {
    const int lw = std::max(8, w_ / scale), lh = std::max(8, h_ / scale);
    const auto [x0, x1] = lowSpan(r.x, r.x + r.w, w_, lw);
    const auto [y0, y1] = lowSpan(r.y, r.y + r.h, h_, lh);
    return std::tuple{lw, lh, Rect{x0, y0, x1 - x0 + 1, y1 - y0 + 1}};
  };
  // The preview's scale, so the renderer's backdrop for that size is already there; coarser where
  // the last coarse traces cost more a pixel than fits in the budget (rays through a pile of set
  // operations cost ten times a plain sheet's, and the coarse picture held up the pen).
  int scale = previewScale_;
  while (!coarseScaleHeld_ && scale < kMaxCoarseScale &&
         static_cast<double>(std::get<2>(lowRect(scale)).area()) * coarseMsPerPx_ > budgetMs)
    ++scale;
  auto [lw, lh, low] = lowRect(scale);
  const auto t0 = std::chrono::steady_clock::now();
  renderer_->setCamera(Camera(camera_, lw, lh));
  RenderStats st;
  // The last coarse pictures' cost can be far from this one's (a pile of set operations grows
  // under the pen, rays through it cost ten times a plain sheet's): a picture that overruns its
  // budget stops, and the coarsest scale's is shown instead (a sixteenth of the rays a picture at
  // scale 4 traces). Not with a held scale (tests), whose pictures must not depend on the clock.
  if (!coarseScaleHeld_ && scale < kMaxCoarseScale)
    renderer_->setDeadline(msAfter(t0, kCoarseOverrun * std::max(budgetMs, minCoarseMs_)));
  // One ray a pixel: enlarged, an edge's extra rays show nothing.
  renderer_->setAntialias(false);
  const bool done = renderer_->render(low_, low, &st);
  renderer_->setDeadline(std::nullopt);
  const double ms = msSince(t0);
  // A low pixel's cost: over the picture's pixels, or over the rays it traced when it stopped
  // (none: the time went before the first ray, and says nothing of a ray's cost).
  if (done || st.rays > 0) {
    const double perPx = done ? ms / std::max(1.0, static_cast<double>(low.area())) : ms / static_cast<double>(st.rays);
    coarseMsPerPx_ = !done ? std::max(coarseMsPerPx_, perPx) : coarseMsPerPx_ > 0 ? 0.5 * (coarseMsPerPx_ + perPx) : perPx;
    // Its exact pixels will cost about what a coarse ray cost here (at least).
    bandMsPerPx_ = std::max(bandMsPerPx_, perPx);
  }
  if (!done) {
    ++counters_.coarseStopped;
    std::tie(lw, lh, low) = lowRect(kMaxCoarseScale);
    renderer_->setCamera(Camera(camera_, lw, lh));
    renderer_->render(low_, low, &st);
    scale = kMaxCoarseScale;
  }
  renderer_->setAntialias(true);
  renderer_->setCamera(Camera(camera_, w_, h_));
  lastCoarseScale_ = scale;
  counters_.render += st;
  enlarge(lw, lh, spans);
  ++counters_.coarseRects;
  changed.push_back(r);
}

void FrameComposer::preview(std::vector<Rect>& changed) {
  needPreview_ = false;
  const int pw = std::max(8, w_ / previewScale_), ph = std::max(8, h_ / previewScale_);
  const auto t0 = std::chrono::steady_clock::now();
  renderer_->setCamera(Camera(camera_, pw, ph));
  RenderStats st;
  renderer_->renderFull(low_, &st);
  renderer_->setCamera(Camera(camera_, w_, h_));
  counters_.render += st;
  enlarge(pw, ph, PixelSpans::of(Rect{0, 0, w_, h_}));
  const double ms = msSince(t0);
  counters_.lastPreviewMs = ms;
  ++counters_.previews;
  // Keep a preview within a frame at 30 Hz (a camera in motion shows nothing else): coarser
  // above 28 ms, finer below 12 (one step finer costs up to 1.8x: 4 -> 3 pixels a sample).
  if (ms > 28 && previewScale_ < 8) ++previewScale_;
  else if (ms < 12 && previewScale_ > 2) --previewScale_;
  changed.push_back({0, 0, w_, h_});
}

void FrameComposer::work(double budgetMs, std::vector<Rect>& changed, bool dirtyAlone, bool mayWait,
                         std::optional<std::chrono::steady_clock::time_point> presentBy) {
  waiting_ = false;
  if (!model_ || !cameraSet_) return;
  const auto t0 = std::chrono::steady_clock::now();
  // With mayWait, work whose cost is not known beforehand starts only with a period: traced late
  // in one it made the tick late. True when the call is to stop and wait.
  const auto waitForThePeriod = [&] {
    waiting_ = mayWait && budgetMs - msSince(t0) < kWaitUnlessMs;
    return waiting_;
  };
  if (blankCopied_) {
    blankCopied_ = false;
    changed.push_back({0, 0, w_, h_});
  }
  if (needPreview_) {
    if (waitForThePeriod()) return;  // (a preview is a whole period's work)
    preview(changed);
  }
  if (renderer_->fieldPending() && urgent_.empty()) {
    // A big raised region rises a band of rows a turn (Renderer::continueField), each band traced
    // as a dirty rectangle (coarse first when it is big).
    PixelSpans r = renderer_->continueField(fieldBandMs_);
    ++counters_.fieldBands;
    if (!r.empty()) urgent_.push_back(std::move(r));
  }
  // (A dirty rectangle's pixels cost ten times more where a set operation's tool must be traced
  // again than where the last hits are shaded again.)
  if (!urgent_.empty() && waitForThePeriod()) {
    ++counters_.dirtyWaits;
    return;
  }
  const std::vector<PixelSpans> dirty = mergeSpans(std::move(urgent_));
  urgent_.clear();
  // What the visitor just did is on the screen within the frame: when tracing all of it would
  // take longer than the dirty budget at the measured speed (until a trace has measured it, everything
  // is traced exactly), the big rectangles are traced coarse now and exactly after the present.
  long area = 0;
  for (const PixelSpans& r : dirty) area += r.area();
  const double speed = dirtySpeed();
  // The dirty budget, less what the step has spent of its frame (an exact trace that overruns
  // it and its coarse picture after fit in what is left).
  const auto tDirty = std::chrono::steady_clock::now();
  const double dirtyMs =
      presentBy ? std::clamp(-msSince(*presentBy) / (kDirtyOverrun + 0.25), minDirtyMs_, std::max(dirtyMs_, minDirtyMs_))
              : dirtyMs_;
  const bool tooSlow = speed > 0 && area > dirtyMs * speed;
  bool anyCoarse = false;
  for (const PixelSpans& r : dirty) {
    ++counters_.dirtyRects;
    counters_.dirtyPixels += static_cast<std::uint64_t>(r.area());
    if (tooSlow && r.area() > 0.25 * dirtyMs * speed) {
      // Shown coarse now, exactly a band of its rows at a time next (within what is left of the
      // dirty budget: two big rectangles share it).
      traceCoarse(r, changed, dirtyMs - msSince(tDirty));
      coarse_.push_back(r);
      anyCoarse = true;
    } else {
      // Traced exactly; where it costs far more than the speed promised (a pile of set operations
      // under a small rectangle), stopped and shown coarse instead (its rays traced so far kept).
      bool stopped = false;
      renderSpans(r, changed, true, msAfter(std::chrono::steady_clock::now(), kDirtyOverrun * dirtyMs), &stopped);
      if (stopped) {
        // (the dirty budget is spent: as coarse as a quarter of it allows)
        ++counters_.dirtyStopped;
        traceCoarse(r, changed, 0.25 * dirtyMs);
        coarse_.push_back(r);
        anyCoarse = true;
      }
    }
  }
  // (Merged: a big region's bands overlap by the shading's reach; their exact pixels once.)
  if (anyCoarse) coarse_ = mergeSpans(std::move(coarse_));
  if (anyCoarse || (dirtyAlone && !dirty.empty())) return;
  // The coarse rectangles' exact pixels, a band at a time in row order, oldest first: as many
  // pixels as fit in what is left at what the last band cost a pixel (at first what the coarse
  // pictures cost a ray). A pixel can cost twenty times its neighbour's (a pile of set
  // operations beside flat metal): a band still unfinished at the end of the budget stops there,
  // and is traced again later, its rays traced so far shaded at their kept hits.
  const auto budgetEnd = msAfter(t0, std::min(budgetMs, 1e9));
  while (!coarse_.empty()) {
    const double left = budgetMs - msSince(t0);
    if (left <= 0) break;
    PixelSpans& s = coarse_.front();
    const double speed = dirtySpeed();
    const double perPx = bandMsPerPx_ > 0 ? bandMsPerPx_ : speed > 0 ? 1.0 / speed : 0.0;
    // (in doubles first: flush()'s budget would overflow a long)
    const long px = perPx > 0 ? static_cast<long>(std::min(left / perPx, 1e12)) : 8L * s.box.w;
    auto [band, rest] = s.split(std::max(px, kMinBandPixels));
    bool stopped = false;
    const double ms = renderSpans(band, changed, true, budgetEnd, &stopped);
    if (stopped) {
      // Dearer than expected: the next band is sized from what this one did in its time.
      ++counters_.bandsStopped;
      bandMsPerPx_ = std::max(2.0 * perPx, bandMsPerPx_);
      break;
    }
    bandMsPerPx_ = ms / static_cast<double>(std::max(1L, band.area()));
    s = std::move(rest);
    if (s.empty()) coarse_.erase(coarse_.begin());
    if (coarse_.empty()) bandMsPerPx_ = 0;
  }
  while (nextBand_ < h_) {
    const double left = budgetMs - msSince(t0);
    if (left <= 0) break;
    // As many rows as fit in what is left of the budget, at their measured costs.
    // (A row costs more than when it was measured where the piece has grown since: when a tick
    // waits, the band is sized for three quarters of what is left.)
    const int rows = std::clamp(bandRows(mayWait ? 0.75 * left : left), 4, h_);
    const Rect band{0, nextBand_, w_, std::min(rows, h_ - nextBand_)};
    const double ms = renderRect(band, changed, false);
    const float perRow = static_cast<float>(ms / band.h);
    for (int y = band.y; y < band.y + band.h; ++y) rowMs_[static_cast<size_t>(y)] = perRow;
    maxRowMs_ = std::max(maxRowMs_, static_cast<double>(perRow));
    ++counters_.bands;
    nextBand_ += band.h;
    if (nextBand_ >= h_ && model_->activeCount() == 0 && blanks_.size() < 8) blanks_[blankKey()] = frame_;
  }
}

bool FrameComposer::flush(std::vector<Rect>& changed, double limitMs) {
  if (refineAfterMove_) {
    refineAfterMove_ = false;
    nextBand_ = 0;
  }
  const auto t0 = std::chrono::steady_clock::now();
  while (pending()) {
    const double left = std::min(limitMs - msSince(t0), 1e9);
    if (left <= 0) return false;
    work(left, changed);
  }
  return true;
}

}  // namespace emboss
