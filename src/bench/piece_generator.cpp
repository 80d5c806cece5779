// The relief generator.
#include "bench/piece_generator.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "frep/vm_generate.h"
#include "frep/vm_model.h"
#include "frep/workpieces.h"

namespace emboss {

namespace {

struct Area {
  PieceShape shape;
  double hw, hh;  // half sizes (disc: radius in both)
  bool inside(double x, double y, double margin) const {
    if (shape == PieceShape::Disc) return std::hypot(x, y) <= hw - margin;
    return std::abs(x) <= hw - margin && std::abs(y) <= hh - margin;
  }
};

Area areaOf(const GeneratedPiece& p) {
  const Box3 b = p.workpiece->bounds();
  const bool disc = dynamic_cast<const Disc*>(p.workpiece.get()) != nullptr;
  return {disc ? PieceShape::Disc : PieceShape::Plate, 0.5 * (b.x1 - b.x0), 0.5 * (b.y1 - b.y0)};
}

Vec2 pointInside(PieceRandom& rng, const Area& a, double margin) {
  for (int i = 0; i < 1000; ++i) {
    const Vec2 p{rng.uniform(-a.hw, a.hw), rng.uniform(-a.hh, a.hh)};
    if (a.inside(p.x, p.y, margin)) return p;
  }
  return {0, 0};
}

Operation punch(double x, double y, Side side, double a, double p) {
  Operation o;
  o.kind = OpKind::Punch;
  o.side = side;
  o.a = a, o.p = p, o.q = 1.0;
  o.at = {x, y, 0.0};
  return o;
}

Operation trace(Vec2 p0, Vec2 p1, double a) {
  Operation o;
  o.kind = OpKind::Trace;
  o.side = Side::Front;
  o.a = a;
  o.points = {p0, p1};
  return o;
}

// A wobbly closed outline around c of mean radius r (a motif: a leaf, a head, a horse's flank).
std::vector<Vec2> outline(PieceRandom& rng, Vec2 c, double r, int n) {
  const double k1 = rng.uniform(0.05, 0.2), k2 = rng.uniform(0.03, 0.12);
  const double ph1 = rng.uniform(0, 6.3), ph2 = rng.uniform(0, 6.3), squash = rng.uniform(0.6, 1.0);
  const double rot = rng.uniform(0, std::numbers::pi);
  std::vector<Vec2> pts;
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * std::numbers::pi * i / n;
    const double rr = r * (1.0 + k1 * std::sin(2 * t + ph1) + k2 * std::sin(5 * t + ph2));
    const double x = rr * std::cos(t), y = rr * std::sin(t) * squash;
    pts.push_back({c.x + x * std::cos(rot) - y * std::sin(rot), c.y + x * std::sin(rot) + y * std::cos(rot)});
  }
  return pts;
}

bool insidePolygon(double x, double y, const std::vector<Vec2>& c) {
  bool in = false;
  for (size_t i = 0, j = c.size() - 1; i < c.size(); j = i++)
    if ((c[i].y > y) != (c[j].y > y) && x < c[j].x + (y - c[j].y) * (c[i].x - c[j].x) / (c[i].y - c[j].y)) in = !in;
  return in;
}

Operation blendBead(PieceRandom& rng, Vec2 at, double halfThickness, double scale) {
  Operation o;
  o.kind = OpKind::BlendUnion;
  o.tool.type = ToolShape::Type::Sphere;
  o.tool.r = rng.uniform(1.2, 2.0) * scale;
  o.tool.center = {at.x, at.y, halfThickness};
  o.a1 = 0.4 * scale, o.a2 = 1.0 * scale, o.a3 = 2.0 * o.tool.r;
  return o;
}

}  // namespace

Result<Model> GeneratedPiece::makeModel() const {
  Model m(workpiece, deformation);
  for (size_t i = 0; i < operations.size(); ++i) {
    Status s = m.add(operations[i]);
    if (!s) return fail("generated operation " + std::to_string(i) + ": " + s.error());
  }
  return m;
}

