// The exact ray tracer.
#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace emboss {

namespace {

constexpr int kSpanSteps = 8;
constexpr int kBisections = 40;
constexpr int kThinSplits = 3;

struct Segment {
  glm::dvec3 a, b;
};

P3<Interval> boxOf(const glm::dvec3& a, const glm::dvec3& b) {
  return {Interval(std::min(a.x, b.x), std::max(a.x, b.x)), Interval(std::min(a.y, b.y), std::max(a.y, b.y)),
          Interval(std::min(a.z, b.z), std::max(a.z, b.z))};
}

}  // namespace

void Renderer::sync(const Model& model) {
  model_ = &model;
  grid_.sync(model);
  bounds_ = model.bounds();
  // The step: a quarter of the sheet's thickness, at most 0.25 mm: a sheet can never slip between
  // two samples, and the thin-feature splits go down to h / 8.
  step_ = std::min(0.25, 0.5 * model.workpiece().halfThickness());
  all_.resize(model.activeCount());
  std::iota(all_.begin(), all_.end(), 0u);
}

std::optional<glm::dvec3> Renderer::traceColor(int px, int py, RenderStats& st, std::vector<std::uint32_t>& scratch) const {
  const Ray ray = camera_->ray(px, py);
  ++st.rays;
  // Clip to the model's bounds.
  double t0 = 0.0, t1 = 1e30;
  const double lo[3] = {bounds_.x0, bounds_.y0, bounds_.z0}, hi[3] = {bounds_.x1, bounds_.y1, bounds_.z1};
  for (int k = 0; k < 3; ++k) {
    const double o = ray.origin[k], d = ray.dir[k];
    if (std::abs(d) < 1e-15) {
      if (o < lo[k] || o > hi[k]) return std::nullopt;
      continue;
    }
    double ta = (lo[k] - o) / d, tb = (hi[k] - o) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta), t1 = std::min(t1, tb);
  }
  if (!(t0 < t1)) return std::nullopt;

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

  // Finds a root in [ta, tb] given f(ta) < 0; depth limits the thin-feature splits.
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
  return shadeMetal(shading_, p, n, ray.dir);
}

bool Renderer::render(Image& image, const Rect& rectIn, RenderStats* stats, const std::atomic_bool* cancel) {
  const int w = camera_->width(), h = camera_->height();
  if (image.width != w || image.height != h) image = Image(w, h);
  Rect rect{std::max(0, rectIn.x), std::max(0, rectIn.y), 0, 0};
  rect.w = std::min(w, rectIn.x + rectIn.w) - rect.x;
  rect.h = std::min(h, rectIn.y + rectIn.h) - rect.y;
  if (rect.empty()) return true;
  std::mutex statsMutex;
  const bool done = pool_.parallelFor2D(rect, options_.tileSize, [&](const Rect& tile) {
    RenderStats st;
    std::vector<std::uint32_t> scratch;
    for (int y = tile.y; y < tile.y + tile.h; ++y)
      for (int x = tile.x; x < tile.x + tile.w; ++x) {
        const auto c = traceColor(x, y, st, scratch);
        const auto rgb = toSrgb8(c ? *c : backdrop(x, y, w, h));
        std::uint8_t* px = image.pixel(x, y);
        px[0] = rgb[0], px[1] = rgb[1], px[2] = rgb[2], px[3] = 255;
      }
    if (stats) {
      std::lock_guard lock(statsMutex);
      *stats += st;
    }
  }, cancel);
  return done;
}

bool Renderer::renderFull(Image& image, RenderStats* stats, const std::atomic_bool* cancel) {
  return render(image, Rect{0, 0, camera_->width(), camera_->height()}, stats, cancel);
}

Rect Renderer::dirtyRect(const Model& model, size_t index) const {
  const Box2 s = model.operations()[index].support();
  const Box3 b = model.bounds();
  const double zs[2] = {b.z0, b.z1};
  double x0 = 1e30, y0 = 1e30, x1 = -1e30, y1 = -1e30;
  // Grow the box by a span of the root finder (its interval boxes reach that far from the ray).
  const double g = kSpanSteps * step_;
  for (double x : {s.x0 - g, s.x1 + g})
    for (double y : {s.y0 - g, s.y1 + g})
      for (double z : zs) {
        const auto q = camera_->project({x, y, z + (z > 0 ? g : -g)});
        if (!q) return {0, 0, camera_->width(), camera_->height()};
        x0 = std::min(x0, q->x), y0 = std::min(y0, q->y), x1 = std::max(x1, q->x), y1 = std::max(y1, q->y);
      }
  Rect r{static_cast<int>(std::floor(x0)) - 2, static_cast<int>(std::floor(y0)) - 2, 0, 0};
  r.w = static_cast<int>(std::ceil(x1)) + 2 - r.x;
  r.h = static_cast<int>(std::ceil(y1)) + 2 - r.y;
  const int w = camera_->width(), h = camera_->height();
  const int cx0 = std::clamp(r.x, 0, w), cy0 = std::clamp(r.y, 0, h);
  const int cx1 = std::clamp(r.x + r.w, 0, w), cy1 = std::clamp(r.y + r.h, 0, h);
  return {cx0, cy0, cx1 - cx0, cy1 - cy0};
}

}  // namespace emboss
