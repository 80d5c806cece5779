// Capture drawing: sheet, rectification, ink, guide, skeleton, polylines and trace operations in one pass.
#include "capture/capture_drawing.h"

#include <algorithm>
#include <cmath>

#include "capture/gray.h"
#include "capture/ink.h"
#include "capture/sheet.h"
#include "capture/skeleton.h"
#include "tools/metal.h"
#include "tools/tool_catalogue.h"

namespace emboss {

namespace {

constexpr int kMaxPaperPx = 2400;  // the rectified sheet's longer side at most (memory and time)
constexpr int kMinPaperPx = 64;
constexpr std::uint8_t kInkRgb[3] = {24, 24, 30};

double dist(Vec2 a, Vec2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

}  // namespace

Vec2 DrawingMapping::paperToPlate(Vec2 p) const {
  return {(p.x - paperWidth / 2.0) * mmPerPaperPx, (paperHeight / 2.0 - p.y) * mmPerPaperPx};
}

Vec2 DrawingMapping::plateToPaper(Vec2 mm) const {
  return {mm.x / mmPerPaperPx + paperWidth / 2.0, paperHeight / 2.0 - mm.y / mmPerPaperPx};
}

Result<std::vector<Operation>> traceOperations(const std::vector<std::vector<Vec2>>& polylines, const CaptureOptions& options) {
  const ToolSpec* tool = nullptr;
  std::string tracers;
  for (const auto& t : toolCatalogue()) {
    if (t.kind != ToolKind::Tracer) continue;
    tracers += (tracers.empty() ? "" : ", ") + t.name;
    if (t.name == options.tracer) tool = &t;
  }
  if (!tool) return fail("capture: no tracer named '" + options.tracer + "' in the tool catalogue (tracers: " + tracers + ")");
  const auto metal = metalByName(options.metal);
  if (!metal) return fail("capture: unknown metal '" + options.metal + "' (copper, brass, silver, aluminium)");

  std::vector<Operation> ops;
  for (const auto& line : polylines) {
    if (line.size() < 2) continue;
    const size_t first = ops.size();
    std::vector<Vec2> piece{line[0]};
    double len = 0;
    Vec2 last = line[0];
    for (size_t i = 1; i < line.size(); ++i) {
      const Vec2 q = line[i];
      double seg = dist(last, q);
      while (len + seg > kTraceSegment) {
        const double t = (kTraceSegment - len) / seg;
        const Vec2 cut{last.x + t * (q.x - last.x), last.y + t * (q.y - last.y)};
        piece.push_back(cut);
        ops.push_back(traceOp(*tool, *metal, piece, options.pressure));
        piece = {cut};
        last = cut;
        len = 0;
        seg = dist(last, q);
      }
      if (seg > 0) piece.push_back(q);
      len += seg;
      last = q;
    }
    if (piece.size() >= 2) ops.push_back(traceOp(*tool, *metal, piece, options.pressure));
    joinTracePieces(ops, first);
  }
  return ops;
}

Result<CaptureResult> captureDrawingInSheet(const Image& photo, const std::array<Vec2, 4>& corners, double plateW, double plateH,
                                            const CaptureOptions& options) {
  if (!(plateW > 2 * options.marginMm) || !(plateH > 2 * options.marginMm))
    return fail("capture: the plate (" + std::to_string(plateW) + " x " + std::to_string(plateH) + " mm) is smaller than its margins");
  const GrayImage gray = toGray(photo);
  const auto& c = corners;
  const double top = dist(c[0], c[1]), bottom = dist(c[3], c[2]), left = dist(c[0], c[3]), right = dist(c[1], c[2]);
  double wr = std::max(top, bottom), hr = std::max(left, right);
  if (options.paperAspect > 0) {
    if (top + bottom >= left + right) hr = wr / options.paperAspect;
    else wr = hr / options.paperAspect;
  }
  const double shrink = std::min(1.0, kMaxPaperPx / std::max(wr, hr));
  const int W = static_cast<int>(std::lround(wr * shrink)), H = static_cast<int>(std::lround(hr * shrink));
  if (std::min(W, H) < kMinPaperPx)
    return fail("no sheet of paper found: the sheet is only " + std::to_string(W) + "x" + std::to_string(H) + " pixels in the photo; bring the camera closer");

  CaptureResult r;
  r.corners = corners;
  DrawingMapping& map = r.mapping;
  const auto h = Homography::fromQuad(corners, {Vec2{0, 0}, Vec2{double(W), 0}, Vec2{double(W), double(H)}, Vec2{0, double(H)}});
  const auto hi = h ? h->inverse() : std::nullopt;
  if (!h || !hi) return fail("no sheet of paper found: the corners are degenerate (three on a line)");
  map.photoToPaper = *h;
  map.paperToPhoto = *hi;
  map.paperWidth = W;
  map.paperHeight = H;
  map.plateW = plateW;
  map.plateH = plateH;
  map.guidePxPerMm = options.guidePxPerMm;
  map.mmPerPaperPx = std::min((plateW - 2 * options.marginMm) / W, (plateH - 2 * options.marginMm) / H);
  const double s = map.mmPerPaperPx;

  // Rectify: each paper pixel's centre back into the photo.
  GrayImage paper(W, H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const Vec2 p = map.paperToPhoto.apply({x + 0.5, y + 0.5});
      paper.at(x, y) = gray.sample(p.x, p.y);
    }

  // Ink: a local threshold over a window of a twentieth of the sheet, the border left out.
  InkOptions ink;
  ink.window = std::max(15, (std::min(W, H) / 20) | 1);
  Mask mask = inkMask(paper, ink);
  const int border = static_cast<int>(std::ceil(options.borderFrac * std::min(W, H)));
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      if (x < border || y < border || x >= W - border || y >= H - border) mask.at(x, y) = 0;
  // Specks: ink blobs smaller than the shortest stroke.
  {
    const Components comps = connectedComponents(mask, true);
    std::vector<int> x0(comps.area.size(), W), x1(comps.area.size(), -1), y0(comps.area.size(), H), y1(comps.area.size(), -1);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x)
        if (const int id = comps.label[static_cast<size_t>(y) * W + x])
          x0[id] = std::min(x0[id], x), x1[id] = std::max(x1[id], x), y0[id] = std::min(y0[id], y), y1[id] = std::max(y1[id], y);
    const double minPx = options.minStrokeMm / s;
    for (size_t i = 0; i < mask.v.size(); ++i)
      if (const int id = comps.label[i]; id && std::max(x1[id] - x0[id], y1[id] - y0[id]) + 1 < minPx) mask.v[i] = 0;
  }

