// Building the overlay from the kiosk's state, in pixels scaled to the screen's height.
#include "app/kiosk_overlay.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/workbench.h"
#include "render/shading.h"

namespace emboss {

namespace {

constexpr OverlayColor kPanel{0.05f, 0.045f, 0.04f, 0.62f};
constexpr OverlayColor kWell{0.16f, 0.14f, 0.13f, 0.92f};
constexpr OverlayColor kInk{0.96f, 0.93f, 0.88f, 1.0f};
constexpr OverlayColor kDim{0.96f, 0.93f, 0.88f, 0.28f};
constexpr OverlayColor kAmber{1.0f, 0.72f, 0.30f, 1.0f};

OverlayColor alpha(OverlayColor c, float a) {
  c.a *= a;
  return c;
}

OverlayColor metalColor(const Metal& m, double light = 0.78) {
  const auto c = toSrgb8({m.f0[0] * light, m.f0[1] * light, m.f0[2] * light});
  return {c[0] / 255.f, c[1] / 255.f, c[2] / 255.f, 1.f};
}

void disc(Overlay& o, double cx, double cy, double r, OverlayColor c) {
  o.rects.push_back({float(cx - r), float(cy - r), float(2 * r), float(2 * r), c, float(r)});
}

void text(Overlay& o, double x, double y, double size, const std::string& t, OverlayColor c) {
  o.texts.push_back({float(x), float(y), float(size), t, c});
}

// Text centred on cx (width estimated: the display measures, the overlay is built without it).
void textCentred(Overlay& o, double cx, double y, double size, const std::string& t, OverlayColor c) {
  text(o, cx - 0.33 * size * t.size(), y, size, t, c);
}

// A pictogram of the tool in a circle of radius r around (cx, cy).
void toolIcon(Overlay& o, const ToolSpec& t, double cx, double cy, double r) {
  disc(o, cx, cy, r, kWell);
  const double k = r / 55.0;  // the icon is drawn for r = 55
  const double sz = std::clamp(t.size / 6.0, 0.5, 1.8);
  switch (t.kind) {
    case ToolKind::Tracer: {  // a traced S-curve: a chain of small discs as wide as the tracer
      const double w = std::clamp(1.5 + 2.2 * t.size, 2.5, 8.0) * k;
      for (int i = 0; i <= 28; ++i) {
        const double u = i / 28.0;
        disc(o, cx + (u - 0.5) * 70 * k, cy + std::sin(u * 2 * M_PI) * 16 * k, w, kInk);
      }
      break;
    }
    case ToolKind::Punch:  // a raised boss: a disc with a highlight
      disc(o, cx, cy, 22 * k * sz, alpha(kInk, 0.9f));
      disc(o, cx - 7 * k * sz, cy - 7 * k * sz, 8 * k * sz, {1, 1, 1, 1});
      break;
    case ToolKind::OvalPunch:
      o.rects.push_back({float(cx - 32 * k), float(cy - 13 * k), float(64 * k), float(26 * k), alpha(kInk, 0.9f), float(13 * k)});
      break;
    case ToolKind::FlatPunch:
      o.rects.push_back({float(cx - 24 * k), float(cy - 17 * k), float(48 * k), float(34 * k), alpha(kInk, 0.9f), float(4 * k)});
      break;
    case ToolKind::Hammer:  // a field of small dents
      for (int i = -2; i <= 2; ++i)
        for (int j = -2; j <= 2; ++j)
          if (i * i + j * j <= 5) disc(o, cx + i * 13 * k + (j % 2) * 6 * k, cy + j * 11 * k, 3.6 * k, kInk);
      break;
    case ToolKind::RegionRaiser:  // an outline, raised inside
      disc(o, cx, cy, 26 * k, alpha(kInk, 0.35f));
      o.rings.push_back({float(cx), float(cy), float(30 * k), float(4 * k), kInk});
      break;
    case ToolKind::PatinaBrush: {  // a brush stroke of the tinge's colour
      const auto& c = tinges()[static_cast<size_t>(std::clamp(t.tinge, 1, 4))].color;
      const OverlayColor ink{float(std::sqrt(c[0])), float(std::sqrt(c[1])), float(std::sqrt(c[2])), 0.95f};
      for (int i = 0; i <= 24; ++i) {
        const double u = i / 24.0;
        disc(o, cx + (u - 0.5) * 66 * k, cy + std::sin(u * M_PI) * -14 * k + 7 * k, (9.0 - 4.0 * u) * k, ink);
      }
      break;
    }
    case ToolKind::BlendPunch:  // material added: two discs merging
      disc(o, cx - 10 * k, cy, 18 * k, alpha(kInk, 0.9f));
      disc(o, cx + 12 * k, cy, 14 * k, alpha(kInk, 0.9f));
      o.rects.push_back({float(cx - 10 * k), float(cy - 10 * k), float(22 * k), float(20 * k), alpha(kInk, 0.9f), 0});
      break;
  }
}

void benchOverlay(Overlay& o, const OverlayState& s, double u) {
  const Workbench& b = *s.bench;
  const ToolSpec t = b.tool();
  const double W = s.width, H = s.height;
  // The left column: tool, size, metal.
  const double px = 18 * u, pw = 150 * u, py = H * 0.5 - 225 * u, ph = 450 * u;
  o.rects.push_back({float(px), float(py), float(pw), float(ph), kPanel, float(22 * u)});
  const double cx = px + pw / 2;
  double y = py + 80 * u;
  toolIcon(o, t, cx, y, 58 * u);
  y += 70 * u;
  textCentred(o, cx, y, 14 * u, t.name, alpha(kInk, 0.8f));
  y += 30 * u;
  // Where the tool is in the catalogue: a row of small dots.
  const size_t n = toolCatalogue().size();
  const double step = std::min(12.0 * u, (pw - 20 * u) / n);
  for (size_t i = 0; i < n; ++i)
    disc(o, cx + (i - (n - 1) / 2.0) * step, y, (i == b.toolIndex() ? 4.2 : 2.6) * u, i == b.toolIndex() ? kInk : kDim);
  y += 50 * u;
  // Size: five circles growing; the chosen one filled.
  {
    const int steps = kMaxSizeStep - kMinSizeStep + 1;
    std::vector<double> radii;
    double total = 0;
    for (int i = 0; i < steps; ++i) radii.push_back((4.0 + 2.2 * i) * u), total += 2 * radii.back();
    const double gap = 5 * u;
    double x = cx - 0.5 * (total + gap * (steps - 1));
    for (int i = 0; i < steps; ++i) {
      const double r = radii[i];
      x += r;
      if (i + kMinSizeStep == b.sizeStep()) disc(o, x, y, r, kInk);
      else o.rings.push_back({float(x), float(y), float(r), float(1.6 * u), kDim});
      x += r + gap;
    }
  }
  y += 80 * u;
  // Metal: a coin of the metal's colour with a highlight.
  const Metal& m = b.metal();
  disc(o, cx, y, 44 * u, metalColor(m, 0.55));
  disc(o, cx - 4 * u, y - 4 * u, 38 * u, metalColor(m, 0.85));
  disc(o, cx - 14 * u, y - 14 * u, 10 * u, {1, 1, 1, 0.55f});
  y += 54 * u;
  std::string name(m.name);
  if (!name.empty()) name[0] = static_cast<char>(std::toupper(name[0]));
  textCentred(o, cx, y, 14 * u, name, alpha(kInk, 0.8f));
  // The turned view: a ring with a dot, shown while the piece is turned.
  if (b.turned()) {
    o.rings.push_back({float(cx), float(py + ph - 26 * u), float(12 * u), float(3 * u), kAmber});
    disc(o, cx + 12 * u, py + ph - 26 * u, 4 * u, kAmber);
  }

  // The pressure bar on the right: fills with the pen's pressure, in the metal's colour.
  const double bw = 30 * u, bh = 440 * u, bx = W - 18 * u - bw - 12 * u, by = H * 0.5 - bh / 2;
  o.rects.push_back({float(bx - 12 * u), float(by - 12 * u), float(bw + 24 * u), float(bh + 24 * u), kPanel, float(20 * u)});
  o.rects.push_back({float(bx), float(by), float(bw), float(bh), kWell, float(bw / 2)});
  const double p = std::clamp(b.pressure(), 0.0, 1.0);
  if (p > 0.005) {
    const double fh = std::max(bw, bh * p);
    o.rects.push_back({float(bx), float(by + bh - fh), float(bw), float(fh), metalColor(m, 0.95), float(bw / 2)});
  }
  for (int i = 1; i < 4; ++i)
    o.rects.push_back({float(bx - 5 * u), float(by + bh * i / 4.0), float(5 * u), float(1.5 * u), kDim, 0});

  // The footprint under the pen.
  const auto& hv = b.hover();
  if (hv.visible) {
    const OverlayColor c = hv.touching ? kAmber : alpha(kInk, 0.85f);
    o.rings.push_back({float(hv.sx), float(hv.sy), float(hv.radius), float((hv.touching ? 3.0 : 2.0) * u), c});
    o.rings.push_back({float(hv.sx), float(hv.sy), float(hv.radius + 2 * u), float(1.0 * u), {0, 0, 0, 0.35f}});
    disc(o, hv.sx, hv.sy, 2.0 * u, c);
  }
  // The region raiser's contour while it is being drawn.
  for (const auto& [x, y2] : b.openContour()) disc(o, x, y2, 2.2 * u, kAmber);
}

void captureOverlay(Overlay& o, const OverlayState& s, double u) {
  const double W = s.width, H = s.height;
  // The traced drawing on the plate: amber dots along its lines, as the region raiser's contour.
  constexpr size_t kMaxDots = 6000;
  const double step = std::max(1.5, 3.0 * u);
  size_t dots = 0;
  for (const auto& line : s.guide) {
    for (size_t i = 0; i < line.size() && dots < kMaxDots; ++i) {
      const auto [x1, y1] = line[i];
      if (i == 0) {
        disc(o, x1, y1, 1.6 * u, alpha(kAmber, 0.9f)), ++dots;
        continue;
      }
      const auto [x0, y0] = line[i - 1];
      const int n = std::max(1, static_cast<int>(std::hypot(x1 - x0, y1 - y0) / step));
      for (int k = 1; k <= n && dots < kMaxDots; ++k, ++dots) disc(o, x0 + (x1 - x0) * k / n, y0 + (y1 - y0) * k / n, 1.6 * u, alpha(kAmber, 0.9f));
    }
  }
  // A still being taken: a ring pulsing round a dot at the top, like a shutter.
  if (s.capturing) {
    const double cx = W / 2, cy = 46 * u;
    const double ph = std::fmod(s.now, 1.0);
    disc(o, cx, cy, 30 * u, kPanel);
    disc(o, cx, cy, 9 * u, kInk);
    o.rings.push_back({float(cx), float(cy), float((13 + 12 * ph) * u), float(3 * u), alpha(kAmber, float(1 - ph))});
  }
  std::string line = s.captureMessage;
  if (line.empty() && s.capturing) line = "Taking a picture of your drawing...";
  if (!line.empty()) {
    const double size = 17 * u, y = H - 64 * u;
    const double w = std::min(W - 40 * u, 0.66 * size * line.size() + 40 * u);
    o.rects.push_back({float(W / 2 - w / 2), float(y - 14 * u), float(w), float(size + 28 * u), kPanel, float(14 * u)});
    textCentred(o, W / 2, y, size, line, s.captureMessageIsError ? OverlayColor{1.0f, 0.55f, 0.45f, 1} : alpha(kInk, 0.95f));
  }
}

void stillThereOverlay(Overlay& o, const OverlayState& s, double u) {
  const double W = s.width, H = s.height;
  o.rects.push_back({0, 0, float(W), float(H), {0, 0, 0, 0.5f}, 0});
  const double cx = W / 2, cy = H / 2 - 30 * u;
  disc(o, cx, cy, 130 * u, {0.05f, 0.045f, 0.04f, 0.8f});
  o.rings.push_back({float(cx), float(cy), float(130 * u), float(10 * u), alpha(kAmber, 0.9f)});
  char buf[16];
  std::snprintf(buf, sizeof buf, "%d", static_cast<int>(std::ceil(s.countdownLeft)));
  textCentred(o, cx, cy - 52 * u, 104 * u, buf, kInk);
  // The time left as a bar that drains.
  const double frac = std::clamp(s.countdownLeft / std::max(0.1, s.countdownTotal), 0.0, 1.0);
  const double bw = 420 * u, bh = 14 * u, bx = cx - bw / 2, by = cy + 170 * u;
  o.rects.push_back({float(bx), float(by), float(bw), float(bh), kWell, float(bh / 2)});
  o.rects.push_back({float(bx), float(by), float(std::max(bh, bw * frac)), float(bh), kAmber, float(bh / 2)});
  textCentred(o, cx, by + 34 * u, 20 * u, "Still there? Touch the metal to go on.", alpha(kInk, 0.9f));
}

void attractOverlay(Overlay& o, const OverlayState& s, double u) {
  const double W = s.width, H = s.height;
  // The hint: a ring that pulses outward from a dot, like a touch.
  const double cx = W / 2, cy = H - 44 * u;
  const double ph = std::fmod(s.now, 1.8) / 1.8;
  disc(o, cx, cy, 10 * u, alpha(kInk, 0.95f));
  o.rings.push_back({float(cx), float(cy), float((15 + 24 * ph) * u), float(3 * u), alpha(kInk, float(0.9 * (1 - ph)))});
  o.rings.push_back({float(cx), float(cy), float(16 * u), float(2 * u), alpha(kInk, 0.5f)});
  if (!s.title.empty()) text(o, 28 * u, 24 * u, 18 * u, s.title, alpha(kInk, 0.75f));
  // How far the piece has come: a hairline along the bottom.
  o.rects.push_back({0, float(H - 4 * u), float(W * std::clamp(s.progress, 0.0, 1.0)), float(2 * u), alpha(kAmber, 0.6f), 0});
}

void staffOverlay(Overlay& o, const OverlayState& s, double u) {
  const double W = s.width, H = s.height;
  o.rects.push_back({0, 0, float(W), float(H), {0.02f, 0.02f, 0.03f, 0.86f}, 0});
  text(o, 40 * u, 32 * u, 30 * u, "Staff", kInk);
  const auto boxes = staffMenuBoxes(s.width, s.height, s.staff.menu.size());
  for (size_t i = 0; i < boxes.size(); ++i) {
    const ScreenBox& b = boxes[i];
    const bool sel = i == s.staff.selected;
    o.rects.push_back({float(b.x), float(b.y), float(b.w), float(b.h), sel ? OverlayColor{0.85f, 0.55f, 0.2f, 0.95f} : kWell,
                       float(12 * u)});
    text(o, b.x + 20 * u, b.y + b.h / 2 - 10 * u, 20 * u, s.staff.menu[i], sel ? OverlayColor{0.05f, 0.04f, 0.03f, 1} : kInk);
  }
  double y = 32 * u;
  const double x = W * 0.44;
  for (const auto& line : s.staff.lines) {
    text(o, x, y, 15 * u, line, alpha(kInk, 0.9f));
    y += 25 * u;
  }
  if (!s.staff.message.empty())
    text(o, 40 * u, H - 60 * u, 17 * u, s.staff.message,
         s.staff.messageIsError ? OverlayColor{1.0f, 0.45f, 0.4f, 1} : OverlayColor{0.55f, 0.95f, 0.6f, 1});
}

}  // namespace

std::vector<ScreenBox> staffMenuBoxes(int width, int height, size_t count) {
  const double u = height / 800.0;
  std::vector<ScreenBox> out;
  for (size_t i = 0; i < count; ++i) out.push_back({40 * u, (110 + i * 86.0) * u, std::min(width * 0.44 - 80 * u, 420 * u), 66 * u});
  return out;
}

Overlay buildOverlay(const OverlayState& s) {
  Overlay o;
  const double u = s.height / 800.0;
  switch (s.mode) {
    case KioskMode::Attract: attractOverlay(o, s, u); break;
    case KioskMode::Visitor:
      if (s.bench) benchOverlay(o, s, u);
      captureOverlay(o, s, u);
      break;
    case KioskMode::StillThere:
      if (s.bench) benchOverlay(o, s, u);
      captureOverlay(o, s, u);
      stillThereOverlay(o, s, u);
      break;
    case KioskMode::Staff: staffOverlay(o, s, u); break;
  }
  return o;
}

}  // namespace emboss
