// Finding the sheet: candidate regions, their largest inscribed quadrilaterals, a score, and sub-pixel edges.
#include "capture/sheet.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <vector>

namespace emboss {

namespace {

using Quad = std::array<Vec2, 4>;

constexpr int kWorkSize = 800;           // candidates are searched on an image this large at most
constexpr double kMinAreaFrac = 0.03;    // a sheet covers at least this much of the photo
constexpr double kLogOffset = 16.0;      // log(g + offset): keeps the noise of dark pixels in bounds
constexpr double kStepMin = 0.15;        // log step across an edge that counts (about 16 % brighter)
constexpr double kMinFill = 0.85;        // region area / quadrilateral area
constexpr double kMaxOverflow = 0.10;    // region area outside the quadrilateral / region area
constexpr double kMinEdgeSupport = 0.7;  // of all the edge samples
constexpr double kMinSideSupport = 0.4;  // of each side's: a hand or a stroke may hide some of an edge

Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
double cross(Vec2 o, Vec2 a, Vec2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }
double norm(Vec2 a) { return std::hypot(a.x, a.y); }

double quadArea(const Quad& q) {
  double s = 0;
  for (int i = 0; i < 4; ++i) s += q[i].x * q[(i + 1) % 4].y - q[(i + 1) % 4].x * q[i].y;
  return std::fabs(s) / 2;
}

// Top-left, top-right, bottom-right, bottom-left (y down): by angle around the centre, starting at
// the corner nearest the top-left.
Quad orderCorners(Quad q) {
  Vec2 c{0, 0};
  for (const auto& p : q) c = c + 0.25 * p;
  std::sort(q.begin(), q.end(), [&](Vec2 a, Vec2 b) { return std::atan2(a.y - c.y, a.x - c.x) < std::atan2(b.y - c.y, b.x - c.x); });
  int first = 0;
  for (int i = 1; i < 4; ++i)
    if (q[i].x + q[i].y < q[first].x + q[first].y) first = i;
  std::rotate(q.begin(), q.begin() + first, q.end());
  return q;
}

bool convexAndSane(const Quad& q) {
  double sign = 0;
  for (int i = 0; i < 4; ++i) {
    const Vec2 a = q[(i + 3) % 4], b = q[i], c = q[(i + 1) % 4];
    const double z = cross(a, b, c);
    if (sign == 0) sign = z;
    if (z * sign <= 0) return false;
    const Vec2 u = a - b, v = c - b;
    const double cosAngle = dot(u, v) / (norm(u) * norm(v) + 1e-12);
    if (std::fabs(cosAngle) > 0.82) return false;  // interior angles 35..145 degrees
  }
  return true;
}

bool insideQuad(const Quad& q, Vec2 p) {
  int pos = 0, neg = 0;
  for (int i = 0; i < 4; ++i) {
    const double z = cross(q[i], q[(i + 1) % 4], p);
    pos += z > 0, neg += z < 0;
  }
  return pos == 0 || neg == 0;
}

std::optional<Vec2> intersect(Vec2 p1, Vec2 d1, Vec2 p2, Vec2 d2) {
  const double den = d1.x * d2.y - d1.y * d2.x;
  if (std::fabs(den) < 1e-12) return std::nullopt;
  const double t = ((p2.x - p1.x) * d2.y - (p2.y - p1.y) * d2.x) / den;
  return p1 + t * d1;
}

// A line through points (total least squares): a point on it and its unit direction.
struct Line {
  Vec2 p, d;
};
std::optional<Line> fitLine(const std::vector<Vec2>& pts, const std::vector<double>* weights = nullptr) {
  if (pts.size() < 2) return std::nullopt;
  double sw = 0, cx = 0, cy = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    const double w = weights ? (*weights)[i] : 1.0;
    sw += w, cx += w * pts[i].x, cy += w * pts[i].y;
  }
  if (sw <= 0) return std::nullopt;
  cx /= sw, cy /= sw;
  double sxx = 0, sxy = 0, syy = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    const double w = weights ? (*weights)[i] : 1.0;
    const double dx = pts[i].x - cx, dy = pts[i].y - cy;
    sxx += w * dx * dx, sxy += w * dx * dy, syy += w * dy * dy;
  }
  const double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);
  return Line{{cx, cy}, {std::cos(angle), std::sin(angle)}};
}

