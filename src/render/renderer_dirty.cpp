// Dirty regions: the pixels whose rays can see a change of the model (docs/rendering.md, "Dirty
// regions"); the renderer's frames are renderer.cpp's.
#include "render/renderer_internal.h"

namespace emboss {

using namespace render_internal;

// ---------------------------------------------------------------- dirty regions

Rect Renderer::projectBox(const Camera& camera, const Box3& b) {
  double x0 = 1e30, y0 = 1e30, x1 = -1e30, y1 = -1e30;
  for (double x : {b.x0, b.x1})
    for (double y : {b.y0, b.y1})
      for (double z : {b.z0, b.z1}) {
        const auto q = camera.project({x, y, z});
        if (!q) return {0, 0, camera.width(), camera.height()};
        x0 = std::min(x0, q->x), y0 = std::min(y0, q->y), x1 = std::max(x1, q->x), y1 = std::max(y1, q->y);
      }
  // A ray meets the box only if its pixel centre projects inside the corners' hull.
  const int w = camera.width(), h = camera.height();
  const double lim = 1e6;
  const int cx0 = std::clamp(static_cast<int>(std::floor(std::max(x0, -lim))) - 1, 0, w);
  const int cy0 = std::clamp(static_cast<int>(std::floor(std::max(y0, -lim))) - 1, 0, h);
  const int cx1 = std::clamp(static_cast<int>(std::ceil(std::min(x1, lim))) + 1, 0, w);
  const int cy1 = std::clamp(static_cast<int>(std::ceil(std::min(y1, lim))) + 1, 0, h);
  return {cx0, cy0, cx1 - cx0, cy1 - cy0};
}

PixelSpans Renderer::dirtySpans(const Model& model, size_t index) const {
  // A pixel reads its four neighbours' rays (render()): one pixel more each way.
  return dirtySpansOfRays(model, index).grown(1, camera_->width(), camera_->height());
}

PixelSpans Renderer::dirtySpansOfRays(const Model& model, size_t index) const {
  if (index >= model.operations().size()) return {};
  const auto& ops = model.operations();
  const PreparedOp& op = ops[index];
  const Box3 wb = model.workpiece().bounds();
  std::vector<std::uint32_t> scratch;

  if (!usesField()) {
    // The exact tracer: f changes in the support's column; a surface can be anywhere the model's
    // bounds allow, counted with the operation even when it was just undone. Interval spans
    // reach 8 steps from the ray.
    const double g = kSpanSteps * step_;
    double reach = 0.0;
    const size_t n = std::max(model.activeCount(), index + 1);
    for (size_t i = 0; i < n; ++i) reach += peakOf(ops[i].op());
    Box3 box{0, 0, wb.z0 - reach - g, 0, 0, wb.z1 + reach + g};
    for (size_t i = 0; i < n; ++i) {
      const Operation& o = ops[i].op();
      if (!o.isSet()) continue;
      const Box3 t = o.tool.bounds();
      const double r = kernels::kSupportSpan * o.tool.size() + reach + g;
      box.z0 = std::min(box.z0, t.z0 - r), box.z1 = std::max(box.z1, t.z1 + r);
    }
    const Box2 s = op.support().grown(g);
    box.x0 = s.x0, box.y0 = s.y0, box.x1 = s.x1, box.y1 = s.y1;
    return PixelSpans::of(projectBox(box));
  }

  // The field tracer. A pixel's result depends on the signs of f at its ray's grid points, on f
  // within the cell of its hit, and on the field's stencil and the set operations at the hit.
  const double cell = step_ + 1e-6;
  if (op.op().isSet()) {
    // A set operation changes f only within its 3D support, moved by the offsets after it.
    double shift = 0.0;
    for (std::uint32_t j : grid_.in(op.support(), scratch))
      if (j > index && j < model.activeCount() && ops[j].op().isOffset()) shift += peakOf(ops[j].op());
    const Box3 t = op.op().tool.bounds();
    const double r = kernels::kSupportSpan * op.op().tool.size() + shift + cell;
    const Box2 s = op.support().grown(cell);
    const Box3 box{s.x0, s.y0, t.z0 - r, s.x1, s.y1, t.z1 + r};
    if (op.op().tool.type == ToolShape::Type::Sphere && options_.roundWindows) {
      // A ball changes f only within its capsule (SetOp::round: its radius and kSupportSpan tool
      // sizes round its centre's column): the pixels of that column between the box's heights.
      const ToolShape& tool = op.op().tool;
      PreparedOp::SupportPieces column;
      column.pieces = {{Vec2{tool.center.x, tool.center.y}}};
      column.radius = tool.r + kernels::kSupportSpan * tool.size();
      return piecesSpans(*camera_, column, cell, box);
    }
    return PixelSpans::of(projectBox(box));
  }
  // An offset changes the samples under its support, and through the Hermite stencil (the
  // twists read the neighbours' slopes) the patches up to two samples further. A patina stroke
  // changes the colour of the hits under its support only (its peak is 0): the same box serves.
  // The shading reads D within kCavityReach of a hit (the cavity term).
  const Box3 box = offsetReach(wb, op.support(), 2.0 * field_.spacing() + cell + kCavityReach,
                               peakOf(op.op()));

  // The same growth around the support's convex pieces instead of its box (the field's stencil
  // reaches 2 spacings along x and y at once: its diagonal).
  return piecesSpans(*camera_, op.supportPieces(), 2.0 * std::sqrt(2.0) * field_.spacing() + cell + kCavityReach, box);
}

Box3 Renderer::offsetReach(const Box3& wb, const Box2& support, double grow, double peak) const {
  const double cell = step_ + 1e-6;
  const Box2 s = support.grown(grow);
  HeightField::Bound d = field_.rootBound();
  const Box2 dom = field_.domain();
  const Box2 q = s.intersected(dom);
  if (!q.empty()) d = field_.leafBound(q);
  // Before and after differ by at most the peak.
  Box3 box{s.x0, s.y0, wb.z0 + d.lo - peak - cell, s.x1, s.y1, wb.z1 + d.hi + peak + cell};
  // A set operation's tool moves with the sheet under it: its heights there too.
  for (const SetOp& so : setOps_)
    if (so.support.overlaps(s)) box.z0 = std::min(box.z0, so.zlo - peak - cell), box.z1 = std::max(box.z1, so.zhi + peak + cell);
  return box;
}

PixelSpans Renderer::piecesSpans(const Camera& camera, const PreparedOp::SupportPieces& pieces, double grow,
                                 const Box3& box) {
  // Each piece's points ringed by a polygon round a circle of the support's radius plus `grow`,
  // at the box's lowest and highest z, projected; the pixels near the hull of each.
  constexpr int kSides = 16;
  const double radius = (pieces.radius + grow) / std::cos(std::numbers::pi / kSides);  // the polygon holds the circle
  static const std::array<glm::dvec2, kSides> kRing = [] {
    std::array<glm::dvec2, kSides> ring;
    for (int k = 0; k < kSides; ++k) ring[k] = {std::cos(2.0 * std::numbers::pi * k / kSides), std::sin(2.0 * std::numbers::pi * k / kSides)};
    return ring;
  }();
  SpanBuilder spans(camera.width(), camera.height());
  std::vector<glm::dvec2> projected;
  for (const auto& piece : pieces.pieces) {
    projected.clear();
    for (const Vec2& c : piece)
      for (const glm::dvec2& u : kRing) {
        for (double z : {box.z0, box.z1}) {
          const auto p = camera.project({c.x + radius * u.x, c.y + radius * u.y, z});
          if (!p) return PixelSpans::of(projectBox(camera, box));
          projected.push_back(*p);
        }
      }
    spans.addHullOf(projected);
  }
  return spans.take();
}

}  // namespace emboss