GeneratedPiece generatePiece(int count, unsigned seed, const PieceOptions& opt) {
  GeneratedPiece piece;
  piece.deformation = opt.deformation;
  if (opt.shape == PieceShape::Disc) {
    piece.workpiece = std::make_shared<Disc>(0.5 * std::min(opt.width, opt.height), opt.halfThickness);
  } else {
    piece.workpiece = std::make_shared<Plate>(0.5 * opt.width, 0.5 * opt.height, opt.halfThickness);
  }
  piece.camera = defaultCamera(piece.workpiece->bounds());
  const Area area = areaOf(piece);
  const double s = opt.toolScale;
  PieceRandom rng(seed);
  auto& ops = piece.operations;
  const int regions = std::max(1, count / 1000), blends = std::max(1, count / 1000);
  int regionsLeft = regions, blendsLeft = blends;
  // Motifs of about 150 operations (smaller pieces: one motif), radius by the area they share.
  const int motifs = std::max(1, (count + 75) / 150);
  const double areaMm2 = (area.shape == PieceShape::Disc ? std::numbers::pi * area.hw * area.hw : 4 * area.hw * area.hh);
  const double motifR = std::clamp(std::sqrt(areaMm2 / motifs / std::numbers::pi) * 0.75, 4.0 * s, 0.45 * std::min(area.hw, area.hh));
  for (int m = 0; m < motifs && static_cast<int>(ops.size()) < count; ++m) {
    const int budget = m == motifs - 1 ? count - static_cast<int>(ops.size()) : std::min(count - static_cast<int>(ops.size()), (count - static_cast<int>(ops.size())) / (motifs - m));
    const bool wantBlend = blendsLeft > 0 && (m == motifs - 1 || rng.chance(static_cast<double>(blends) / motifs));
    const int reserved = (regionsLeft > 0 ? 1 : 0) + (wantBlend ? 1 : 0);
    const double r = motifR * rng.uniform(0.7, 1.2);
    const Vec2 c = pointInside(rng, area, r + 6.0 * s);
    // Operations left for the strokes: ~40% outline segments, ~45% punches, the rest chasing.
    const int strokes = std::max(0, budget - reserved);
    const int segments = std::max(std::min(strokes, 3), static_cast<int>(0.4 * strokes));
    const std::vector<Vec2> contour = outline(rng, c, r, std::max(3, segments));
    if (regionsLeft > 0) {
      Operation o;
      o.kind = OpKind::Region;
      o.side = Side::Back;
      std::vector<Vec2> coarse;
      for (size_t i = 0; i < contour.size(); i += std::max<size_t>(1, contour.size() / 24)) coarse.push_back(contour[i]);
      if (coarse.size() < 3) coarse = contour;
      o.points = coarse;
      o.height = rng.uniform(0.5, 1.0) * s;
      o.falloff = rng.uniform(1.5, 2.5) * s;
      ops.push_back(o);
      --regionsLeft;
    }
    int made = 0;
    // The outline, in segments of about 2.5 mm, traced from the front.
    for (int i = 0; i < segments && made < strokes; ++i, ++made)
      ops.push_back(trace(contour[static_cast<size_t>(i)], contour[static_cast<size_t>(i + 1) % contour.size()], rng.uniform(0.4, 0.7) * s));
    // Bossing up from behind inside the outline, chasing the background down around it.
    const int inside = (strokes - made) * 3 / 4;
    for (int i = 0, tries = 0; i < inside && tries < 20 * inside + 100; ++tries) {
      const double x = c.x + rng.uniform(-1.3 * r, 1.3 * r), y = c.y + rng.uniform(-1.3 * r, 1.3 * r);
      if (!insidePolygon(x, y, contour) || !area.inside(x, y, 2.0 * s)) continue;
      ops.push_back(punch(x, y, Side::Back, rng.uniform(1.0, 2.2) * s, rng.uniform(0.25, 0.5)));
      ++i, ++made;
    }
    for (int tries = 0; made < strokes && tries < 40 * strokes + 100; ++tries) {
      const double t = rng.uniform(0, 2 * std::numbers::pi), rr = r * rng.uniform(1.15, 1.6);
      const double x = c.x + rr * std::cos(t), y = c.y + rr * std::sin(t);
      if (insidePolygon(x, y, contour) || !area.inside(x, y, 2.0 * s)) continue;
      ops.push_back(punch(x, y, Side::Front, rng.uniform(0.8, 1.5) * s, rng.uniform(0.15, 0.3)));
      ++made;
    }
    while (made < strokes) ops.push_back(punch(c.x, c.y, Side::Back, 1.5 * s, 0.3)), ++made;
    if (wantBlend) {
      ops.push_back(blendBead(rng, contour[static_cast<size_t>(rng.below(static_cast<int>(contour.size())))], opt.halfThickness, s));
      --blendsLeft;
    }
  }
  // Exactly `count`: trim or pad with punches.
  while (static_cast<int>(ops.size()) > count) ops.pop_back();
  while (static_cast<int>(ops.size()) < count) {
    const Vec2 p = pointInside(rng, area, 3.0 * s);
    ops.push_back(punch(p.x, p.y, Side::Back, 1.5 * s, 0.3));
  }
  return piece;
}