// Robust: fits, drops points further than max(minTol, 3 robust sigmas), fits again (twice).
std::optional<Line> fitLineRobust(std::vector<Vec2> pts, double minTol) {
  for (int round = 0; round < 3; ++round) {
    auto line = fitLine(pts);
    if (!line) return std::nullopt;
    if (round == 2) return line;
    std::vector<double> res;
    for (const auto& p : pts) res.push_back(std::fabs(cross(line->p, line->p + line->d, p)));
    std::vector<double> sorted = res;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double tol = std::max(minTol, 3.0 * 1.4826 * sorted[sorted.size() / 2]);
    std::vector<Vec2> kept;
    for (size_t i = 0; i < pts.size(); ++i)
      if (res[i] <= tol) kept.push_back(pts[i]);
    if (kept.size() < 4) return line;
    pts = std::move(kept);
  }
  return std::nullopt;
}

// Monotone chain; counter-clockwise in a y-up frame, collinear points dropped.
std::vector<Vec2> convexHull(std::vector<Vec2> pts) {
  std::sort(pts.begin(), pts.end(), [](Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  pts.erase(std::unique(pts.begin(), pts.end(), [](Vec2 a, Vec2 b) { return a.x == b.x && a.y == b.y; }), pts.end());
  if (pts.size() < 3) return pts;
  std::vector<Vec2> h(2 * pts.size());
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], pts[i]) <= 0) --k;
    h[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], pts[i - 1]) <= 0) --k;
    h[k++] = pts[i - 1];
  }
  h.resize(k - 1);
  return h;
}

// The largest quadrilateral with its corners among the hull's vertices (rotating pointers, O(n^2)).
std::optional<Quad> maxAreaQuad(const std::vector<Vec2>& hull) {
  const int n = static_cast<int>(hull.size());
  if (n < 4) return std::nullopt;
  auto at = [&](int i) { return hull[((i % n) + n) % n]; };
  auto tri = [&](int a, int b, int c) { return std::fabs(cross(at(a), at(b), at(c))); };
  double best = -1;
  Quad q{};
  for (int i = 0; i < n; ++i) {
    int j = i + 1, l = i + 3;
    for (int k = i + 2; k <= i + n - 2; ++k) {
      if (j >= k) j = k - 1;
      while (j + 1 < k && tri(i, j + 1, k) >= tri(i, j, k)) ++j;
      if (l <= k) l = k + 1;
      while (l + 1 < i + n && tri(i, k, l + 1) >= tri(i, k, l)) ++l;
      const double area = tri(i, j, k) + tri(i, k, l);
      if (area > best) best = area, q = {at(i), at(j), at(k), at(l)};
    }
  }
  return q;
}

// One candidate region's outline: where each row and column of it starts and ends (pixel edges).
struct Outline {
  std::vector<Vec2> points;
  int area = 0;
};

struct Candidate {
  Quad quad{};
  double score = 0;
  double support = 0;
  double contrast = 0;
};

class Finder {
 public:
  explicit Finder(const GrayImage& photo) : photo_(photo) {
    factor_ = std::max(1, (std::max(photo.width, photo.height) + kWorkSize - 1) / kWorkSize);
    work_ = gaussianBlur(downscale(photo, factor_), 1.0);
    logWork_ = work_;
    for (float& v : logWork_.v) v = static_cast<float>(std::log(v + kLogOffset));
  }

  Result<Sheet> find();

 private:
  void addThresholdCandidates();
  void addEdgeCandidates();
  void tryRegions(const Mask& mask);
  void tryRegion(const Components& comps, int id, const Mask& mask);
  std::optional<Quad> refineOnOutline(Quad q, const std::vector<Vec2>& outline) const;
  // Support and median step of a quadrilateral's sides in a log image, steps `delta` either side.
  // minSide: the support of the weakest side (a threshold that slices through a lit sheet makes a
  // side with no edge behind it).
  void edgeStats(const Quad& q, const GrayImage& logImg, double delta, double* support, double* contrast, double* minSide) const;
  // Each side moved to the steepest bright-to-dark fall within `radius` along its normal (robust line
  // fits of 64 samples); nullopt when a side shows too little edge.
  std::optional<Quad> refineEdges(const Quad& q, double radius, const GrayImage& logImg) const;

  const GrayImage& photo_;
  int factor_ = 1;
  GrayImage work_, logWork_;
  std::vector<Candidate> candidates_;
};

