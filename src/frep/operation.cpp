// The operations' kernels, supports and parameter checks (equations (2), (3), (4) of the paper).
#include "frep/operation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <type_traits>
#include <utility>

#include "frep/convex_hull.h"
#include "frep/kernels.h"

namespace emboss {

namespace {

using kernels::kExactSpan;
using kernels::kSupportSpan;

// The slope of a^3/(t^2+a^2) is at most 9/(8 sqrt 3) (at t = a/sqrt 3), and the taper adds at most
// peak/10 * 1.875 / L (the kernel is at most a tenth of its peak beyond 3 L, |w'| <= 1.875 / L).
constexpr double kAgnesiMaxSlope = 0.649519052838329;
constexpr double kTaperSlopeFactor = 0.1875;


template <class T>
T segmentDistance2In3D(const P3<T>& p, const Vec3& a, const Vec3& b) {
  const double ex = b.x - a.x, ey = b.y - a.y, ez = b.z - a.z;
  const double len2 = ex * ex + ey * ey + ez * ez;
  const T px = p.x - a.x, py = p.y - a.y, pz = p.z - a.z;
  if (len2 <= 0.0) return sqr(px) + sqr(py) + sqr(pz);
  T t = (px * ex + py * ey + pz * ez) * (1.0 / len2);
  t = min(max(t, T(0.0)), T(1.0));
  return sqr(px - t * ex) + sqr(py - t * ey) + sqr(pz - t * ez);
}

// Squared distance from (x, y) to a polyline (closed: the last point joins the first).
template <class T>
T polylineDistance2(const T& x, const T& y, const std::vector<Vec2>& pts, bool closed) {
  if (pts.size() == 1) return sqr(x - pts[0].x) + sqr(y - pts[0].y);
  T best = kernels::segmentDistance2(x, y, pts[0].x, pts[0].y, pts[1].x, pts[1].y);
  for (size_t i = 2; i < pts.size(); ++i)
    best = min(best, kernels::segmentDistance2(x, y, pts[i - 1].x, pts[i - 1].y, pts[i].x, pts[i].y));
  if (closed && pts.size() > 2)
    best = min(best, kernels::segmentDistance2(x, y, pts.back().x, pts.back().y, pts[0].x, pts[0].y));
  return best;
}

// k(t2) * taper(sqrt(t2) / L), with the exact zero beyond the support and no taper work inside 3 L.
template <class T, class K>
T tapered(const T& t2, double L, K kernel) {
  if constexpr (std::is_same_v<T, Interval>) {
    const double lim = kSupportSpan * L;
    if (t2.lo >= lim * lim) return Interval(0.0);
    const Interval k = kernel(t2);
    const double ex = kExactSpan * L;
    if (t2.hi <= ex * ex) return k;
    return k * kernels::taper(sqrt(t2) * (1.0 / L));
  } else {
    const double v = valueOf(t2);
    const double lim = kSupportSpan * L;
    if (v >= lim * lim) return T(0.0);
    const T k = kernel(t2);
    const double ex = kExactSpan * L;
    if (v <= ex * ex) return k;
    return k * kernels::taper(sqrt(t2) * (1.0 / L));
  }
}

}  // namespace

namespace {

// A tool's f_tool at p and the squared distance from its surface (0 inside), which share their
// terms (a sphere's or a cylinder's squared distance from its centre or axis, a flat tool's
// |p - c| along each axis): one switch for both, in combine()'s every call.
template <class T>
[[gnu::always_inline]] inline void toolAt(const ToolShape& t, const P3<T>& p, T& g, T& dist2) {
  switch (t.type) {
    case ToolShape::Type::Sphere:
    case ToolShape::Type::Cylinder: {
      const T s2 = t.type == ToolShape::Type::Sphere ? sqr(p.x - t.center.x) + sqr(p.y - t.center.y) + sqr(p.z - t.center.z)
                                                     : segmentDistance2In3D(p, t.center, t.end);
      g = t.r * t.r - s2;
      dist2 = sqr(max(sqrt(s2) - t.r, T(0.0)));
      return;
    }
    case ToolShape::Type::Flat: {
      const T ax = abs(p.x - t.center.x), ay = abs(p.y - t.center.y), az = abs(p.z - t.center.z);
      g = min(min(t.half.x - ax, t.half.y - ay), t.half.z - az);
      dist2 = sqr(max(ax - t.half.x, T(0.0))) + sqr(max(ay - t.half.y, T(0.0))) + sqr(max(az - t.half.z, T(0.0)));
      return;
    }
  }
  g = T(-1.0), dist2 = T(0.0);
}

}  // namespace

template <class T>
T ToolShape::value(const P3<T>& p) const {
  T g(0.0), dist2(0.0);
  toolAt(*this, p, g, dist2);
  return g;
}

Box3 ToolShape::bounds() const {
  switch (type) {
    case Type::Sphere:
      return {center.x - r, center.y - r, center.z - r, center.x + r, center.y + r, center.z + r};
    case Type::Cylinder:
      return {std::min(center.x, end.x) - r, std::min(center.y, end.y) - r, std::min(center.z, end.z) - r,
              std::max(center.x, end.x) + r, std::max(center.y, end.y) + r, std::max(center.z, end.z) + r};
    case Type::Flat:
      return {center.x - half.x, center.y - half.y, center.z - half.z,
              center.x + half.x, center.y + half.y, center.z + half.z};
  }
  return {};
}

double ToolShape::size() const {
  if (type == Type::Flat) return std::min(half.x, std::min(half.y, half.z));
  return r;
}

double Operation::characteristicLength() const {
  switch (kind) {
    case OpKind::Trace:
    case OpKind::Patina:
      return a;
    case OpKind::Punch:
    case OpKind::Press:
      return a / std::sqrt(q);
    case OpKind::Region:
      return falloff;
    default:
      return tool.size();
  }
}

const char* opKindName(OpKind k) {
  switch (k) {
    case OpKind::Trace: return "trace";
    case OpKind::Punch: return "punch";
    case OpKind::Press: return "press";
    case OpKind::Region: return "region";
    case OpKind::BlendUnion: return "blend_union";
    case OpKind::Subtract: return "subtract";
    case OpKind::BlendSubtract: return "blend_subtract";
    case OpKind::Patina: return "patina";
  }
  return "?";
}

namespace {

std::string shortNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// "" when lo <= v <= hi, else "key: v is out of range: lo to hi unit".
std::string outOfRange(const std::string& key, double v, double lo, double hi, const char* unit) {
  if (v >= lo && v <= hi) return {};
  return key + ": " + (std::isnan(v) ? std::string("nan") : shortNumber(v)) + " is out of range: " + shortNumber(lo) +
         " to " + shortNumber(hi) + unit;
}
std::string length(const std::string& key, double v) { return outOfRange(key, v, kMinLengthMm, kMaxLengthMm, " mm"); }
std::string coordinate(const std::string& key, double v) {
  return outOfRange(key, v, -kMaxLengthMm, kMaxLengthMm, " mm");
}
std::string point3(const std::string& key, const Vec3& v) {
  for (const auto& [axis, c] : {std::pair{0, v.x}, std::pair{1, v.y}, std::pair{2, v.z}}) {
    std::string e = coordinate(key + "[" + std::to_string(axis) + "]", c);
    if (!e.empty()) return e;
  }
  return {};
}

}  // namespace

std::string validate(const Operation& op) {
  std::string e;
  const auto check = [&e](std::string problem) {
    if (e.empty()) e = std::move(problem);
  };
  const char* pathKey = op.kind == OpKind::Region ? "contour" : "points";
  if (op.points.size() > kMaxPathPoints)
    return std::string(pathKey) + ": " + std::to_string(op.points.size()) + " points, at most " +
           shortNumber(kMaxPathPoints);
  for (size_t i = 0; i < op.points.size() && e.empty(); ++i) {
    const std::string key = std::string(pathKey) + "[" + std::to_string(i) + "]";
    check(coordinate(key + "[0]", op.points[i].x));
    check(coordinate(key + "[1]", op.points[i].y));
  }
  if (!e.empty()) return e;
  switch (op.kind) {
    case OpKind::Trace:
      check(length("a", op.a));
      if (op.points.empty()) return "points: a trace needs at least one point";
      for (const auto* j : {&op.joinStart, &op.joinEnd}) {
        const std::string name = j == &op.joinStart ? "join_start" : "join_end";
        // The tools shorten a joint to 0.4 of a short piece's length, so its lower bound is lower.
        if (j->r != 0.0) check(outOfRange(name + ".r", j->r, 1e-6, kMaxLengthMm, " mm"));
        if (j->on() && (!(std::abs(j->dir.x) <= 1e6 && std::abs(j->dir.y) <= 1e6) ||
                        std::hypot(j->dir.x, j->dir.y) <= 1e-12))
          check(name + ".dir: must be a direction (two numbers of at most 1e6, not both zero)");
      }
      break;
    case OpKind::Punch:
    case OpKind::Press:
      check(length("a", op.a));
      check(outOfRange("q", op.q, 1.0 / kMaxShape, kMaxShape, ""));
      check(outOfRange("p", op.p, -kMaxShape, kMaxShape, ""));
      if (op.kind == OpKind::Punch) check(point3("at", op.at));
      if (op.kind == OpKind::Press && op.points.empty()) return "points: a press needs at least one point";
      if (op.kind == OpKind::Press && e.empty()) {
        // The punches PreparedOp places every L/4 along the path (counted in double: no overflow).
        const double spacing = 0.25 * op.characteristicLength();
        double punches = 1.0;
        for (size_t i = 1; i < op.points.size(); ++i) {
          const double len = std::hypot(op.points[i].x - op.points[i - 1].x, op.points[i].y - op.points[i - 1].y);
          punches += std::max(1.0, std::ceil(len / spacing));
        }
        if (punches > kMaxPathPoints)
          check("points: the path needs " + shortNumber(punches) + " punches at a spacing of " + shortNumber(spacing) +
                " mm, at most " + shortNumber(kMaxPathPoints));
      }
      break;
    case OpKind::Patina:
      check(length("r", op.a));
      if (op.points.empty()) return "points: a patina stroke needs at least one point";
      if (op.tinge < 1 || op.tinge > 4) check("tinge: must be black, brown, green or golden");
      check(outOfRange("strength", op.strength, 0.0, 1.0, ""));
      break;
    case OpKind::Region:
      if (op.points.size() < 3) return "contour: a region needs a closed contour of at least 3 points";
      check(coordinate("height", op.height));
      check(length("falloff", op.falloff));
      break;
    default: {
      const ToolShape& t = op.tool;
      check(point3("tool.center", t.center));
      if (t.type == ToolShape::Type::Flat) {
        check(length("tool.size[0]", 2.0 * t.half.x));
        check(length("tool.size[1]", 2.0 * t.half.y));
        check(length("tool.size[2]", 2.0 * t.half.z));
      } else {
        check(length("tool.r", t.r));
      }
      if (t.type == ToolShape::Type::Cylinder) check(point3("tool.end", t.end));
      if (op.kind != OpKind::Subtract) {
        check(coordinate("a1", op.a1));
        check(length("a2", op.a2));
        check(length("a3", op.a3));
      }
    }
  }
  return e;
}

PreparedOp::PreparedOp(Operation op) : op_(std::move(op)) {
  if (op_.kind == OpKind::Region) {
    std::vector<double> xy;
    xy.reserve(2 * op_.points.size());
    for (const Vec2& q : op_.points) xy.push_back(q.x), xy.push_back(q.y);
    contour_ = ContourEdges(xy);
  }
  if ((op_.kind == OpKind::Trace || op_.kind == OpKind::Region) && op_.points.size() >= 2) {
    const auto& pts = op_.points;
    const size_t n = pts.size();
    const size_t count = op_.kind == OpKind::Region && n > 2 ? n : n - 1;
    segments_.reserve(count);
    for (size_t i = 0; i < count; ++i) {
      const Vec2 &a = pts[i], &b = pts[i + 1 < n ? i + 1 : 0];
      const double ex = b.x - a.x, ey = b.y - a.y, len2 = ex * ex + ey * ey;
      segments_.push_back({a.x, a.y, ex, ey, len2 <= 0.0 ? 0.0 : 1.0 / len2});
    }
    pathFields_ = PathFields(segments_);
  }
  const double L = length_ = op_.characteristicLength();
  invA2_ = 1.0 / op_.a2, invA3_ = 1.0 / op_.a3;  // (the blends'; a plain subtraction's unread)
  const double reach = kSupportSpan * L;
  switch (op_.kind) {
    case OpKind::Trace: {
      for (const auto& pt : op_.points) support_.extend(pt.x, pt.y);
      maxSlope_ = kAgnesiMaxSlope + op_.a * kTaperSlopeFactor / L;
      for (int e = 0; e < 2; ++e) {
        const TraceJoin& j = e == 0 ? op_.joinStart : op_.joinEnd;
        if (!j.on()) continue;
        Joint& k = joints_[e];
        const Vec2& at = e == 0 ? op_.points.front() : op_.points.back();
        const double n = std::hypot(j.dir.x, j.dir.y);
        k.on = true;
        k.px = at.x, k.py = at.y;
        k.kx = j.dir.x / (n * j.r), k.ky = j.dir.y / (n * j.r);
        // The line continued straight through the joint for r: backwards before the first point,
        // forwards after the last one.
        const double sx = (e == 0 ? -1.0 : 1.0) * j.dir.x / n * j.r, sy = (e == 0 ? -1.0 : 1.0) * j.dir.y / n * j.r;
        k.e0 = at;
        k.e1 = {at.x + sx, at.y + sy};
        support_.extend(k.e1.x, k.e1.y);
        // The weight's slope times the largest value it multiplies (the profile's peak a).
        maxSlope_ += op_.a * kernels::kJoinMaxSlope / j.r;
      }
      support_ = support_.grown(reach);
      break;
    }
    case OpKind::Punch: {
      support_.extend(op_.at.x, op_.at.y);
      support_ = support_.grown(reach);
      const double peak = std::abs(op_.p) * op_.a;
      maxSlope_ = std::abs(op_.p) * std::sqrt(op_.q) * kAgnesiMaxSlope + peak * kTaperSlopeFactor / L;
      break;
    }
    case OpKind::Press: {
      // Punch points every L/4 along the path, end points included: along a straight stretch the
      // sum of (3) over them varies by less than 2e-5 of its height (what is left comes from the
      // taper window; at L/2 spacing it was 1.5e-4).
      const double spacing = 0.25 * L;
      const auto& pts = op_.points;
      pressPoints_.push_back({pts[0].x, pts[0].y, 0.0});
      for (size_t i = 1; i < pts.size(); ++i) {
        const double dx = pts[i].x - pts[i - 1].x, dy = pts[i].y - pts[i - 1].y;
        const double len = std::hypot(dx, dy);
        // validate() has bounded the count (kMaxPathPoints), so it fits an int.
        const int n = std::max(1, static_cast<int>(std::ceil(len / spacing)));
        for (int k = 1; k <= n; ++k) {
          const double t = static_cast<double>(k) / n;
          pressPoints_.push_back({pts[i - 1].x + t * dx, pts[i - 1].y + t * dy, 0.0});
        }
      }
      for (const auto& pt : pressPoints_) support_.extend(pt.x, pt.y);
      support_ = support_.grown(reach);
      // At most 2 * 4L / spacing + 1 = 33 punch points reach a point of a straight path.
      const double peak = std::abs(op_.p) * op_.a;
      maxSlope_ = 33.0 * (std::abs(op_.p) * std::sqrt(op_.q) * kAgnesiMaxSlope + peak * kTaperSlopeFactor / L);
      break;
    }
    case OpKind::Region: {
      for (const auto& pt : op_.points) support_.extend(pt.x, pt.y);
      support_ = support_.grown(reach);
      maxSlope_ = std::abs(op_.height) / L * (kAgnesiMaxSlope + kTaperSlopeFactor);
      break;
    }
    case OpKind::Patina: {
      for (const auto& pt : op_.points) support_.extend(pt.x, pt.y);
      support_ = support_.grown(op_.a);  // the brush leaves nothing beyond its radius
      // The path's segments kPatinaChunk at a time: the box of their ends (patinaAt()).
      for (size_t i = 1; i < op_.points.size(); i += kPatinaChunk) {
        Box2 b;
        for (size_t k = i - 1; k < std::min(i + kPatinaChunk, op_.points.size()); ++k) b.extend(op_.points[k].x, op_.points[k].y);
        patinaChunks_.push_back(b);
      }
      maxSlope_ = 0.0;  // moves nothing
      break;
    }
    default: {
      const Box3 b = op_.tool.bounds();
      support_ = b.xy().grown(reach);
      maxSlope_ = 0.0;  // set operations are not offsets
      break;
    }
  }
}

// The squared distance to the path (polylineDistance2's value). With gradients the nearest
// segment is found in doubles from the segments' precomputed parts by nearestSegments (the
// arithmetic of kernels::segmentDistance2, so the same values, the first of equal ones kept as
// min keeps it), and only its distance is taken with its gradient.
template <class T>
T PreparedOp::pathDistance2(const T& x, const T& y) const {
  const bool closed = op_.kind == OpKind::Region;
  if constexpr (std::is_same_v<T, Grad>) {
    if (segments_.empty()) return polylineDistance2(x, y, op_.points, closed);
    std::uint32_t best = 0;
    (void)nearestSegment(pathFields_, x.v, y.v, &best);  // (a vector of segments at a time, long paths by chunks)
    return segmentDistance2(best, x, y);
  } else if constexpr (std::is_same_v<T, double>) {
    // A vector of segments at a time (path_rows.h): the same value.
    return segments_.empty() ? polylineDistance2(x, y, op_.points, closed) : nearestDistance2(pathFields_, x, y);
  } else {
    return polylineDistance2(x, y, op_.points, closed);
  }
}

Grad PreparedOp::segmentDistance2(size_t i, const Grad& x, const Grad& y) const {
  const auto& pts = op_.points;
  const Vec2 &a = pts[i], &b = pts[i + 1 < pts.size() ? i + 1 : 0];
  return kernels::segmentDistance2(x, y, a.x, a.y, b.x, b.y);
}

template <class T>
T PreparedOp::traceOffset(T t2, const P3<T>& p) const {
  const Operation& o = op_;
  const double L = length_;
  if (!joints_[0].on && !joints_[1].on) return o.sign() * tapered(t2, L, [&](const T& d2) { return kernels::agnesi(d2, o.a); });
  // Joints: the line continued through them, the hand-over weights (docs/kernels.md).
  for (const Joint& k : joints_)
    if (k.on) t2 = min(t2, kernels::segmentDistance2(p.x, p.y, k.e0.x, k.e0.y, k.e1.x, k.e1.y));
  T v = tapered(t2, L, [&](const T& d2) { return kernels::agnesi(d2, o.a); });
  for (int e = 0; e < 2; ++e) {
    const Joint& k = joints_[e];
    if (!k.on) continue;
    const T w = kernels::joinStep((p.x - k.px) * k.kx + (p.y - k.py) * k.ky);
    v = v * (e == 0 ? w : T(1.0) - w);
  }
  return o.sign() * v;
}

// The region's descent outside its contour, before its sign.
template <class T>
T PreparedOp::regionOutside(const T& t2) const {
  const Operation& o = op_;
  return tapered(t2, length_, [&](const T& d2) { return o.height * kernels::agnesi(d2, o.falloff) * (1.0 / o.falloff); });
}

template <class T>
T PreparedOp::offset(const P3<T>& p, Deformation model) const {
  const Operation& o = op_;
  const double L = length_;
  switch (o.kind) {
    case OpKind::Trace:
      return traceOffset(pathDistance2(p.x, p.y), p);
    case OpKind::Punch: {
      T r2 = sqr(p.x - o.at.x) + sqr(p.y - o.at.y);
      // The paper's |P'| is the distance in space; the sheet measures it along the sheet.
      if (model == Deformation::Offset) r2 = r2 + sqr(p.z - o.at.z);
      return o.sign() * tapered(r2, L, [&](const T& d2) { return kernels::punch(d2, o.a, o.p, o.q); });
    }
    case OpKind::Press: {
      T sum(0.0);
      const double lim2 = sqr(kSupportSpan * L);
      for (const Vec3& c : pressPoints_) {
        T r2 = sqr(p.x - c.x) + sqr(p.y - c.y);
        if (model == Deformation::Offset) r2 = r2 + sqr(p.z - c.z);
        double lo;
        if constexpr (std::is_same_v<T, Interval>) lo = r2.lo; else lo = valueOf(r2);
        if (lo >= lim2) continue;
        sum += tapered(r2, L, [&](const T& d2) { return kernels::punch(d2, o.a, o.p, o.q); });
      }
      return o.sign() * sum;
    }
    case OpKind::Region: {
      const T t2 = pathDistance2(p.x, p.y);
      if constexpr (std::is_same_v<T, Interval>) {
        const Interval outside = regionOutside(t2);
        if (t2.lo > 0.0) {
          // The box does not touch the contour: it lies wholly inside or wholly outside.
          const bool in = insideContour(contour_, p.x.mid(), p.y.mid());
          return o.sign() * (in ? Interval(o.height) : outside);
        }
        return o.sign() * Interval(std::min(outside.lo, o.height), std::max(outside.hi, o.height));
      } else {
        if (insideContour(contour_, valueOf(p.x), valueOf(p.y))) return T(o.sign() * o.height);
        return o.sign() * regionOutside(t2);
      }
    }
    default:
      return T(0.0);
  }
}

void PreparedOp::offsetRow(double y, const double* xs, int n, Grad* out) const {
  const Operation& o = op_;
  const Grad gy(y, 0.0, 1.0, 0.0);
  auto at = [&](int k) { return P3<Grad>{Grad(xs[k], 1.0, 0.0, 0.0), gy, Grad(0.0)}; };
  if ((o.kind != OpKind::Trace && o.kind != OpKind::Region) || segments_.empty()) {
    for (int k = 0; k < n; ++k) out[k] = offset(at(k), Deformation::Sheet);
    return;
  }
  // Per thread: the field's bands are updated on the pool.
  thread_local std::vector<double> px, bestV, crossings;
  thread_local std::vector<std::uint32_t> best;
  thread_local std::vector<int> which;
  const double* searchX = xs;
  int searched = n;
  if (o.kind == OpKind::Region) {
    // insideContour's crossings of this row, in its arithmetic: a point is inside where an odd
    // number of them lie to its right (x < xc).
    crossings.clear();
    const auto& c = o.points;
    for (size_t i = 0, j = c.size() - 1; i < c.size(); j = i++)
      if ((c[i].y > y) != (c[j].y > y)) crossings.push_back(c[j].x + (y - c[j].y) * (c[i].x - c[j].x) / (c[i].y - c[j].y));
    std::sort(crossings.begin(), crossings.end());
    // Inside: the region's height; the distance is looked for only outside.
    px.clear();
    which.clear();
    for (int k = 0; k < n; ++k) {
      const auto right = crossings.end() - std::upper_bound(crossings.begin(), crossings.end(), xs[k]);
      if (right % 2 == 1) {
        out[k] = Grad(o.sign() * o.height);
      } else {
        px.push_back(xs[k]);
        which.push_back(k);
      }
    }
    searchX = px.data();
    searched = static_cast<int>(px.size());
  }
  best.resize(static_cast<size_t>(searched));
  bestV.resize(static_cast<size_t>(searched));
  nearestSegments(segments_, y, searchX, searched, best.data(), bestV.data());
  for (int m = 0; m < searched; ++m) {
    const int k = o.kind == OpKind::Region ? which[static_cast<size_t>(m)] : m;
    const P3<Grad> p = at(k);
    const Grad t2 = segmentDistance2(best[static_cast<size_t>(m)], p.x, p.y);
    out[k] = o.kind == OpKind::Trace ? traceOffset(t2, p) : o.sign() * regionOutside(t2);
  }
}

template <class T>
T PreparedOp::combine(const T& f, const P3<T>& p) const {
  const Operation& o = op_;
  if (!o.isSet()) return f;
  const ToolShape& tool = o.tool;
  // The tool's value g and the distance from its surface (toolAt()). The distance, in units of L,
  // decides first: the blend is exact within 3 L and tapered to the untouched f at 4 L, so beyond
  // that it is not worked out.
  T g(0.0), dist2(0.0);
  toolAt(tool, p, g, dist2);
  const T w = tapered(dist2, length_, [](const T&) { return T(1.0); });  // (length_: the tool's size)
  bool whole;  // w is 1: the blend as it is
  if constexpr (std::is_same_v<T, Interval>) {
    if (w.hi <= 0.0) return f;
    whole = w.lo >= 1.0;
  } else {
    const double wv = valueOf(w);
    if (wv <= 0.0) return f;
    whole = wv >= 1.0;
  }
  T result;
  switch (o.kind) {
    case OpKind::BlendUnion: result = kernels::blendUnionByInverses(f, g, o.a1, invA2_, invA3_); break;
    case OpKind::BlendSubtract: result = kernels::blendSubtractByInverses(f, g, o.a1, invA2_, invA3_); break;
    default: result = kernels::subtract(f, g); break;
  }
  if (whole) return result;
  return f + w * (result - f);
}

namespace {

// The corners of the convex hull of `pts`, counter-clockwise (Andrew's monotone chain), fewer where
// a corner lies within `slack` of the chord that passes it by: every point of `pts` is then within
// `slack` of the hull of the corners returned.
std::vector<Vec2> hullCorners(const std::vector<Vec2>& pts, double slack) {
  const std::vector<Vec2> h = convexHull(pts);
  if (h.size() < 3) return h;
  // Corners within `slack` of a chord between two kept ones are dropped (a long smooth contour has
  // hundreds of corners a few micrometres off the chords).
  const size_t n = h.size();
  auto within = [&](size_t a, size_t b) {  // every corner strictly between a and b (b may be n: corner 0)
    const Vec2& p = h[a];
    const Vec2& q = h[b % n];
    const double dx = q.x - p.x, dy = q.y - p.y, len = std::sqrt(dx * dx + dy * dy);
    for (size_t c = a + 1; c < b; ++c)
      if (std::abs(dx * (h[c].y - p.y) - dy * (h[c].x - p.x)) > slack * len) return false;
    return true;
  };
  std::vector<Vec2> kept{h[0]};
  for (size_t a = 0; a < n;) {
    size_t b = a + 1;
    while (b < n && within(a, b + 1)) ++b;
    if (b < n) kept.push_back(h[b]);
    a = b;
  }
  return kept;
}

}  // namespace

PreparedOp::SupportPieces PreparedOp::supportPieces() const {
  SupportPieces s;
  s.radius = kSupportSpan * length_;
  const auto& pts = op_.points;
  // Each segment of the path a piece (one point alone: itself).
  auto segments = [&](const std::vector<Vec2>& path) {
    if (path.size() == 1) s.pieces.push_back({path[0]});
    for (size_t i = 0; i + 1 < path.size(); ++i) s.pieces.push_back({path[i], path[i + 1]});
  };
  switch (op_.kind) {
    case OpKind::Trace:
      segments(pts);
      for (const Joint& k : joints_)
        if (k.on) s.pieces.push_back({k.e0, k.e1});
      break;
    case OpKind::Punch:
      s.pieces.push_back({Vec2{op_.at.x, op_.at.y}});
      break;
    case OpKind::Press:
      segments(pts);  // the punches lie on the path
      break;
    case OpKind::Region: {
      // The hull of the contour holds what it encloses: its corners, fewer by a hundredth of a
      // millimetre more radius (what dirty updates project: a region of 300 points cost 2 ms).
      constexpr double kSlack = 0.01;
      s.pieces.push_back(hullCorners(pts, kSlack));
      s.radius += kSlack;
      break;
    }
    case OpKind::Patina:
      s.radius = op_.a;
      segments(pts);
      break;
    default:
      s.radius = 0.0;
      s.pieces.push_back({{support_.x0, support_.y0}, {support_.x1, support_.y0}, {support_.x1, support_.y1}, {support_.x0, support_.y1}});
      break;
  }
  return s;
}

bool PreparedOp::insideRegion(double x, double y) const { return insideContour(contour_, x, y); }

double PreparedOp::patinaAt(double x, double y) const {
  if (op_.kind != OpKind::Patina || !support_.contains(x, y)) return 0.0;
  // The distance to the stroke matters only within its reach a: a segment whose box grown by a
  // does not hold the point is farther than that and is passed (four comparisons instead of its
  // distance; a shaded point of a long stroke met every segment). The nearest segment within reach
  // is the polyline's nearest, so the value is polylineDistance2's to the bit.
  const std::vector<Vec2>& p = op_.points;
  const double a = op_.a, reach2 = a * a;
  double d2 = reach2;
  if (p.size() == 1) {
    d2 = sqr(x - p[0].x) + sqr(y - p[0].y);
  } else {
    // A chunk of segments whose box grown by a does not hold the point is passed whole: each of
    // its segments' boxes grown by a lies inside that (rounding keeps the order of x0 - a), so
    // each segment would be passed.
    for (size_t c = 0; c < patinaChunks_.size(); ++c) {
      const Box2& b = patinaChunks_[c];
      if (x < b.x0 - a || x > b.x1 + a || y < b.y0 - a || y > b.y1 + a) continue;
      const size_t i0 = 1 + c * kPatinaChunk, i1 = std::min(i0 + kPatinaChunk, p.size());
      for (size_t i = i0; i < i1; ++i) {
        const Vec2 &s = p[i - 1], &e = p[i];
        if (x < std::min(s.x, e.x) - a || x > std::max(s.x, e.x) + a || y < std::min(s.y, e.y) - a || y > std::max(s.y, e.y) + a)
          continue;
        d2 = std::min(d2, kernels::segmentDistance2(x, y, s.x, s.y, e.x, e.y));
      }
    }
  }
  const double u = d2 / reach2;
  if (u >= 1.0) return 0.0;
  return op_.strength * (1.0 - u * u) * (1.0 - u * u);
}

template double ToolShape::value(const P3<double>&) const;
template Grad ToolShape::value(const P3<Grad>&) const;
template Interval ToolShape::value(const P3<Interval>&) const;
template double PreparedOp::offset(const P3<double>&, Deformation) const;
template Grad PreparedOp::offset(const P3<Grad>&, Deformation) const;
template Interval PreparedOp::offset(const P3<Interval>&, Deformation) const;
template double PreparedOp::combine(const double&, const P3<double>&) const;
template Grad PreparedOp::combine(const Grad&, const P3<Grad>&) const;
template Interval PreparedOp::combine(const Interval&, const P3<Interval>&) const;

}  // namespace emboss
