// A display in memory with a software overlay.
#include "app/memory_display.h"

#include <algorithm>
#include <cmath>

namespace emboss {

namespace {

void blend(Image& img, int x, int y, const OverlayColor& c, double coverage) {
  const double a = std::clamp(c.a * coverage, 0.0, 1.0);
  if (a <= 0) return;
  std::uint8_t* p = img.pixel(x, y);
  const double src[3] = {c.r * 255.0, c.g * 255.0, c.b * 255.0};
  for (int k = 0; k < 3; ++k) p[k] = static_cast<std::uint8_t>(std::lround(p[k] * (1 - a) + std::clamp(src[k], 0.0, 255.0) * a));
  p[3] = 255;
}

// Signed distance to a rounded rectangle (negative inside).
double roundedBox(double px, double py, const OverlayRect& r) {
  const double rad = std::clamp(static_cast<double>(r.radius), 0.0, 0.5 * std::min(r.w, r.h));
  const double cx = r.x + r.w / 2.0, cy = r.y + r.h / 2.0;
  const double qx = std::abs(px - cx) - (r.w / 2.0 - rad), qy = std::abs(py - cy) - (r.h / 2.0 - rad);
  const double outside = std::hypot(std::max(qx, 0.0), std::max(qy, 0.0));
  return outside + std::min(std::max(qx, qy), 0.0) - rad;
}

}  // namespace

void drawOverlayInto(Image& img, const Overlay& o) {
  for (const auto& r : o.rects) {
    const int x0 = std::max(0, static_cast<int>(std::floor(r.x)) - 1), x1 = std::min(img.width, static_cast<int>(std::ceil(r.x + r.w)) + 1);
    const int y0 = std::max(0, static_cast<int>(std::floor(r.y)) - 1), y1 = std::min(img.height, static_cast<int>(std::ceil(r.y + r.h)) + 1);
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) blend(img, x, y, r.color, std::clamp(0.5 - roundedBox(x + 0.5, y + 0.5, r), 0.0, 1.0));
  }
  for (const auto& g : o.rings) {
    const double out = g.r + g.thickness / 2.0 + 1;
    const int x0 = std::max(0, static_cast<int>(g.cx - out)), x1 = std::min(img.width, static_cast<int>(g.cx + out) + 1);
    const int y0 = std::max(0, static_cast<int>(g.cy - out)), y1 = std::min(img.height, static_cast<int>(g.cy + out) + 1);
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const double d = std::abs(std::hypot(x + 0.5 - g.cx, y + 0.5 - g.cy) - g.r) - g.thickness / 2.0;
        blend(img, x, y, g.color, std::clamp(0.5 - d, 0.0, 1.0));
      }
  }
}

MemoryDisplay::MemoryDisplay(int width, int height, std::string why) : w_(width), h_(height), why_(std::move(why)), shown_(width, height) {}

std::string MemoryDisplay::name() const { return why_.empty() ? "memory (software overlay)" : "memory (" + why_ + ")"; }

bool MemoryDisplay::present(const Image& frame, std::span<const Rect>, const Overlay& overlay) {
  if (frame.width != w_ || frame.height != h_) return true;  // a wrong size is skipped, never fatal
  shown_ = frame;
  drawOverlayInto(shown_, overlay);
  textsSkipped_ += overlay.texts.size();
  ++presents_;
  return true;
}

}  // namespace emboss