void Finder::addThresholdCandidates() {
  std::vector<double> hist(256, 0.0);
  for (float v : work_.v) hist[std::clamp(static_cast<int>(v), 0, 255)] += 1;
  const double total = static_cast<double>(work_.v.size());
  // Otsu: the threshold that maximises the between-class variance.
  double sumAll = 0;
  for (int i = 0; i < 256; ++i) sumAll += i * hist[i];
  double wB = 0, sumB = 0, bestVar = -1;
  int otsu = 128;
  for (int t = 0; t < 256; ++t) {
    wB += hist[t];
    if (wB == 0 || wB == total) continue;
    sumB += t * hist[t];
    const double mB = sumB / wB, mF = (sumAll - sumB) / (total - wB);
    const double var = wB * (total - wB) * (mB - mF) * (mB - mF);
    if (var > bestVar) bestVar = var, otsu = t;
  }
  auto percentile = [&](double p) {
    double acc = 0;
    for (int i = 0; i < 256; ++i)
      if ((acc += hist[i]) >= p * total) return i;
    return 255;
  };
  const double lo = percentile(0.02), hi = percentile(0.98);
  std::vector<double> levels{otsu + 0.5};
  for (double f : {0.3, 0.45, 0.6, 0.75}) levels.push_back(lo + f * (hi - lo));
  for (double t : levels) {
    Mask m(work_.width, work_.height);
    for (size_t i = 0; i < m.v.size(); ++i) m.v[i] = work_.v[i] > t;
    tryRegions(m);
  }
}

void Finder::addEdgeCandidates() {
  const int w = logWork_.width, h = logWork_.height;
  GrayImage mag(w, h);
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      auto L = [&](int dx, int dy) { return logWork_.at(x + dx, y + dy); };
      const float gx = (L(1, -1) + 2 * L(1, 0) + L(1, 1) - L(-1, -1) - 2 * L(-1, 0) - L(-1, 1)) / 8;
      const float gy = (L(-1, 1) + 2 * L(0, 1) + L(1, 1) - L(-1, -1) - 2 * L(0, -1) - L(1, -1)) / 8;
      mag.at(x, y) = std::hypot(gx, gy);
    }
  std::vector<float> sorted = mag.v;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double high = std::max(0.06, 5.0 * sorted[sorted.size() / 2]), low = 0.5 * high;
  // Hysteresis: strong edge pixels, grown through weak ones.
  Mask edges(w, h);
  std::vector<int> stack;
  for (int i = 0; i < w * h; ++i)
    if (mag.v[i] >= high) edges.v[i] = 1, stack.push_back(i);
  while (!stack.empty()) {
    const int p = stack.back();
    stack.pop_back();
    const int x = p % w, y = p / w;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
        const int q = ny * w + nx;
        if (!edges.v[q] && mag.v[q] >= low) edges.v[q] = 1, stack.push_back(q);
      }
  }
  // Close one-pixel gaps, then everything the border cannot reach without crossing an edge is enclosed.
  Mask thick(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (edges.at(x, y))
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            if (x + dx >= 0 && y + dy >= 0 && x + dx < w && y + dy < h) thick.at(x + dx, y + dy) = 1;
  tryRegions(fillHoles(thick));
}

void Finder::tryRegions(const Mask& mask) {
  const Components comps = connectedComponents(mask);
  std::vector<int> ids(comps.area.size() - 1);
  std::iota(ids.begin(), ids.end(), 1);
  std::sort(ids.begin(), ids.end(), [&](int a, int b) { return comps.area[a] > comps.area[b]; });
  const double minArea = kMinAreaFrac * mask.width * mask.height;
  for (size_t k = 0; k < ids.size() && k < 3; ++k) {
    if (comps.area[ids[k]] < minArea) break;
    tryRegion(comps, ids[k], mask);
  }
}