  // The sheet with its light evened out, and the guide on the plate.
  const GrayImage white = paperWhite(paper, mask, ink.window);
  GrayImage level(W, H);
  r.paper = Image(W, H);
  for (size_t i = 0; i < level.v.size(); ++i) {
    level.v[i] = std::clamp(paper.v[i] / std::max(1.0f, white.v[i]), 0.0f, 1.0f);
    const auto g = static_cast<std::uint8_t>(std::lround(level.v[i] * 255));
    std::uint8_t* px = &r.paper.rgba[i * 4];
    px[0] = px[1] = px[2] = g, px[3] = 255;
  }
  const int gw = std::max(1, static_cast<int>(std::lround(plateW * options.guidePxPerMm)));
  const int gh = std::max(1, static_cast<int>(std::lround(plateH * options.guidePxPerMm)));
  r.guide = Image(gw, gh);
  for (int y = 0; y < gh; ++y)
    for (int x = 0; x < gw; ++x) {
      const Vec2 mm{(x + 0.5) / options.guidePxPerMm - plateW / 2, plateH / 2 - (y + 0.5) / options.guidePxPerMm};
      const Vec2 p = map.plateToPaper(mm);
      if (p.x < border || p.y < border || p.x > W - border || p.y > H - border) continue;
      const double n = level.sample(p.x, p.y);
      const double alpha = std::clamp((0.85 - n) / 0.45, 0.0, 1.0);
      std::uint8_t* px = r.guide.pixel(x, y);
      px[0] = kInkRgb[0], px[1] = kInkRgb[1], px[2] = kInkRgb[2];
      px[3] = static_cast<std::uint8_t>(std::lround(alpha * 255));
    }

  const size_t inkPixels = mask.count();
  if (inkPixels == 0) return fail("no drawing found on the sheet: draw with a dark felt-tip pen, lines at least 1 mm wide");

  // Strokes: skeleton, paths, simplification, plate millimetres.
  Mask skeleton = mask;
  thinZhangSuen(skeleton);
  const double widthPx = double(inkPixels) / std::max<size_t>(1, skeleton.count());
  r.strokeWidthMm = widthPx * s;
  TraceOptions trace;
  trace.strokeWidth = std::max(2.0, widthPx);
  trace.spurLength = std::max(3.0, 1.5 * widthPx);
  trace.minLength = std::max(3.0, options.minStrokeMm / s);
  const double tolerance = std::max(0.7, options.simplifyMm / s);
  for (const auto& path : traceSkeleton(skeleton, trace)) {
    std::vector<Vec2> line;
    for (const auto& p : simplifyRdp(path.points, tolerance)) line.push_back(map.paperToPlate(p));
    r.polylines.push_back(std::move(line));
  }
  if (r.polylines.empty()) return fail("no drawing found on the sheet: only specks; draw with a dark felt-tip pen, lines at least 1 mm wide");
  auto ops = traceOperations(r.polylines, options);
  if (!ops) return fail(ops.error());
  r.operations = std::move(*ops);
  return r;
}

Result<CaptureResult> captureDrawing(const Image& photo, double plateW, double plateH, const CaptureOptions& options) {
  auto sheet = findSheet(photo);
  if (!sheet) return fail(sheet.error());
  return captureDrawingInSheet(photo, sheet->corners, plateW, plateH, options);
}

}  // namespace emboss
