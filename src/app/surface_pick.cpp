// Ray picking on the F-rep model and the mapping of the tablet onto the visible sheet.
#include "app/surface_pick.h"

#include "frep/interval.h"

#include <algorithm>
#include <vector>
#include <cmath>
#include <limits>

namespace emboss {

namespace {

// The part [t0, t1] of the ray inside box b, if any.
bool clipToBox(const Ray& r, const Box3& b, double& t0, double& t1) {
  t0 = 0, t1 = std::numeric_limits<double>::infinity();
  const double o[3] = {r.origin.x, r.origin.y, r.origin.z}, d[3] = {r.dir.x, r.dir.y, r.dir.z};
  const double lo[3] = {b.x0, b.y0, b.z0}, hi[3] = {b.x1, b.y1, b.z1};
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < 1e-15) {
      if (o[i] < lo[i] || o[i] > hi[i]) return false;
      continue;
    }
    double a = (lo[i] - o[i]) / d[i], c = (hi[i] - o[i]) / d[i];
    if (a > c) std::swap(a, c);
    t0 = std::max(t0, a), t1 = std::min(t1, c);
  }
  return t0 <= t1;
}

}  // namespace

std::optional<glm::dvec3> pickSurface(const Model& model, const Camera& camera, double sx, double sy, bool skipOutside) {
  const Ray ray = camera.rayAt(sx, sy);
  Box3 b = model.bounds();
  b.x0 -= 1, b.y0 -= 1, b.z0 -= 1, b.x1 += 1, b.y1 += 1, b.z1 += 1;
  double t0, t1;
  if (!clipToBox(ray, b, t0, t1)) return std::nullopt;
  const glm::dvec3 a = ray.origin + ray.dir * t0, e = ray.origin + ray.dir * t1;
  const Box2 foot{std::min(a.x, e.x), std::min(a.y, e.y), std::max(a.x, e.x), std::max(a.y, e.y)};
  std::vector<std::uint32_t> candidates;
  const auto& ops = model.operations();
  for (size_t i = 0; i < model.activeCount(); ++i)
    if (ops[i].support().overlaps(foot)) candidates.push_back(static_cast<std::uint32_t>(i));
  // Each evaluation reads only the candidates whose support holds its point (or meets its box):
  // outside its support an operation changes nothing, and an oblique ray's footprint crosses the
  // supports of most of a busy sheet's operations.
  std::vector<std::uint32_t> near;
  auto nearTo = [&](const Box2& where) {
    near.clear();
    for (std::uint32_t i : candidates)
      if (ops[i].support().overlaps(where)) near.push_back(i);
    return std::span<const std::uint32_t>(near);
  };
  auto f = [&](double t) {
    const glm::dvec3 p = ray.origin + ray.dir * t;
    return model.evaluate(P3<double>{p.x, p.y, p.z}, nearTo(Box2{p.x, p.y, p.x, p.y}));
  };
  // Samples a step well under the sheet's thickness apart, so a ray cannot step over the sheet;
  // the first one inside is bracketed with the one before it and bisected.
  const double h = std::clamp(0.35 * model.workpiece().halfThickness(), 0.02, 0.25);
  if (f(t0) >= 0) return ray.origin + ray.dir * t0;
  std::vector<double> ts{t0};
  for (double t = t0 + h;; t += h) {
    ts.push_back(std::min(t, t1));
    if (ts.back() >= t1) break;
  }
  // Most of the ray is far above or below the sheet: a stretch of samples whose segment of the ray
  // interval arithmetic proves to be outside is skipped (the same first sample inside is found,
  // with a few interval evaluations instead of a point evaluation a sample).
  auto firstInside = [&](auto&& self, size_t a, size_t b) -> size_t {
    if (b - a < 4 || !skipOutside) {
      for (size_t k = a; k <= b; ++k)
        if (f(ts[k]) >= 0) return k;
      return 0;
    }
    const glm::dvec3 p = ray.origin + ray.dir * ts[a], q = ray.origin + ray.dir * ts[b];
    const P3<Interval> box{Interval(std::min(p.x, q.x), std::max(p.x, q.x)), Interval(std::min(p.y, q.y), std::max(p.y, q.y)),
                           Interval(std::min(p.z, q.z), std::max(p.z, q.z))};
    if (model.evaluate(box, nearTo(Box2{box.x.lo, box.y.lo, box.x.hi, box.y.hi})).hi < 0) return 0;
    const size_t m = a + (b - a) / 2;
    const size_t k = self(self, a, m);
    return k ? k : self(self, m + 1, b);
  };
  const size_t k = firstInside(firstInside, 1, ts.size() - 1);
  if (!k) return std::nullopt;
  double lo = ts[k - 1], hi = ts[k];
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (f(mid) >= 0) hi = mid; else lo = mid;
  }
  return ray.origin + ray.dir * hi;
}

double projectedRadius(const Camera& camera, const glm::dvec3& p, double radiusMm) {
  const auto c = camera.project(p);
  if (!c) return 0.0;
  double r = 0.0;
  for (const glm::dvec3 d : {glm::dvec3(radiusMm, 0, 0), glm::dvec3(0, radiusMm, 0)}) {
    const auto q = camera.project(p + d);
    if (q) r = std::max(r, glm::length(*q - *c));
  }
  return r;
}

ScreenBox sheetOnScreen(const Camera& camera, const Box3& wb) {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (double x : {wb.x0, wb.x1})
    for (double y : {wb.y0, wb.y1}) {
      const auto q = camera.project({x, y, wb.z1});
      if (!q) continue;
      x0 = std::min(x0, q->x), y0 = std::min(y0, q->y), x1 = std::max(x1, q->x), y1 = std::max(y1, q->y);
    }
  if (x0 > x1) return {0, 0, static_cast<double>(camera.width()), static_cast<double>(camera.height())};
  return {x0, y0, x1 - x0, y1 - y0};
}

ScreenBox tabletArea(const ScreenBox& s, double aspect, double margin) {
  double w = s.w * (1 + 2 * margin), h = s.h * (1 + 2 * margin);
  if (aspect <= 0) aspect = 1.6;
  if (w / h < aspect) w = h * aspect; else h = w / aspect;
  return {s.x + 0.5 * s.w - 0.5 * w, s.y + 0.5 * s.h - 0.5 * h, w, h};
}

}  // namespace emboss
