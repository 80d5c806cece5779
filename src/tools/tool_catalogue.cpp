// Tools to operations: the paper's rule that tool size and metal set the equations' parameters.
#include "tools/tool_catalogue.h"

#include <algorithm>
#include <cmath>

#include "frep/kernels.h"
#include "util/portable_math.h"

namespace emboss {

const std::vector<ToolSpec>& toolCatalogue() {
  static const std::vector<ToolSpec> kTools = {
      {"Fine tracer", ToolKind::Tracer, 0.8, Side::Front},
      {"Tracer", ToolKind::Tracer, 1.4, Side::Front},
      {"Wide tracer", ToolKind::Tracer, 2.2, Side::Front},
      {"Small punch", ToolKind::Punch, 3.0, Side::Back},
      {"Punch", ToolKind::Punch, 6.0, Side::Back},
      {"Large punch", ToolKind::Punch, 10.0, Side::Back},
      {"Oval punch", ToolKind::OvalPunch, 5.0, Side::Back},
      {"Flat punch", ToolKind::FlatPunch, 6.0, Side::Front},
      {"Hammer", ToolKind::Hammer, 2.0, Side::Front},
      {"Region raiser", ToolKind::RegionRaiser, 3.0, Side::Back},
      {"Blending punch", ToolKind::BlendPunch, 4.0, Side::Back},
      {"Black patina", ToolKind::PatinaBrush, 6.0, Side::Front, 1},
      {"Brown patina", ToolKind::PatinaBrush, 6.0, Side::Front, 2},
      {"Green patina", ToolKind::PatinaBrush, 6.0, Side::Front, 3},
      {"Golden patina", ToolKind::PatinaBrush, 6.0, Side::Front, 4},
  };
  return kTools;
}

double penetrationDepth(const ToolSpec& tool, const Metal& metal, double pressure) {
  pressure = std::clamp(pressure, 0.0, 1.0);
  // Linear in pressure from a light touch (15 %) to full depth; softer metals yield further.
  const double full = tool.kind == ToolKind::Hammer ? 0.12 * tool.size : 0.22 * tool.size;
  return metal.ductility * full * (0.15 + 0.85 * pressure);
}

Operation traceOp(const ToolSpec& tool, const Metal& metal, const std::vector<Vec2>& path, double pressure) {
  Operation op;
  op.kind = OpKind::Trace;
  op.side = tool.side;
  // (2)'s profile peaks at a on the line and is a wide at half height: a is the depth, bounded by
  // the tracer's half width so that a harder press widens the line a little, as a real tracer does.
  op.a = std::min(0.5 * tool.size, std::max(0.05, penetrationDepth(tool, metal, pressure) * 1.6));
  op.points = path;
  return op;
}

Operation punchOp(const ToolSpec& tool, const Metal& metal, const Vec3& at, double pressure) {
  Operation op;
  op.kind = OpKind::Punch;
  op.side = tool.side;
  op.a = 0.5 * tool.size;  // radius of the punch
  op.q = tool.kind == ToolKind::Hammer ? 2.0 : 1.0;
  // (3)'s peak is p a: p is the depth over the radius.
  op.p = penetrationDepth(tool, metal, pressure) / op.a;
  op.at = at;
  return op;
}

namespace {

double averagePressure(const std::vector<StrokePoint>& s) {
  double sum = 0;
  for (const auto& p : s) sum += p.pressure;
  return s.empty() ? 0.0 : sum / s.size();
}

// Points at least `spacing` apart along the stroke (first and last kept).
std::vector<StrokePoint> resample(const std::vector<StrokePoint>& s, double spacing) {
  std::vector<StrokePoint> out;
  if (s.empty()) return out;
  out.push_back(s.front());
  for (size_t i = 1; i < s.size(); ++i)
    if (portableHypot(s[i].x - out.back().x, s[i].y - out.back().y) >= spacing) out.push_back(s[i]);
  if (s.size() > 1 && (out.back().x != s.back().x || out.back().y != s.back().y) &&
      portableHypot(s.back().x - out.back().x, s.back().y - out.back().y) > 0.25 * spacing)
    out.push_back(s.back());
  return out;
}

// Points exactly `spacing` apart in a straight line, the first the stroke's own: each where the path
// first gets that far from the one before, its z and pressure interpolated there. A point is final
// once the path has passed it (what the pen does afterwards moves none of them).
std::vector<StrokePoint> evenlySpaced(const std::vector<StrokePoint>& s, double spacing) {
  std::vector<StrokePoint> out;
  if (s.empty()) return out;
  out.push_back(s.front());
  const double s2 = spacing * spacing;
  StrokePoint a = s.front();  // where the walk along the path has got to
  for (size_t i = 1; i < s.size(); ++i) {
    const StrokePoint& b = s[i];
    for (;;) {
      const StrokePoint l = out.back();
      if ((b.x - l.x) * (b.x - l.x) + (b.y - l.y) * (b.y - l.y) < s2) break;
      // a + t (b - a) at `spacing` from l, t in (0, 1]: a lies inside the circle, b on or outside it.
      const double dx = b.x - a.x, dy = b.y - a.y, ax = a.x - l.x, ay = a.y - l.y;
      const double qa = dx * dx + dy * dy, qb = ax * dx + ay * dy, qc = ax * ax + ay * ay - s2;
      const double t = std::clamp((-qb + std::sqrt(std::max(0.0, qb * qb - qa * qc))) / qa, 0.0, 1.0);
      a = {a.x + t * dx, a.y + t * dy, a.z + t * (b.z - a.z), a.pressure + t * (b.pressure - a.pressure)};
      out.push_back(a);
    }
    a = b;
  }
  return out;
}

}  // namespace

double flatPunchDescent() {
  // The region's descent F^2 / (d^2 + F^2), exact to 3 F and tapered to zero at 4 F, integrated
  // over d in units of F (Simpson's rule; the taper's ends are smooth).
  static const double kIntegral = [] {
    constexpr int n = 4000;
    const auto g = [](double u) { return kernels::taperWeight(u) / (u * u + 1.0); };
    double sum = g(0.0) + g(kernels::kSupportSpan);
    for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * g(kernels::kSupportSpan * i / n);
    return sum * kernels::kSupportSpan / (3.0 * n);
  }();
  return kIntegral;
}

namespace {

// Joins a's end to b's start (at a's last point, which b starts from): false when a's last segment
// has no direction. The joint's direction bisects the turn from a's last segment to b's first.
bool joinPair(Operation& a, Operation& b) {
  const Vec2 p = a.points[a.points.size() - 2], q = a.points.back();
  const double dx = q.x - p.x, dy = q.y - p.y, seg = portableHypot(dx, dy);
  if (seg <= 1e-9) return false;
  double len = 0;
  for (size_t k = 1; k < a.points.size(); ++k) len += portableHypot(a.points[k].x - a.points[k - 1].x, a.points[k].y - a.points[k - 1].y);
  TraceJoin j;
  j.dir = {dx / seg, dy / seg};
  if (b.points.size() >= 2) {
    const double ex = b.points[1].x - b.points[0].x, ey = b.points[1].y - b.points[0].y, next = portableHypot(ex, ey);
    if (next > 1e-9) {
      const double mx = dx / seg + ex / next, my = dy / seg + ey / next, m = portableHypot(mx, my);
      // A turn back on itself has no bisector: its normal then (the two pieces lie on one line).
      j.dir = m > 1e-6 ? Vec2{mx / m, my / m} : Vec2{-dy / seg, dx / seg};
    }
  }
  // The half width along the pieces: u = (P - J)·d / r reaches 1 at the same distance along either
  // piece at any bend (along a piece, (P - J)·d is its distance times the cosine of half the turn;
  // at most 4 times narrower, a turn of 151 degrees).
  const double across = std::abs(j.dir.x * dx / seg + j.dir.y * dy / seg);
  j.r = std::min({1.5 * a.a, 0.4 * len, 1.6}) * std::max(0.25, across);
  a.joinEnd = j;
  b.joinStart = j;
  return true;
}

bool isTracePiece(const Operation& o) { return o.kind == OpKind::Trace && o.points.size() >= 2; }

}  // namespace

void joinTracePieces(std::vector<Operation>& ops, size_t first) {
  bool chained = ops.size() >= first + 2;  // every piece joined to the next
  for (size_t i = first; i + 1 < ops.size(); ++i) {
    Operation& a = ops[i];
    Operation& b = ops[i + 1];
    const bool joined = isTracePiece(a) && b.kind == OpKind::Trace && !b.points.empty() &&
                        a.points.back().x == b.points.front().x && a.points.back().y == b.points.front().y && joinPair(a, b);
    chained = chained && joined;
  }
  // A closed line (its last piece ends where its first starts, to within kCloseTolerance): the
  // closing joint too, at the first piece's start, so that the loop has no bead where it closes.
  if (!chained) return;
  Operation& last = ops.back();
  Operation& head = ops[first];
  if (!isTracePiece(last) || !isTracePiece(head)) return;
  const Vec2 s = head.points.front(), e = last.points.back();
  if (portableHypot(e.x - s.x, e.y - s.y) > kCloseTolerance) return;
  last.points.back() = s;  // the one joint point both pieces hold
  if (!joinPair(last, head)) last.points.back() = e;
}

std::vector<Operation> strokeToOperations(const ToolSpec& tool, const Metal& metal, const std::vector<StrokePoint>& stroke) {
  std::vector<Operation> ops;
  if (stroke.empty()) return ops;
  switch (tool.kind) {
    case ToolKind::Tracer: {
      // Simplify to points ~0.5 mm apart, then one trace operation per kTraceSegment of path, each
      // with the pressure of its own stretch; consecutive pieces share their joint point.
      const auto pts = resample(stroke, 0.5);
      if (pts.size() == 1) {
        ops.push_back(traceOp(tool, metal, {{pts[0].x, pts[0].y}}, pts[0].pressure));
        break;
      }
      std::vector<Vec2> piece{{pts[0].x, pts[0].y}};
      double len = 0, pressure = 0;
      int n = 0;
      for (size_t i = 1; i < pts.size(); ++i) {
        piece.push_back({pts[i].x, pts[i].y});
        len += portableHypot(pts[i].x - pts[i - 1].x, pts[i].y - pts[i - 1].y);
        pressure += pts[i].pressure, ++n;
        if (len >= kTraceSegment || i + 1 == pts.size()) {
          ops.push_back(traceOp(tool, metal, piece, pressure / n));
          piece = {piece.back()};
          len = 0, pressure = 0, n = 0;
        }
      }
      joinTracePieces(ops);
      break;
    }
    case ToolKind::Punch:
    case ToolKind::Hammer: {
      const double spacing = tool.kind == ToolKind::Hammer ? 0.9 * tool.size : 0.6 * tool.size;
      for (const auto& p : resample(stroke, spacing)) ops.push_back(punchOp(tool, metal, {p.x, p.y, p.z}, p.pressure));
      break;
    }
    case ToolKind::OvalPunch: {
      // Each strike is (3) pressed along a short path the length of the oval, along the stroke.
      const auto pts = resample(stroke, 0.8 * tool.size);
      for (size_t i = 0; i < pts.size(); ++i) {
        const auto& a = pts[i];
        const auto& b = pts[std::min(i + 1, pts.size() - 1)];
        double dx = b.x - a.x, dy = b.y - a.y;
        const double len = portableHypot(dx, dy);
        if (len < 1e-9) dx = 1, dy = 0; else dx /= len, dy /= len;
        Operation op;
        op.kind = OpKind::Press;
        op.side = tool.side;
        op.a = 0.25 * tool.size;
        op.q = 1.0;
        // A press sums about 2 pi punches per characteristic length: p is scaled down to match depth.
        op.p = penetrationDepth(tool, metal, a.pressure) / op.a / (2.0 * M_PI);
        const double h = 0.3 * tool.size;
        op.points = {{a.x - dx * h, a.y - dy * h}, {a.x + dx * h, a.y + dy * h}};
        ops.push_back(op);
      }
      break;
    }
    case ToolKind::FlatPunch: {
      // The chaser's flat punch walked along the stroke to beat the background down: each strike
      // pushes its rectangular face (the tool's size across the stroke, 0.7 of it along) down, a
      // region lowered from the front: uniform inside, the region's descent outside. The sheet
      // bends under it as a whole, so no strike cuts into the metal, however steep the relief it
      // lands on. The strikes overlap, as a chaser's do: kFlatPunchOverlap faces cover every point
      // of the line, each turned along the stroke, so the band is smooth along it; their depths
      // add up to half the penetration depth, a single strike's own.
      const double along = 0.35 * tool.size, across = 0.5 * tool.size, falloff = kFlatPunchFalloff * tool.size;
      const double spacing = 2.0 * along / kFlatPunchOverlap;
      const auto pts = evenlySpaced(stroke, spacing);
      // A point of a straight line lies under faces and descents that add up to this many strikes
      // (a single strike, a tap, goes the whole depth).
      const double strikes = pts.size() == 1 ? 1.0 : (2.0 * along + 2.0 * falloff * flatPunchDescent()) / spacing;
      for (size_t i = 0; i < pts.size(); ++i) {
        // Along the stroke: from the strike a face's length before (the first strikes: from the
        // first, or to the next). A single strike lies with its long side along x.
        double ux = 0.0, uy = 1.0;
        if (pts.size() >= 2) {
          const StrokePoint& a = pts[i >= kFlatPunchOverlap ? i - kFlatPunchOverlap : 0];
          const StrokePoint& b = pts[std::max<size_t>(i, 1)];
          const double len = portableHypot(b.x - a.x, b.y - a.y);
          ux = (b.x - a.x) / len, uy = (b.y - a.y) / len;
        }
        const double nx = uy, ny = -ux;  // across the stroke
        const StrokePoint& c = pts[i];
        Operation op;
        op.kind = OpKind::Region;
        op.side = tool.side;
        for (const auto& [su, sn] : {std::pair{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}})
          op.points.push_back({c.x + su * along * ux + sn * across * nx, c.y + su * along * uy + sn * across * ny});
        op.height = penetrationDepth(tool, metal, c.pressure) * 0.5 / strikes;
        op.falloff = falloff;
        ops.push_back(op);
      }
      break;
    }
    case ToolKind::RegionRaiser: {
      const auto pts = resample(stroke, 0.5);
      if (pts.size() < 3) break;
      Operation op;
      op.kind = OpKind::Region;
      op.side = tool.side;
      for (const auto& p : pts) op.points.push_back({p.x, p.y});
      op.height = penetrationDepth(tool, metal, averagePressure(stroke)) * 1.5;
      op.falloff = tool.size;
      ops.push_back(op);
      break;
    }
    case ToolKind::PatinaBrush: {
      Operation op;
      op.kind = OpKind::Patina;
      op.tinge = std::clamp(tool.tinge, 1, 4);
      op.a = 0.5 * tool.size;
      op.strength = std::clamp(0.25 + 0.75 * averagePressure(stroke), 0.0, 1.0);
      for (const auto& p : resample(stroke, 0.5)) op.points.push_back({p.x, p.y});
      ops.push_back(op);
      break;
    }
    case ToolKind::BlendPunch: {
      for (const auto& p : resample(stroke, 0.7 * tool.size)) {
        Operation op;
        op.kind = OpKind::BlendUnion;
        op.tool.type = ToolShape::Type::Sphere;
        op.tool.r = 0.5 * tool.size;
        // The ball sits on the surface, sunk by the depth of the press.
        op.tool.center = {p.x, p.y, p.z - op.tool.r + penetrationDepth(tool, metal, p.pressure)};
        op.a1 = 0.15 * tool.size * metal.hardness;
        op.a2 = 0.25 * tool.size;
        op.a3 = 0.5 * tool.size;
        ops.push_back(op);
      }
      break;
    }
  }
  return ops;
}

}  // namespace emboss
