// A visitor's session as a tablet recording (evemu text, Wacom Intuos4 6x9 description): a flower
// traced, its petals raised, a boss punched and beads struck, switching tools with the pen's barrel
// button. Written to tests/app/data/visitor-demo.events (a test checks the file equals this); and
// six big raised regions, tests/app/data/big-regions.events.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "app/surface_pick.h"
#include "app/workbench.h"
#include "frep/workpieces.h"
#include "pieces/piece_art.h"

namespace emboss::test {

// The pen over the bench as a 1280x800 kiosk shows it (any 16:10 screen frames the sheet the same
// way), written as evemu text of a Wacom Intuos4 6x9: strokes and taps in sheet millimetres,
// through the kiosk's own mapping, and presses of the barrel button.
class PenRecording {
 public:
  explicit PenRecording(const std::string& about)
      : plate_(std::make_shared<Plate>(60.0, 40.0, 0.5)),
        spec_(benchCamera(plate_->bounds(), 1280, 800, 0.78, benchSideRoom(800))),
        cam_(spec_, 1280, 800),
        area_(tabletArea(sheetOnScreen(cam_, plate_->bounds()), 1.6)) {
    out_ = "# EVEMU 1.3\n# " + about + " for emboss-kiosk tests (tests/app/demo_recording.h)\n"
           "N: Wacom Intuos4 6x9 Pen\nI: 0003 056a 00b9 0100\nP: 01 00 00 00 00 00 00 00\n"
           "B: 00 0b 00 00 00 00 00 00 00\nB: 01 00 00 00 00 00 00 00 00\nB: 01 00 00 00 00 00 00 00 00\n"
           "B: 01 00 00 00 00 00 00 00 00\nB: 01 00 00 00 00 00 00 00 00\nB: 01 00 00 1f 00 00 00 00 00\n"
           "B: 01 df 1c 00 00 00 00 00 00\nB: 01 00 00 00 00 00 00 00 00\nB: 01 00 00 00 00 00 00 00 00\n"
           "B: 01 00 00 00 00 00 00 00 00\nB: 01 00 00 00 00 00 00 00 00\nB: 01 00 00 00 00 00 00 00 00\n"
           "B: 01 00 00 00 00 00 00 00 00\nB: 02 00 01 00 00 00 00 00 00\nB: 03 67 01 00 0f 00 01 00 00\n"
           "B: 04 01 00 00 00 00 00 00 00\nB: 05 00 00 00 00 00 00 00 00\nB: 11 00 00 00 00 00 00 00 00\n"
           "B: 12 00 00 00 00 00 00 00 00\nB: 14 00 00 00 00 00 00 00 00\nB: 15 00 00 00 00 00 00 00 00\n"
           "B: 15 00 00 00 00 00 00 00 00\nA: 00 0 44704 4 0 200\nA: 01 0 27940 4 0 200\n"
           "A: 18 0 2047 0 0 0\nA: 19 0 63 0 0 0\n";
  }
  void event(int type, int code, long value) {
    char buf[96];
    const long long us = std::llround(t_ * 1e6);  // whole microseconds, so usec never reads 1000000
    const long sec = static_cast<long>(us / 1000000), usec = static_cast<long>(us % 1000000);
    std::snprintf(buf, sizeof buf, "E: %ld.%06ld %04x %04x %ld\n", sec, usec, type, code, value);
    out_ += buf;
  }
  void frame(double advance) {
    event(0, 0, 0);
    t_ += advance;
  }
  // Sheet millimetres -> tablet counts, through the kiosk's own mapping.
  void toTablet(Vec2 p) {
    const auto s = cam_.project({p.x, p.y, 0.5});
    const double u = (s->x - area_.x) / area_.w, v = (s->y - area_.y) / area_.h;
    tx_ = std::lround(std::clamp(u, 0.0, 1.0) * kMaxX), ty_ = std::lround(std::clamp(v, 0.0, 1.0) * kMaxY);
  }
  void hoverTo(Vec2 p) {
    toTablet(p);
    event(3, 0x00, tx_), event(3, 0x01, ty_), event(3, 0x19, 20);
    frame(0.12);
  }
  void stroke(const art::Path& path, double pressure) {
    hoverTo(path.front());
    const auto pts = art::resampleEvery(path, 0.45);  // ~90 mm/s at 200 samples a second
    for (size_t i = 0; i < pts.size(); ++i) {
      toTablet(pts[i]);
      const double ramp = std::min({1.0, (i + 1) / 6.0, (pts.size() - i) / 6.0});
      const double p = pressure * (0.55 + 0.45 * ramp) * (1.0 + 0.06 * std::sin(i * 0.3));
      event(3, 0x00, tx_), event(3, 0x01, ty_), event(3, 0x18, std::lround(std::clamp(p, 0.0, 1.0) * kMaxP));
      if (i == 0) event(3, 0x19, 0), event(1, 0x14a, 1);
      frame(0.005);
    }
    event(3, 0x18, 0), event(1, 0x14a, 0), event(3, 0x19, 12);
    frame(0.15);
  }
  void tap(Vec2 p, double pressure) { stroke({p}, pressure); }
  void barrel(int times) {
    for (int i = 0; i < times; ++i) {
      event(1, 0x14b, 1), frame(0.08);
      event(1, 0x14b, 0), frame(0.12);
    }
  }
  // The pen comes into range over the sheet's centre.
  void penIn() {
    toTablet({0, 0});
    event(1, 0x140, 1), event(3, 0x00, tx_), event(3, 0x01, ty_), event(3, 0x19, 40);
    frame(0.2);
  }
  // The pen leaves; the recording's text.
  std::string penOut() {
    event(1, 0x140, 0);
    frame(0.1);
    return out_;
  }