void Finder::tryRegion(const Components& comps, int id, const Mask& mask) {
  const int w = mask.width, h = mask.height;
  Mask region(w, h);
  for (size_t i = 0; i < region.v.size(); ++i) region.v[i] = comps.label[i] == id;
  region = fillHoles(region);
  // Row and column extremes, as pixel edges: the hull of these is the hull of the region.
  std::vector<Vec2> outline, corners;
  for (int y = 0; y < h; ++y) {
    int x0 = -1, x1 = -1;
    for (int x = 0; x < w; ++x)
      if (region.at(x, y)) x1 = x, x0 = x0 < 0 ? x : x0;
    if (x0 < 0) continue;
    outline.push_back({double(x0), y + 0.5}), outline.push_back({x1 + 1.0, y + 0.5});
    for (double yy : {double(y), y + 1.0}) corners.push_back({double(x0), yy}), corners.push_back({x1 + 1.0, yy});
  }
  for (int x = 0; x < w; ++x) {
    int y0 = -1, y1 = -1;
    for (int y = 0; y < h; ++y)
      if (region.at(x, y)) y1 = y, y0 = y0 < 0 ? y : y0;
    if (y0 < 0) continue;
    outline.push_back({x + 0.5, double(y0)}), outline.push_back({x + 0.5, y1 + 1.0});
  }
  auto quad = maxAreaQuad(convexHull(corners));
  if (!quad) return;
  Quad q = orderCorners(*quad);
  for (int round = 0; round < 2; ++round)
    if (auto r = refineOnOutline(q, outline)) q = *r;
  // Snap to the edges themselves: a region's outline may sit off them (thresholds, edge bands).
  if (convexAndSane(q))
    if (auto r = refineEdges(q, 8.0, logWork_)) q = *r;
  if (!convexAndSane(q)) return;
  // All four corners in view, clear of the border.
  for (const auto& p : q)
    if (p.x < 1 || p.y < 1 || p.x > w - 1 || p.y > h - 1) return;
  const double area = quadArea(q);
  if (area < kMinAreaFrac * w * h) return;
  size_t inside = 0, total = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (region.at(x, y)) ++total, inside += insideQuad(q, {x + 0.5, y + 0.5});
  const double fill = inside / area, overflow = total ? 1.0 - double(inside) / total : 1.0;
  if (fill < kMinFill || overflow > kMaxOverflow) return;
  double support = 0, contrast = 0, minSide = 0;
  edgeStats(q, logWork_, 2.5, &support, &contrast, &minSide);
  if (support < kMinEdgeSupport || minSide < kMinSideSupport) return;
  candidates_.push_back({q, area * std::min(fill, 1.0) * (1.0 - overflow) * support, support, contrast});
}

std::optional<Quad> Finder::refineOnOutline(Quad q, const std::vector<Vec2>& outline) const {
  std::array<Line, 4> lines;
  for (int s = 0; s < 4; ++s) {
    const Vec2 a = q[s], b = q[(s + 1) % 4];
    const double len = norm(b - a);
    if (len < 4) return std::nullopt;
    const Vec2 d = (1.0 / len) * (b - a), n{-d.y, d.x};
    const double tol = std::max(2.0, 0.04 * len);
    std::vector<Vec2> pts;
    for (const auto& p : outline) {
      const double t = dot(p - a, d), off = std::fabs(dot(p - a, n));
      if (t > 0.1 * len && t < 0.9 * len && off <= tol) pts.push_back(p);
    }
    auto line = fitLineRobust(pts, 1.0);
    if (!line || pts.size() < 6) lines[s] = {a, d};
    else lines[s] = *line;
  }
  Quad out;
  for (int s = 0; s < 4; ++s) {
    auto p = intersect(lines[(s + 3) % 4].p, lines[(s + 3) % 4].d, lines[s].p, lines[s].d);
    if (!p) return std::nullopt;
    out[s] = *p;
  }
  return out;
}

void Finder::edgeStats(const Quad& q, const GrayImage& logImg, double delta, double* support, double* contrast, double* minSide) const {
  Vec2 c{0, 0};
  for (const auto& p : q) c = c + 0.25 * p;
  std::vector<double> steps;
  int good = 0;
  *minSide = 1.0;
  constexpr int kSamples = 32;
  for (int s = 0; s < 4; ++s) {
    const int before = good;
    const Vec2 a = q[s], b = q[(s + 1) % 4];
    const Vec2 d = (1.0 / (norm(b - a) + 1e-12)) * (b - a);
    Vec2 n{-d.y, d.x};
    if (dot(n, c - a) < 0) n = -1.0 * n;  // n points inward
    for (int i = 0; i < kSamples; ++i) {
      const Vec2 p = a + ((0.1 + 0.8 * (i + 0.5) / kSamples) * (b - a));
      // The largest step within +-2 delta of the side: a region's outline may sit a little off the edge.
      double step = -1e9;
      for (double o = -2 * delta; o <= 2 * delta + 1e-9; o += 0.5 * delta) {
        const Vec2 in = p + (o + delta) * n, out = p + (o - delta) * n;
        step = std::max(step, double(logImg.sample(in.x, in.y) - logImg.sample(out.x, out.y)));
      }
      steps.push_back(step);
      good += step >= kStepMin;
    }
    *minSide = std::min(*minSide, double(good - before) / kSamples);
  }
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  *support = double(good) / steps.size();
  *contrast = steps[steps.size() / 2];
}

