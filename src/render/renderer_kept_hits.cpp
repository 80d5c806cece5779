// The kept hits a change of the model can move, forgotten (docs/rendering.md, "Kept hits"): the
// rest are shaded again at the same point instead of traced. The changes come from sync()
// (renderer_sync.cpp).
#include <algorithm>
#include <cstddef>

#include "render/renderer_internal.h"

namespace emboss {

using namespace render_internal;

void Renderer::forgetMovedHits(bool followed, const std::vector<std::uint64_t>& setIdsBefore) {
  // Everything: another model, a rebuilt field, or another list of set operations. (An offset
  // under a set operation moves its tool where the offset reaches: the heights below.)
  bool all = !followed || !fieldReady_ || lastSync_.rebuilt || setOps_.size() != setIdsBefore.size();
  for (size_t k = 0; k < setOps_.size() && !all; ++k) all = setOps_[k].id != setIdsBefore[k];
  if (!all) {
    forgetHitsNear(fieldChanges_);
    return;
  }
  for (HitCache& cache : hitCaches_)
    if (cache.camera) cache.blank = true, cache.sampled.clear();
}

namespace {

double cross(const Vec2& a, const Vec2& b, const Vec2& c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

// Whether point p lies within sqrt(r2) of segment a-b (without a division).
bool pointNear(const Vec2& p, const Vec2& a, const Vec2& b, double r2) {
  const double ex = b.x - a.x, ey = b.y - a.y, px = p.x - a.x, py = p.y - a.y;
  const double along = px * ex + py * ey, l = ex * ex + ey * ey;
  if (along <= 0.0) return px * px + py * py <= r2;
  if (along >= l) return (px - ex) * (px - ex) + (py - ey) * (py - ey) <= r2;
  const double across = px * ey - py * ex;
  return across * across <= r2 * l;
}

// Whether segment a-b comes within `radius` of `piece` (a point, or a segment c-d: they cross, or
// an end of one lies near the other).
bool segmentNear(const Vec2& a, const Vec2& b, const std::vector<Vec2>& piece, double radius) {
  const double r2 = radius * radius;
  if (piece.size() == 1) return pointNear(piece[0], a, b, r2);
  const Vec2& c = piece[0];
  const Vec2& d = piece[1];
  const double d1 = cross(c, d, a), d2 = cross(c, d, b), d3 = cross(a, b, c), d4 = cross(a, b, d);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  return pointNear(a, c, d, r2) || pointNear(b, c, d, r2) || pointNear(c, a, b, r2) || pointNear(d, a, b, r2);
}

// The most convex pieces (points or segments) a change can have for forgetHitsNear() to test
// its pixels' rays one by one.
constexpr size_t kTestedPieces = 4;

}  // namespace

void Renderer::forgetHitsNear(const std::vector<FieldChange>& changes) {
  double peaks = 0.0;  // how far the changes together move the sheet at most, anywhere
  for (const FieldChange& c : changes) peaks += c.peak;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // A kept hit depends on the signs of f at its ray's points up to it and on f in its cell, one
  // point further (beginWalk(): the points lie h / kSubdivisions apart): on the ray's stretch up
  // to two points past the hit. A change can move it only if that stretch meets the 3D reach of
  // the change (the box of offsetReach(), and within it the column over the operation's convex
  // pieces). The pixels whose rays can meet it are the projection of that reach (piecesSpans());
  // among them, a ray whose kept hit lies before the reach along the ray (a hit in front of the
  // change, or on the sheet nearer the eye than its rise) keeps its hit: each pixel's ray is
  // tested (a punch on the vm medallion keeps 10 700 hits of its 31 500 pixels instead of 8 500,
  // and the rays it no longer traces are dear ones, many passing near the outline;
  // docs/performance.md, "Stop 47").
  const double past = 2.0 * step_ / kSubdivisions + 1e-6;
  for (HitCache& cache : hitCaches_) {
    if (!cache.camera || cache.blank) continue;
    // What a change of D can move: the hit's sign changes, the values in its cell and its normal
    // (the field's stencil, two samples round the samples changed), the box dirtySpansOfRays()
    // projects without the shading's reach; the sheet before and after within `peaks` of now.
    const Camera& camera = *cache.camera;
    const int w = camera.width();
    // The edges' samples' kept hits, where there are (their slots read where `sampled` says).
    std::uint8_t* const sampled = cache.sampled.size() == cache.t.size() ? cache.sampled.data() : nullptr;
    const double* const samples = sampled ? cache.samples.data() : nullptr;
    const double grow = 2.0 * std::sqrt(2.0) * field_.spacing() + step_ + 1e-6;
    // A perspective camera's rays along a row: from the eye, their directions scaled to a forward
    // part of 1 step by the same vector from pixel to pixel (a pixel's divisions: the direction's
    // length and its climb, where the camera's ray and a clip to the box made six).
    const bool perspective = camera.spec().type == CameraSpec::Type::Perspective;
    const glm::dvec3 forward = camera.rayAt(0.5 * camera.width(), 0.5 * camera.height()).dir;
    auto unscaled = [&](double sx, double sy) {
      const glm::dvec3 d = camera.rayAt(sx, sy).dir;
      return d / glm::dot(d, forward);
    };
    for (const FieldChange& c : changes) {
      const Box3 box = offsetReach(model_->workpiece().bounds(), c.region, grow, peaks);
      // Near the operation's convex pieces when it is known, else the box's rectangle.
      PreparedOp::SupportPieces pieces;
      if (c.op) pieces = c.op->supportPieces();
      const PixelSpans px = c.op ? piecesSpans(camera, pieces, grow, box) : PixelSpans::of(projectBox(camera, box));
      // A region's hull of many corners, a path of many segments, or a change without its
      // operation: every kept hit of the spans is forgotten (a region's pixels are nearly all in
      // its column, and a pixel's test costs as many distances as the pieces: it cost more than
      // it saved).
      if (!c.op || pieces.pieces.size() > kTestedPieces ||
          std::any_of(pieces.pieces.begin(), pieces.pieces.end(), [](const auto& p) { return p.size() > 2; })) {
        for (int y = px.box.y; y < px.box.y + px.box.h; ++y) {
          const PixelSpans::Span row = px.row(y);
          if (row.empty()) continue;
          const auto i0 = static_cast<std::ptrdiff_t>(y) * w + row.x0, i1 = static_cast<std::ptrdiff_t>(y) * w + row.x1;
          std::fill(cache.t.begin() + i0, cache.t.begin() + i1, nan);
          if (sampled) std::fill(sampled + i0, sampled + i1, std::uint8_t{0});
        }
        continue;
      }
      const double radius = pieces.radius + grow + 1e-6;
      // Whether the ray from `o` along `dir` (of any length: `inv` is 1 / its length), up to its
      // kept hit t, can meet the change.
      auto meets = [&](const glm::dvec3& o, const glm::dvec3& dir, double inv, double t) {
        const double end = (t + past) * inv;  // (t is along the unit direction)
        double ta, tb;
        // The ray within the box's heights (the pieces' column lies within its sides).
        if (std::abs(dir.z * inv) < 1e-12) {
          if (o.z < box.z0 || o.z > box.z1) return false;
          ta = 0.0, tb = end;
        } else {
          const double iz = 1.0 / dir.z;
          ta = (box.z0 - o.z) * iz, tb = (box.z1 - o.z) * iz;
          if (ta > tb) std::swap(ta, tb);
          ta = std::max(ta, 0.0), tb = std::min(tb, end);
          if (!(ta <= tb)) return false;
        }
        const Vec2 a{o.x + ta * dir.x, o.y + ta * dir.y}, b{o.x + tb * dir.x, o.y + tb * dir.y};
        for (const auto& piece : pieces.pieces)
          if (segmentNear(a, b, piece, radius)) return true;
        return false;
      };
      // Pixel (x, y)'s edge samples (when it has any kept): forgotten both when either ray can
      // meet the change. (Few pixels have them: no division saved here.)
      auto samplesMeet = [&](int x, int y, std::uint8_t* known, const double* ts) {
        if (!*known) return;
        for (int k = 0; k < 2; ++k) {
          if (std::isnan(ts[k])) continue;
          const Ray r = camera.rayAt(x + 0.5 + kEdgeSamples[k][0], y + 0.5 + kEdgeSamples[k][1]);
          if (meets(r.origin, r.dir, 1.0, ts[k])) {
            *known = 0;
            return;
          }
        }
      };
      auto rows = [&](const Rect& band) {
        for (int y = band.y; y < band.y + band.h; ++y) {
          const PixelSpans::Span row = px.row(y);
          double* const t = cache.t.data() + static_cast<std::ptrdiff_t>(y) * w;
          if (row.x0 >= row.x1) continue;
          if (sampled) {
            std::uint8_t* const known = sampled + static_cast<std::ptrdiff_t>(y) * w;
            const double* const ts = samples + 2 * static_cast<std::ptrdiff_t>(y) * w;
            for (int x = row.x0; x < row.x1; ++x) samplesMeet(x, y, known + x, ts + 2 * x);
          }
          if (!perspective) {
            for (int x = row.x0; x < row.x1; ++x) {
              if (std::isnan(t[x])) continue;
              const Ray r = camera.rayAt(x + 0.5, y + 0.5);
              if (meets(r.origin, r.dir, 1.0, t[x])) t[x] = nan;
            }
            continue;
          }
          const glm::dvec3 eye = camera.rayAt(row.x0 + 0.5, y + 0.5).origin;
          const glm::dvec3 d0 = unscaled(row.x0 + 0.5, y + 0.5), step = unscaled(row.x0 + 1.5, y + 0.5) - d0;
          for (int x = row.x0; x < row.x1; ++x) {
            if (std::isnan(t[x])) continue;
            const glm::dvec3 dir = d0 + static_cast<double>(x - row.x0) * step;
            if (meets(eye, dir, 1.0 / std::sqrt(glm::dot(dir, dir)), t[x])) t[x] = nan;
          }
        }
      };
      // (About 10 ns a pixel: many on the pool, by bands of rows.)
      const Rect all{0, px.box.y, 1, px.box.h};
      if (px.area() < 8192) rows(all);
      else pool_.parallelFor2D(all, 16, rows);
    }
  }
}

}  // namespace emboss