Operation randomPunch(PieceRandom& rng, const GeneratedPiece& piece, double s) {
  const Vec2 p = pointInside(rng, areaOf(piece), 10.0 * s);
  return punch(p.x, p.y, Side::Back, rng.uniform(1.5, 2.2) * s, rng.uniform(0.3, 0.5));
}

Operation randomTraceSegment(PieceRandom& rng, const GeneratedPiece& piece, double s) {
  const Vec2 p = pointInside(rng, areaOf(piece), 10.0 * s);
  const double t = rng.uniform(0, 2 * std::numbers::pi), len = rng.uniform(2.0, 3.0) * s;
  return trace(p, {p.x + len * std::cos(t), p.y + len * std::sin(t)}, rng.uniform(0.4, 0.7) * s);
}

Operation randomRegion(PieceRandom& rng, const GeneratedPiece& piece, double s) {
  const double r = rng.uniform(6.0, 14.0) * s;
  const Vec2 c = pointInside(rng, areaOf(piece), r + 4.0 * s);
  Operation o;
  o.kind = OpKind::Region;
  o.side = Side::Back;
  o.points = outline(rng, c, r, 24 + rng.below(25));
  o.height = rng.uniform(0.5, 1.0) * s;
  o.falloff = rng.uniform(1.5, 2.5) * s;
  return o;
}

Operation randomSetOperation(PieceRandom& rng, const GeneratedPiece& piece, double s) {
  const Vec2 p = pointInside(rng, areaOf(piece), 10.0 * s);
  const double d = piece.workpiece->halfThickness();
  Operation o = blendBead(rng, p, d, s);
  const int k = rng.below(3);
  if (k == 1) {
    o.kind = OpKind::Subtract;
    o.tool.center.z = d + 0.5 * o.tool.r;
  } else if (k == 2) {
    o.kind = OpKind::BlendSubtract;
    o.tool.center.z = d + 0.5 * o.tool.r;
  }
  return o;
}

Result<GeneratedPiece> generateOutlinePiece(int clauses, unsigned outlineSeed, double scale, double halfThickness,
                                            int operations, unsigned seed, bool strokesOnly) {
  auto program = VmProgram::parse(generateVmRelief(clauses, outlineSeed), "generated");
  if (!program) return fail(program.error());
  auto wp = VmWorkpiece::create(std::move(*program), "generated.vm", scale, halfThickness);
  if (!wp) return fail(wp.error());
  const Box3 b = (*wp)->bounds();
  PieceOptions opt;
  opt.width = b.x1 - b.x0, opt.height = b.y1 - b.y0, opt.halfThickness = halfThickness;
  GeneratedPiece piece = generatePiece(operations, seed, opt);
  moveOperations(piece, 0.5 * (b.x0 + b.x1), 0.5 * (b.y0 + b.y1));
  if (strokesOnly) std::erase_if(piece.operations, [](const Operation& o) { return !o.isOffset(); });
  piece.workpiece = *wp;
  piece.camera = defaultCamera(b);
  return piece;
}

void moveOperations(GeneratedPiece& piece, double dx, double dy) {
  for (Operation& o : piece.operations) {
    for (Vec2& p : o.points) p.x += dx, p.y += dy;
    o.at.x += dx, o.at.y += dy;
    o.tool.center.x += dx, o.tool.center.y += dy;
    o.tool.end.x += dx, o.tool.end.y += dy;
  }
}

}  // namespace emboss
