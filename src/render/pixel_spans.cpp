// Pixel spans and the spans of convex outlines (pixel_spans.h).
#include "render/pixel_spans.h"

#include <algorithm>
#include <cmath>

#include "frep/convex_hull.h"

namespace emboss {

PixelSpans PixelSpans::of(const Rect& r) {
  PixelSpans s;
  if (r.empty()) return s;
  s.box = r;
  s.rows.assign(static_cast<size_t>(r.h), Span{r.x, r.x + r.w});
  return s;
}

long PixelSpans::area() const {
  long n = 0;
  for (const Span& s : rows) n += s.empty() ? 0 : s.x1 - s.x0;
  return n;
}

PixelSpans::Span PixelSpans::row(int y) const {
  if (y < box.y || y >= box.y + box.h) return {};
  return rows[static_cast<size_t>(y - box.y)];
}

bool PixelSpans::contains(int x, int y) const {
  const Span s = row(y);
  return x >= s.x0 && x < s.x1;
}

namespace {

// The spans between y0 and y1 (exclusive) as a PixelSpans: empty rows at both ends trimmed, the
// box the hull of the rest.
PixelSpans trimmed(int y0, std::vector<PixelSpans::Span> rows) {
  PixelSpans out;
  size_t a = 0, b = rows.size();
  while (a < b && rows[a].empty()) ++a;
  while (b > a && rows[b - 1].empty()) --b;
  if (a == b) return out;
  int x0 = rows[a].x0, x1 = rows[a].x1;
  for (size_t i = a; i < b; ++i)
    if (!rows[i].empty()) x0 = std::min(x0, rows[i].x0), x1 = std::max(x1, rows[i].x1);
  out.box = {x0, y0 + static_cast<int>(a), x1 - x0, static_cast<int>(b - a)};
  out.rows.assign(rows.begin() + static_cast<std::ptrdiff_t>(a), rows.begin() + static_cast<std::ptrdiff_t>(b));
  return out;
}

// a and b together (an empty span is no span).
PixelSpans::Span hull(PixelSpans::Span a, PixelSpans::Span b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  return {std::min(a.x0, b.x0), std::max(a.x1, b.x1)};
}

}  // namespace

PixelSpans PixelSpans::grown(int n, int w, int h) const {
  if (empty()) return {};
  const int y0 = std::max(0, box.y - n), y1 = std::min(h, box.y + box.h + n);
  if (y1 <= y0) return {};
  std::vector<Span> out(static_cast<size_t>(y1 - y0));
  for (int y = y0; y < y1; ++y) {
    Span s;
    for (int k = std::max(y - n, box.y); k <= std::min(y + n, box.y + box.h - 1); ++k) s = hull(s, row(k));
    if (!s.empty()) s = {std::max(0, s.x0 - n), std::min(w, s.x1 + n)};
    out[static_cast<size_t>(y - y0)] = s;
  }
  return trimmed(y0, std::move(out));
}

PixelSpans PixelSpans::united(const PixelSpans& o) const {
  if (empty()) return o;
  if (o.empty()) return *this;
  const int y0 = std::min(box.y, o.box.y), y1 = std::max(box.y + box.h, o.box.y + o.box.h);
  std::vector<Span> out(static_cast<size_t>(y1 - y0));
  for (int y = y0; y < y1; ++y) out[static_cast<size_t>(y - y0)] = hull(row(y), o.row(y));
  return trimmed(y0, std::move(out));
}

PixelSpans PixelSpans::band(int y0, int y1) const {
  y0 = std::max(y0, box.y), y1 = std::min(y1, box.y + box.h);
  if (empty() || y1 <= y0) return {};
  return trimmed(y0, std::vector<Span>(rows.begin() + (y0 - box.y), rows.begin() + (y1 - box.y)));
}

std::pair<PixelSpans, PixelSpans> PixelSpans::split(long n) const {
  if (n <= 0) return {PixelSpans{}, *this};
  std::vector<Span> head(rows.size()), rest(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    const Span s = rows[i];
    if (s.empty()) continue;
    const long take = std::clamp(n, 0L, static_cast<long>(s.x1 - s.x0));
    n -= take;
    if (take > 0) head[i] = {s.x0, s.x0 + static_cast<int>(take)};
    if (s.x0 + take < s.x1) rest[i] = {s.x0 + static_cast<int>(take), s.x1};
  }
  return {trimmed(box.y, std::move(head)), trimmed(box.y, std::move(rest))};
}

void SpanBuilder::addHullOf(std::span<const glm::dvec2> points) {
  if (points.empty()) return;
  // The convex hull (Andrew's monotone chain, frep/convex_hull.h), counter-clockwise in y-down
  // image coordinates.
  std::vector<glm::dvec2> hullPts = convexHull(std::vector<glm::dvec2>(points.begin(), points.end()));
  const size_t n = hullPts.size();

  // Pixel row y is kept where the band [y - 1, y + 2] of image y (the row and a pixel each way)
  // meets the hull; its span runs from a pixel before the band's leftmost point of the hull to a
  // pixel after its rightmost (a rectangle of projected corners keeps the same margin).
  double ylo = hullPts[0].y, yhi = hullPts[0].y;
  for (const auto& q : hullPts) ylo = std::min(ylo, q.y), yhi = std::max(yhi, q.y);
  const double lim = 1e6;
  const int r0 = std::clamp(static_cast<int>(std::floor(std::max(ylo, -lim))) - 2, 0, h_);
  const int r1 = std::clamp(static_cast<int>(std::ceil(std::min(yhi, lim))) + 2, 0, h_);
  if (r1 <= r0) return;
  if (rows_.empty()) {
    y0_ = r0, y1_ = r0;
  }
  // Widen the row store to [min(y0_, r0), max(y1_, r1)).
  if (r0 < y0_) {
    rows_.insert(rows_.begin(), static_cast<size_t>(y0_ - r0), PixelSpans::Span{});
    y0_ = r0;
  }
  if (r1 > y1_) {
    rows_.resize(rows_.size() + static_cast<size_t>(r1 - y1_));
    y1_ = r1;
  }
  for (int y = r0; y < r1; ++y) {
    const double ba = y - 1.0, bb = y + 2.0;
    double xa = 1e300, xb = -1e300;
    for (size_t i = 0; i < n; ++i) {
      glm::dvec2 a = hullPts[i], b = hullPts[(i + 1) % n];
      if ((a.y < ba && b.y < ba) || (a.y > bb && b.y > bb)) continue;
      // The edge clipped to the band: its ends' x there.
      auto at = [&](double yy) { return a.x + (b.x - a.x) * (yy - a.y) / (b.y - a.y); };
      for (const glm::dvec2& e : {a, b}) {
        double x = e.x;
        if (e.y < ba) x = at(ba);
        else if (e.y > bb) x = at(bb);
        xa = std::min(xa, x), xb = std::max(xb, x);
      }
    }
    if (xa > xb) continue;
    const int x0 = std::clamp(static_cast<int>(std::floor(std::max(xa, -lim))) - 1, 0, w_);
    const int x1 = std::clamp(static_cast<int>(std::ceil(std::min(xb, lim))) + 1, 0, w_);
    if (x1 <= x0) continue;
    PixelSpans::Span& s = rows_[static_cast<size_t>(y - y0_)];
    s = s.empty() ? PixelSpans::Span{x0, x1} : PixelSpans::Span{std::min(s.x0, x0), std::max(s.x1, x1)};
  }
}

PixelSpans SpanBuilder::take() const {
  if (rows_.empty()) return {};
  return trimmed(y0_, rows_);
}

}  // namespace emboss