 private:
  static constexpr int kMaxX = 44704, kMaxY = 27940, kMaxP = 2047;
  std::shared_ptr<Plate> plate_;
  CameraSpec spec_;
  Camera cam_;
  ScreenBox area_;
  std::string out_;
  double t_ = 1000.0;  // seconds
  long tx_ = 0, ty_ = 0;
};

inline std::string visitorDemoRecording() {
  PenRecording rec("A synthetic visitor session");
  rec.penIn();
  const Vec2 c{-6, 4};
  const art::Path petal = art::spline({{4, 0}, {8, -4.2}, {15, -5.2}, {20, -2.5}, {21.5, 0}, {20, 2.5}, {15, 5.2}, {8, 4.2}}, true, 0.5);
  std::vector<art::Path> petals;
  for (int i = 0; i < 6; ++i) petals.push_back(art::transform(petal, 1.0, 90 + i * 60.0, c));
  const art::Path leaf = art::spline({{0, 0}, {5, 3.5}, {12, 3.2}, {17, 0}, {12, -2.4}, {5, -2.6}}, true, 0.5);
  const art::Path leafL = art::transform(leaf, 1.0, 160, {c.x - 3, c.y - 30});
  const art::Path leafR = art::transform(leaf, 1.0, 20, {c.x + 2, c.y - 36});
  const art::Path stem = art::spline({{c.x, c.y - 22}, {c.x - 2, c.y - 30}, {c.x + 1, c.y - 38}}, false, 0.5);
  // 1. The tracer (a visitor's first tool): petals, heart, stem, leaves.
  for (const auto& p : petals) rec.stroke(p, 0.7);
  rec.stroke(art::circle(c, 4.2, 0.5), 0.7);
  rec.stroke(stem, 0.75);
  rec.stroke(leafL, 0.65);
  rec.stroke(leafR, 0.65);
  // 2. Eight presses to the region raiser: the petals and leaves raised from behind.
  rec.barrel(8);
  for (const auto& p : petals) rec.stroke(art::offsetContour(p, -0.8), 0.9);
  rec.stroke(art::offsetContour(leafL, -0.6), 0.8);
  rec.stroke(art::offsetContour(leafR, -0.6), 0.8);
  // 3. Ten presses on, round the catalogue past the patina brushes, to the punch: the heart as a boss.
  rec.barrel(10);
  rec.tap(c, 0.85);
  // 4. Fourteen more, round again, to the small punch: beads struck around the flower, half way round so far.
  rec.barrel(14);
  for (int i = 0; i <= 14; ++i) rec.tap({c.x + 30 * std::cos((200 + i * 10) * M_PI / 180), c.y + 30 * std::sin((200 + i * 10) * M_PI / 180)}, 0.7);
  return rec.penOut();
}

// Six raised regions over most of the sheet, one inside the other (ellipses of 24 x 15 mm in
// radius down to 14 x 9, 290 contour points each): the field work a stroke can bring at most on
// the bench (Renderer::continueField). Written to tests/app/data/big-regions.events.
inline std::string bigRegionsRecording() {
  PenRecording rec("Six raised regions over most of the sheet");
  rec.penIn();
  rec.barrel(8);  // to the region raiser
  for (int k = 0; k < 6; ++k) {
    const double rx = 24.0 - 2.0 * k, ry = 15.0 - 1.2 * k, cx = k % 2 ? 1.5 : -1.5;
    art::Path e;
    for (int i = 0; i <= 60; ++i) e.push_back({cx + rx * std::cos(i * M_PI / 30), ry * std::sin(i * M_PI / 30)});
    rec.stroke(e, 0.9);
    rec.frame(0.8);
  }
  // Seven presses more: round the catalogue's fifteen tools to the one it started with, so that it
  // can be played again and again (emboss bench --kiosk plays it five times on one sheet).
  rec.barrel(7);
  return rec.penOut();
}

}  // namespace emboss::test