std::optional<Quad> Finder::refineEdges(const Quad& q, double radius, const GrayImage& logImg) const {
  Vec2 c{0, 0};
  for (const auto& p : q) c = c + 0.25 * p;
  std::array<Line, 4> lines;
  constexpr int kSamples = 64;
  constexpr double kStep = 0.5;
  for (int s = 0; s < 4; ++s) {
    const Vec2 a = q[s], b = q[(s + 1) % 4];
    const Vec2 d = (1.0 / (norm(b - a) + 1e-12)) * (b - a);
    Vec2 n{-d.y, d.x};
    if (dot(n, c - a) > 0) n = -1.0 * n;  // n points outward
    std::vector<Vec2> pts;
    const int m = static_cast<int>(std::ceil(radius / kStep));
    std::vector<double> prof(2 * m + 3);
    for (int i = 0; i < kSamples; ++i) {
      const Vec2 p = a + ((0.08 + 0.84 * (i + 0.5) / kSamples) * (b - a));
      for (int k = 0; k < static_cast<int>(prof.size()); ++k) {
        const Vec2 x = p + ((k - m - 1) * kStep) * n;
        prof[k] = logImg.sample(x.x, x.y);
      }
      // The steepest fall going outward (bright sheet to darker surroundings).
      int bestK = -1;
      double best = 0;
      for (int k = 1; k + 1 < static_cast<int>(prof.size()); ++k) {
        const double fall = prof[k - 1] - prof[k + 1];
        if (fall > best) best = fall, bestK = k;
      }
      if (bestK < 2 || bestK > static_cast<int>(prof.size()) - 3 || best < 0.5 * kStepMin) continue;
      const double f0 = prof[bestK - 2] - prof[bestK], f1 = best, f2 = prof[bestK] - prof[bestK + 2];
      const double den = f0 - 2 * f1 + f2;
      const double off = std::fabs(den) > 1e-12 ? std::clamp(0.5 * (f0 - f2) / den, -0.5, 0.5) : 0.0;
      pts.push_back(p + ((bestK - m - 1 + off) * kStep) * n);
    }
    if (pts.size() < kSamples / 4) return std::nullopt;
    auto line = fitLineRobust(pts, 0.75);
    if (!line) return std::nullopt;
    lines[s] = *line;
  }
  Quad out;
  for (int s = 0; s < 4; ++s) {
    auto p = intersect(lines[(s + 3) % 4].p, lines[(s + 3) % 4].d, lines[s].p, lines[s].d);
    if (!p || norm(*p - q[s]) > 3 * radius + 2) return std::nullopt;
    out[s] = *p;
  }
  return out;
}

Result<Sheet> Finder::find() {
  addThresholdCandidates();
  addEdgeCandidates();
  if (candidates_.empty())
    return fail("no sheet of paper found: lay a white sheet flat under the camera, all four corners in view, on a darker surface");
  const Candidate best = *std::max_element(candidates_.begin(), candidates_.end(), [](const Candidate& a, const Candidate& b) { return a.score < b.score; });

  // To full resolution: the work image's pixel edges scale by the factor.
  Quad q;
  for (int i = 0; i < 4; ++i) q[i] = double(factor_) * best.quad[i];
  GrayImage logFull = gaussianBlur(photo_, 0.7);
  for (float& v : logFull.v) v = static_cast<float>(std::log(v + kLogOffset));
  if (auto r = refineEdges(q, 2.0 * factor_ + 3.0, logFull)) q = *r;
  if (auto r = refineEdges(q, 2.5, logFull)) q = *r;
  q = orderCorners(q);
  Sheet sheet;
  sheet.corners = q;
  double minSide = 0;
  edgeStats(q, logFull, 2.0 * factor_, &sheet.edgeSupport, &sheet.contrast, &minSide);
  return sheet;
}

}  // namespace

Result<Sheet> findSheet(const GrayImage& photo) {
  if (photo.width < 32 || photo.height < 32) return fail("no sheet of paper found: the photo is only " + std::to_string(photo.width) + "x" + std::to_string(photo.height) + " pixels");
  Finder finder(photo);
  return finder.find();
}

Result<Sheet> findSheet(const Image& photo) { return findSheet(toGray(photo)); }

}  // namespace emboss
