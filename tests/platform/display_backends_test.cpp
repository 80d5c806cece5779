// Tests of the display back ends: headless EGL and OSMesa pixels (frame, dirty rectangles,
// overlay), clear failures of kms and x11 here, x11 under Xvfb when present, and the factory.
#include <gtest/gtest.h>

#include <poll.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "display/display_factory.h"
#include "gl/gl_egl.h"
#include "display/display_headless.h"
#include "display/display_kms.h"
#include "display/display_osmesa.h"
#include "display/display_x11.h"
#include "gl/gl_text.h"
#include "test_support.h"

// Xlib last: its macros (Status, Bool, None) must not reach the headers above.
#include <X11/Xlib.h>
#include <X11/keysym.h>
#undef Status
#undef Bool

namespace emboss {
namespace {

constexpr int kW = 320;
constexpr int kH = 200;

Image patternFrame(int w, int h) {
  Image img(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      p[0] = static_cast<std::uint8_t>(x * 255 / (w - 1));
      p[1] = static_cast<std::uint8_t>(y * 255 / (h - 1));
      p[2] = static_cast<std::uint8_t>((x * 7 + y * 13) & 255);
      p[3] = 255;
    }
  }
  return img;
}

Image solidFrame(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  Image img(w, h);
  for (int i = 0; i < w * h; ++i) {
    img.rgba[i * 4 + 0] = r;
    img.rgba[i * 4 + 1] = g;
    img.rgba[i * 4 + 2] = b;
    img.rgba[i * 4 + 3] = 255;
  }
  return img;
}

void fillRect(Image& img, const Rect& r, std::uint8_t red, std::uint8_t green, std::uint8_t blue) {
  for (int y = r.y; y < r.y + r.h; ++y) {
    for (int x = r.x; x < r.x + r.w; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      p[0] = red;
      p[1] = green;
      p[2] = blue;
      p[3] = 255;
    }
  }
}

bool inside(const Rect& r, int x, int y) { return x >= r.x && y >= r.y && x < r.x + r.w && y < r.y + r.h; }

std::string rgbAt(const Image& img, int x, int y) {
  const std::uint8_t* p = img.pixel(x, y);
  return "(" + std::to_string(p[0]) + "," + std::to_string(p[1]) + "," + std::to_string(p[2]) + ")";
}

// Counts pixels that differ from `expected` outside every rectangle of `except`; reports the first.
int differencesOutside(const Image& got, const Image& expected, const std::vector<Rect>& except, std::string* first) {
  int count = 0;
  for (int y = 0; y < got.height; ++y) {
    for (int x = 0; x < got.width; ++x) {
      if (std::any_of(except.begin(), except.end(), [&](const Rect& r) { return inside(r, x, y); })) continue;
      if (std::memcmp(got.pixel(x, y), expected.pixel(x, y), 3) != 0) {
        if (count++ == 0 && first != nullptr) {
          *first = "at " + std::to_string(x) + "," + std::to_string(y) + ": got " + rgbAt(got, x, y) +
                    ", expected " + rgbAt(expected, x, y);
        }
      }
    }
  }
  return count;
}

::testing::AssertionResult colorNear(const Image& img, int x, int y, int r, int g, int b, int tolerance = 2) {
  const std::uint8_t* p = img.pixel(x, y);
  if (std::abs(p[0] - r) <= tolerance && std::abs(p[1] - g) <= tolerance && std::abs(p[2] - b) <= tolerance) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "pixel " << x << "," << y << " is " << rgbAt(img, x, y) << ", expected ("
                                       << r << "," << g << "," << b << ") +-" << tolerance;
}

// ---- headless and osmesa: the same pixel checks for both

struct BackendCase {
  const char* kind;
  bool rowLength;
};

class DisplayPixels : public ::testing::TestWithParam<BackendCase> {
 protected:
  std::unique_ptr<Display> open(int w = kW, int h = kH) {
    GlPresenterSettings settings;
    settings.allowRowLengthUpload = GetParam().rowLength;
    auto d = std::string(GetParam().kind) == "osmesa" ? createOsmesaDisplay(w, h, settings)
                                                      : createHeadlessDisplay(w, h, settings);
    EXPECT_TRUE(d.ok()) << (d.ok() ? "" : d.error());
    return d.ok() ? std::move(*d) : nullptr;
  }
};

TEST_P(DisplayPixels, StartsWithItsNameAndSize) {
  auto display = open();
  ASSERT_TRUE(display);
  EXPECT_EQ(display->width(), kW);
  EXPECT_EQ(display->height(), kH);
  const std::string name = display->name();
  if (std::string(GetParam().kind) == "osmesa") {
    EXPECT_EQ(name.rfind("osmesa (software GL, ", 0), 0u) << name;
  } else {
    EXPECT_EQ(name.rfind("headless (EGL surfaceless, ", 0), 0u) << name;
  }
  EXPECT_NE(name.find("llvmpipe"), std::string::npos) << name;
}

TEST_P(DisplayPixels, ShowsTheFramePixelExact) {
  auto display = open();
  ASSERT_TRUE(display);
  const Image frame = patternFrame(kW, kH);
  ASSERT_TRUE(display->present(frame, {}, Overlay{}));
  const Image shot = display->screenshot();
  ASSERT_EQ(shot.width, kW);
  ASSERT_EQ(shot.height, kH);
  std::string first;
  EXPECT_EQ(differencesOutside(shot, frame, {}, &first), 0) << first;
  EXPECT_EQ(shot.pixel(5, 5)[3], 255);
}

TEST_P(DisplayPixels, UploadsOnlyTheDirtyRectangles) {
  auto display = open();
  ASSERT_TRUE(display);
  const Image first = patternFrame(kW, kH);
  ASSERT_TRUE(display->present(first, {}, Overlay{}));

  // Change two areas of the frame, but declare only one dirty: only that one may reach the screen.
  Image second = first;
  const Rect dirty{37, 21, 53, 41};  // odd sizes: neither aligned nor full rows
  fillRect(second, dirty, 250, 10, 200);
  fillRect(second, Rect{200, 120, 40, 30}, 0, 255, 0);  // not declared
  ASSERT_TRUE(display->present(second, std::vector<Rect>{dirty}, Overlay{}));
  Image shot = display->screenshot();
  std::string where;
  EXPECT_EQ(differencesOutside(shot, first, {dirty}, &where), 0) << where;
  for (int y = dirty.y; y < dirty.y + dirty.h; ++y) {
    for (int x = dirty.x; x < dirty.x + dirty.w; ++x) {
      ASSERT_TRUE(colorNear(shot, x, y, 250, 10, 200, 0));
    }
  }

  // Full-width rows, a rectangle clipped at the frame's corner, and an empty one.
  Image third = second;
  const Rect rows{0, 180, kW, 10};
  fillRect(third, rows, 1, 2, 3);
  fillRect(third, Rect{300, 190, 20, 10}, 9, 9, 9);
  const std::vector<Rect> dirty3 = {rows, Rect{300, 190, 50, 50}, Rect{10, 10, 0, 5}};
  ASSERT_TRUE(display->present(third, dirty3, Overlay{}));
  shot = display->screenshot();
  Image expected = first;
  fillRect(expected, dirty, 250, 10, 200);
  fillRect(expected, rows, 1, 2, 3);
  fillRect(expected, Rect{300, 190, 20, 10}, 9, 9, 9);
  EXPECT_EQ(differencesOutside(shot, expected, {}, &where), 0) << where;

  // No dirty rectangles: the picture stays as it was even if the frame changed.
  Image fourth = third;
  fillRect(fourth, Rect{0, 0, kW, kH}, 0, 0, 0);
  ASSERT_TRUE(display->present(fourth, {}, Overlay{}));
  shot = display->screenshot();
  EXPECT_EQ(differencesOutside(shot, expected, {}, &where), 0) << where;
}

TEST_P(DisplayPixels, DrawsTheOverlayWhereAsked) {
  auto display = open();
  ASSERT_TRUE(display);
  const Image frame = solidFrame(kW, kH, 30, 30, 30);
  Overlay overlay;
  overlay.rects.push_back({20, 20, 80, 40, {1, 0, 0, 1}, 0});       // sharp red box
  overlay.rects.push_back({120, 20, 80, 40, {0, 1, 0, 1}, 14});     // rounded green box
  overlay.rects.push_back({220, 20, 60, 40, {1, 1, 1, 0.5f}, 0});   // half-transparent white
  overlay.rings.push_back({240, 130, 30, 4, {0, 0, 1, 1}});         // blue ring
  overlay.texts.push_back({20, 120, 30, "HHH", {1, 1, 1, 1}});      // white capitals
  ASSERT_TRUE(display->present(frame, {}, overlay));
  const Image shot = display->screenshot();

  // The sharp box covers exactly [20,100) x [20,60).
  EXPECT_TRUE(colorNear(shot, 20, 20, 255, 0, 0, 0));
  EXPECT_TRUE(colorNear(shot, 99, 59, 255, 0, 0, 0));
  EXPECT_TRUE(colorNear(shot, 60, 40, 255, 0, 0, 0));
  EXPECT_TRUE(colorNear(shot, 19, 40, 30, 30, 30, 0));
  EXPECT_TRUE(colorNear(shot, 100, 40, 30, 30, 30, 0));
  EXPECT_TRUE(colorNear(shot, 60, 60, 30, 30, 30, 0));
  // The rounded box: solid inside and along its straight edges, background at its corners.
  EXPECT_TRUE(colorNear(shot, 160, 40, 0, 255, 0));
  EXPECT_TRUE(colorNear(shot, 121, 40, 0, 255, 0));
  EXPECT_TRUE(colorNear(shot, 120, 20, 30, 30, 30));
  EXPECT_TRUE(colorNear(shot, 199, 59, 30, 30, 30));
  EXPECT_TRUE(colorNear(shot, 123, 23, 30, 30, 30));
  // Half-transparent white over 30: about 142.
  EXPECT_TRUE(colorNear(shot, 250, 40, 142, 142, 142, 3));
  // The ring: on the circle in all four directions, not in the middle or between.
  EXPECT_TRUE(colorNear(shot, 270, 130, 0, 0, 255));
  EXPECT_TRUE(colorNear(shot, 209, 130, 0, 0, 255));
  EXPECT_TRUE(colorNear(shot, 240, 100, 0, 0, 255));
  EXPECT_TRUE(colorNear(shot, 240, 159, 0, 0, 255));
  EXPECT_TRUE(colorNear(shot, 240, 130, 30, 30, 30, 0));
  EXPECT_TRUE(colorNear(shot, 255, 130, 30, 30, 30, 0));
  EXPECT_TRUE(colorNear(shot, 240, 80, 30, 30, 30, 0));

  // The text: bright pixels fill a box from the top of the capitals (y=120) to the baseline
  // (y=150), starting near x=20, and nothing bright lies outside it.
  int minX = kW, maxX = -1, minY = kH, maxY = -1, bright = 0;
  for (int y = 70; y < kH; ++y) {
    for (int x = 0; x < 200; ++x) {
      if (shot.pixel(x, y)[0] > 200 && shot.pixel(x, y)[2] > 200) {
        ++bright;
        minX = std::min(minX, x);
        maxX = std::max(maxX, x);
        minY = std::min(minY, y);
        maxY = std::max(maxY, y);
      }
    }
  }
  EXPECT_GT(bright, 200);
  EXPECT_NEAR(minY, 120, 1);
  EXPECT_NEAR(maxY, 149, 1);
  EXPECT_NEAR(minX, 23, 3);
  EXPECT_GT(maxX, 20 + 3 * 25);
  EXPECT_LT(maxX, 20 + 3 * 40);

  // Everything away from the overlay is the frame.
  std::string where;
  const std::vector<Rect> overlayAreas = {{18, 18, 184, 44}, {218, 18, 64, 44}, {206, 96, 68, 68}, {18, 110, 140, 50}};
  EXPECT_EQ(differencesOutside(shot, frame, overlayAreas, &where), 0) << where;
}

TEST_P(DisplayPixels, KeepsTheOverlayAcrossScreenshotsAndFrames) {
  auto display = open();
  ASSERT_TRUE(display);
  Overlay overlay;
  overlay.rects.push_back({10, 10, 20, 20, {1, 1, 0, 1}, 0});
  ASSERT_TRUE(display->present(solidFrame(kW, kH, 0, 0, 0), {}, overlay));
  EXPECT_TRUE(colorNear(display->screenshot(), 15, 15, 255, 255, 0, 0));
  EXPECT_TRUE(colorNear(display->screenshot(), 15, 15, 255, 255, 0, 0));  // twice: nothing consumed
  // A new frame with an empty overlay: the box is gone, the picture underneath is back.
  ASSERT_TRUE(display->present(solidFrame(kW, kH, 0, 0, 0), {}, Overlay{}));
  EXPECT_TRUE(colorNear(display->screenshot(), 15, 15, 0, 0, 0, 0));
}

TEST_P(DisplayPixels, RejectsAFrameWithoutPixelsWithoutCrashing) {
  auto display = open();
  ASSERT_TRUE(display);
  Image broken;
  broken.width = kW;
  broken.height = kH;  // no pixel buffer
  EXPECT_FALSE(display->present(broken, {}, Overlay{}));
  EXPECT_TRUE(display->present(patternFrame(kW, kH), {}, Overlay{}));
}

INSTANTIATE_TEST_SUITE_P(Backends, DisplayPixels,
                         ::testing::Values(BackendCase{"headless", true}, BackendCase{"headless", false},
                                           BackendCase{"osmesa", true}, BackendCase{"osmesa", false}),
                         [](const ::testing::TestParamInfo<BackendCase>& info) {
                           return std::string(info.param.kind) + (info.param.rowLength ? "RowLength" : "Packed");
                         });

// ---- the presenter's upload bookkeeping, straight on an EGL surfaceless context

// A surfaceless EGL context made current (skipped without Mesa's surfaceless platform).
class GlPresenterUploads : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!hasEglExtension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")) GTEST_SKIP() << "no Mesa surfaceless EGL";
    auto opened = EglSession::open(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, "test");
    ASSERT_TRUE(opened.ok()) << opened.error();
    session = std::move(*opened);
    ASSERT_TRUE(session->createContext(EGL_PBUFFER_BIT).ok());
    ASSERT_TRUE(session->makeCurrent());
  }
  std::unique_ptr<EglSession> session;
};

TEST_F(GlPresenterUploads, SendsOnlyTheDirtyPixels) {
  for (bool rowLength : {true, false}) {
    GlPresenterSettings settings;
    settings.allowRowLengthUpload = rowLength;
    auto presenter = GlPresenter::create(session->procLoader(), GlFlavor::kGles2, kW, kH, true, settings);
    ASSERT_TRUE(presenter.ok()) << presenter.error();
    GlPresenter& p = **presenter;
    if (!rowLength) {
      EXPECT_STREQ(p.uploadPath(), "packed copy");
    }
    const Image frame = patternFrame(kW, kH);
    ASSERT_TRUE(p.draw(frame, {}, Overlay{}));
    EXPECT_EQ(p.stats().fullUploads, 1u);
    EXPECT_EQ(p.stats().uploadedPixels, static_cast<std::uint64_t>(kW * kH));
    const std::vector<Rect> dirty = {{10, 10, 7, 5}, {300, 190, 100, 100}, {0, 50, kW, 2}};
    ASSERT_TRUE(p.draw(frame, dirty, Overlay{}));
    EXPECT_EQ(p.stats().fullUploads, 1u);
    EXPECT_EQ(p.stats().rectUploads, 3u);
    EXPECT_EQ(p.stats().uploadedPixels, static_cast<std::uint64_t>(kW * kH + 7 * 5 + 20 * 10 + kW * 2));
    // A frame of another size is uploaded whole (the "after a resize" case) and scaled to fit.
    ASSERT_TRUE(p.draw(solidFrame(kW / 2, kH / 2, 200, 100, 50), {}, Overlay{}));
    EXPECT_EQ(p.stats().fullUploads, 2u);
    EXPECT_TRUE(colorNear(p.screenshot(), kW - 1, kH - 1, 200, 100, 50, 0));
  }
}

// An offscreen target keeps its pixels: after the first frame only the damage is drawn again (the
// dirty rectangles, the old and new places of the shapes that changed), and the picture is the
// one a fresh presenter draws whole, pixel for pixel.
TEST_F(GlPresenterUploads, DrawsAgainOnlyWhatChangedWithTheSamePixels) {
  auto a = GlPresenter::create(session->procLoader(), GlFlavor::kGles2, kW, kH, true);
  ASSERT_TRUE(a.ok()) << a.error();
  GlPresenter& p = **a;
  const long screen = static_cast<long>(kW) * kH;
  Image frame = patternFrame(kW, kH);
  Overlay overlay;
  overlay.rects.push_back({10, 10, 60, 20, {0.1f, 0.2f, 0.9f, 0.8f}, 6});  // a panel that stays
  overlay.rects.push_back({kW - 20.0f, 40, 8, 100, {1, 1, 1, 0.9f}, 4});    // a bar that grows
  overlay.rings.push_back({100, 100, 12, 3, {1, 0.6f, 0.1f, 1}});           // the pen's ring
  overlay.texts.push_back({20, kH - 40.0f, 14, "Copper", {1, 1, 1, 1}});
  ASSERT_TRUE(p.draw(frame, {}, overlay));
  EXPECT_EQ(static_cast<long>(p.stats().drawnPixels), screen);

  // The ring moves, the bar grows, a rectangle of the frame changes.
  overlay.rings[0].cx = 140, overlay.rings[0].cy = 90;
  overlay.rects[1].h = 120;
  const Rect changed{150, 150, 30, 20};
  for (int y = changed.y; y < changed.y + changed.h; ++y)
    for (int x = changed.x; x < changed.x + changed.w; ++x) frame.pixel(x, y)[0] = 255, frame.pixel(x, y)[1] = 0;
  const std::vector<Rect> dirty{changed};
  ASSERT_TRUE(p.draw(frame, dirty, overlay));
  const long second = static_cast<long>(p.stats().drawnPixels) - screen;
  EXPECT_GT(second, 30 * 20);
  EXPECT_LT(second, screen / 5) << "only the damage is drawn again";
  EXPECT_EQ(p.stats().partialFrames, 1u);

  // Nothing changed: nothing is drawn.
  const auto before = p.stats().drawnPixels;
  ASSERT_TRUE(p.draw(frame, {}, overlay));
  EXPECT_EQ(p.stats().drawnPixels, before);
  const Image shot = p.screenshot();

  // The same picture drawn whole by a fresh presenter.
  auto b = GlPresenter::create(session->procLoader(), GlFlavor::kGles2, kW, kH, true);
  ASSERT_TRUE(b.ok()) << b.error();
  ASSERT_TRUE((*b)->draw(frame, {}, overlay));
  const Image whole = (*b)->screenshot();
  std::string where;
  EXPECT_EQ(differencesOutside(shot, whole, {}, &where), 0) << where;

  // A text that changes redraws everything.
  overlay.texts[0].text = "Brass";
  const auto beforeText = p.stats().drawnPixels;
  ASSERT_TRUE(p.draw(frame, {}, overlay));
  EXPECT_EQ(static_cast<long>(p.stats().drawnPixels - beforeText), screen);
}

// ---- text layout without GL

TEST(GlyphAtlasLayout, PutsTheTopOfCapitalsAtYAndTheBaselineAtYPlusSize) {
  int uploads = 0;
  auto atlas = GlyphAtlas::create("", [&](int, int, int w, int h, const std::uint8_t*) {
    EXPECT_GT(w, 0);
    EXPECT_GT(h, 0);
    ++uploads;
  });
  ASSERT_TRUE(atlas.ok()) << atlas.error();
  std::vector<PlacedGlyph> placed;
  ASSERT_TRUE((*atlas)->layout("H H", 10, 20, 30, placed));
  ASSERT_EQ(placed.size(), 2u);  // the space has no bitmap
  EXPECT_EQ(uploads, 1);         // one H, packed once
  EXPECT_EQ(placed[0].y, 20);
  EXPECT_NEAR(placed[0].y + placed[0].glyph->height, 50, 1);
  EXPECT_NEAR(placed[0].x, 12, 3);
  EXPECT_GT(placed[1].x, placed[0].x + placed[0].glyph->width);
  const float one = (*atlas)->measure("H", 30);
  EXPECT_GT(one, 20);
  EXPECT_LT(one, 40);
  EXPECT_NEAR((*atlas)->measure("HHHH", 30), 4 * one, 1);
  EXPECT_NEAR((*atlas)->measure("HH\nH", 30), 2 * one, 1);
  EXPECT_FLOAT_EQ(measureOverlayText("HHHH", 30), (*atlas)->measure("HHHH", 30));
  EXPECT_EQ(measureOverlayText("H", 30, "/nonexistent/font.ttf"), 0.0f);
}

TEST(GlyphAtlasLayout, ReportsAFullAtlasAndRecoversAfterReset) {
  auto atlas = GlyphAtlas::create("", nullptr);
  ASSERT_TRUE(atlas.ok()) << atlas.error();
  std::vector<PlacedGlyph> placed;
  EXPECT_FALSE((*atlas)->layout("ABCDEFGHIJKLMNOPQRSTUVWXYZ", 0, 0, 280, placed));
  (*atlas)->reset();
  placed.clear();
  EXPECT_TRUE((*atlas)->layout("W", 0, 0, 280, placed));
  EXPECT_EQ(placed.size(), 1u);
}

TEST(GlyphAtlasLayout, FailsClearlyWithoutTheFont) {
  auto atlas = GlyphAtlas::create("/nonexistent/font.ttf", nullptr);
  ASSERT_FALSE(atlas.ok());
  EXPECT_NE(atlas.error().find("overlay font: cannot load '/nonexistent/font.ttf'"), std::string::npos) << atlas.error();
}

TEST(GlyphAtlasLayout, DecodesUtf8) {
  const std::vector<char32_t> expected = {U'a', 0xE9, 0x20AC, 0x1F600, 0xFFFD, U'z'};
  EXPECT_EQ(decodeUtf8("a\xC3\xA9\xE2\x82\xAC\xF0\x9F\x98\x80\xFFz"), expected);
  EXPECT_EQ(decodeUtf8("\xE2\x82"), (std::vector<char32_t>{0xFFFD, 0xFFFD}));
}

// ---- kms: there is no GPU here

bool haveDrmCards() {
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator("/dev/dri", ec)) {
    if (e.path().filename().string().rfind("card", 0) == 0) return true;
  }
  return false;
}

TEST(DisplayKms, FailsClearlyWithoutACard) {
  if (haveDrmCards()) GTEST_SKIP() << "this machine has /dev/dri/card*; the no-card message cannot be checked here";
  const std::string expected = "kms: no /dev/dri/card* (no GPU driver loaded)";
  auto display = createKmsDisplay();
  ASSERT_FALSE(display.ok());
  EXPECT_EQ(display.error(), expected);
  auto probe = probeKmsOutput();
  ASSERT_FALSE(probe.ok());
  EXPECT_EQ(probe.error(), expected);
}

TEST(DisplayKms, WaitingReprobesEverySecondUntilTheTimeout) {
  if (haveDrmCards()) GTEST_SKIP() << "this machine has /dev/dri/card*; waiting might find a screen";
  int calls = 0;
  const auto start = std::chrono::steady_clock::now();
  auto display = waitForKmsDisplay(std::chrono::milliseconds(1200), {}, [&](const std::string& error) {
    EXPECT_EQ(error, "kms: no /dev/dri/card* (no GPU driver loaded)");
    ++calls;
    return true;
  });
  const auto took = std::chrono::steady_clock::now() - start;
  ASSERT_FALSE(display.ok());
  EXPECT_EQ(display.error(), "kms: no /dev/dri/card* (no GPU driver loaded) (waited 1 s for a display)");
  EXPECT_EQ(calls, 2);  // probes at 0 s, 1 s and 1.2 s; the callback runs before each wait
  EXPECT_GE(took, std::chrono::milliseconds(1150));
  EXPECT_LT(took, std::chrono::milliseconds(3000));

  auto givenUp = waitForKmsDisplay(std::chrono::hours(1), {}, [](const std::string&) { return false; });
  ASSERT_FALSE(givenUp.ok());
  EXPECT_EQ(givenUp.error(), "kms: no /dev/dri/card* (no GPU driver loaded) (gave up waiting)");
}

// ---- x11

// Sets or unsets an environment variable for one scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value != nullptr) setenv(name, value, 1);
    else unsetenv(name);
  }
  ~ScopedEnv() {
    if (old_) setenv(name_, old_->c_str(), 1);
    else unsetenv(name_);
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

TEST(DisplayX11, FailsClearlyWithoutDisplay) {
  ScopedEnv noDisplay("DISPLAY", nullptr);
  auto display = createX11Display(kW, kH);
  ASSERT_FALSE(display.ok());
  EXPECT_EQ(display.error(), "x11: $DISPLAY not set (no X server; on the kiosk use kms, for a test run use xvfb-run)");
}

TEST(DisplayX11, FailsClearlyWithoutAServer) {
  ScopedEnv badDisplay("DISPLAY", ":987");
  auto display = createX11Display(kW, kH);
  ASSERT_FALSE(display.ok());
  EXPECT_EQ(display.error().rfind("x11: cannot open display ':987' (is the X server running", 0), 0u)
      << display.error();
}

// An Xvfb on a display number it picks itself (-displayfd), stopped at the end of the scope.
class Xvfb {
 public:
  static std::optional<std::string> findBinary() {
    for (const char* p : {"/usr/bin/Xvfb", "/usr/local/bin/Xvfb"}) {
      if (::access(p, X_OK) == 0) return std::string(p);
    }
    return std::nullopt;
  }
  explicit Xvfb(const std::string& binary) {
    int fds[2];
    if (::pipe(fds) != 0) return;
    pid_ = ::fork();
    if (pid_ == 0) {
      ::close(fds[0]);
      const std::string fd = std::to_string(fds[1]);
      std::freopen("/dev/null", "w", stderr);
      ::execl(binary.c_str(), "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "640x480x24", "-nolisten", "tcp",
              static_cast<char*>(nullptr));
      ::_exit(127);
    }
    ::close(fds[1]);
    std::string number;
    pollfd p{fds[0], POLLIN, 0};
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (std::chrono::steady_clock::now() < deadline && ::poll(&p, 1, 100) >= 0) {
      if (!(p.revents & (POLLIN | POLLHUP))) continue;
      char c;
      if (::read(fds[0], &c, 1) != 1) break;
      if (c == '\n') {
        display_ = ":" + number;
        break;
      }
      number += c;
    }
    ::close(fds[0]);
  }
  ~Xvfb() { stop(); }
  void stop() {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      ::waitpid(pid_, nullptr, 0);
      pid_ = -1;
    }
  }
  const std::string& display() const { return display_; }

 private:
  pid_t pid_ = -1;
  std::string display_;
};

// Sends `event` to `window` as if the server had, from a second client.
void sendEvent(::Display* x, unsigned long window, XEvent event, long mask) {
  event.xany.window = window;
  event.xany.display = x;
  event.xany.send_event = 1;
  XSendEvent(x, window, 0, mask, &event);
  XFlush(x);
}

std::vector<X11Event> pollUntil(X11Display& display, std::size_t count, bool* open) {
  std::vector<X11Event> events;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(3);
  while (events.size() < count && std::chrono::steady_clock::now() < deadline) {
    *open = display.pollX11Events(events);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return events;
}

TEST(DisplayX11, WorksUnderXvfb) {
  const auto binary = Xvfb::findBinary();
  if (!binary) GTEST_SKIP() << "Xvfb not installed (apt install xvfb); x11 not tested";
  Xvfb server(*binary);
  ASSERT_FALSE(server.display().empty()) << "Xvfb did not start";
  ScopedEnv env("DISPLAY", server.display().c_str());

  auto created = createX11Display(kW, kH);
  ASSERT_TRUE(created.ok()) << created.error();
  Display& display = **created;
  EXPECT_EQ(display.name().rfind("x11 (EGL window 320x200, ", 0), 0u) << display.name();
  EXPECT_EQ(display.width(), kW);
  EXPECT_EQ(display.height(), kH);

  // The picture, a dirty rectangle and an overlay box, as on the other back ends.
  const Image frame = patternFrame(kW, kH);
  Overlay overlay;
  overlay.rects.push_back({10, 10, 20, 20, {1, 1, 0, 1}, 0});
  ASSERT_TRUE(display.present(frame, {}, overlay));
  Image second = frame;
  fillRect(second, Rect{100, 100, 30, 30}, 0, 0, 255);
  fillRect(second, Rect{200, 20, 30, 30}, 0, 255, 0);  // not declared dirty
  ASSERT_TRUE(display.present(second, std::vector<Rect>{{100, 100, 30, 30}}, overlay));
  const Image shot = display.screenshot();
  ASSERT_EQ(shot.width, kW);
  EXPECT_TRUE(colorNear(shot, 15, 15, 255, 255, 0, 0));
  EXPECT_TRUE(colorNear(shot, 110, 110, 0, 0, 255, 0));
  std::string where;
  EXPECT_EQ(differencesOutside(shot, frame, {{10, 10, 20, 20}, {100, 100, 30, 30}}, &where), 0) << where;

  // Input: the pen is the left button, keys come as keysym names.
  X11Display* x11 = asX11Display(&display);
  ASSERT_NE(x11, nullptr);
  ::Display* client = XOpenDisplay(server.display().c_str());
  ASSERT_NE(client, nullptr);
  const unsigned long window = x11->windowId();
  XEvent e{};
  e.xbutton.type = ButtonPress;
  e.xbutton.x = 10;
  e.xbutton.y = 20;
  e.xbutton.button = Button1;
  e.xbutton.same_screen = 1;
  sendEvent(client, window, e, ButtonPressMask);
  e = XEvent{};
  e.xmotion.type = MotionNotify;
  e.xmotion.x = 30;
  e.xmotion.y = 40;
  e.xmotion.state = Button1Mask;
  e.xmotion.same_screen = 1;
  sendEvent(client, window, e, PointerMotionMask);
  e = XEvent{};
  e.xbutton.type = ButtonRelease;
  e.xbutton.x = 31;
  e.xbutton.y = 41;
  e.xbutton.button = Button1;
  e.xbutton.same_screen = 1;
  sendEvent(client, window, e, ButtonReleaseMask);
  e = XEvent{};
  e.xkey.type = KeyPress;
  e.xkey.keycode = XKeysymToKeycode(client, XK_Escape);
  e.xkey.same_screen = 1;
  sendEvent(client, window, e, KeyPressMask);

  bool open = true;
  std::vector<X11Event> events = pollUntil(*x11, 4, &open);
  EXPECT_TRUE(open);
  ASSERT_EQ(events.size(), 4u);
  EXPECT_EQ(events[0].type, X11Event::Type::kPenDown);
  EXPECT_EQ(events[0].x, 10);
  EXPECT_EQ(events[0].y, 20);
  EXPECT_TRUE(events[0].penDown);
  EXPECT_EQ(events[1].type, X11Event::Type::kMove);
  EXPECT_EQ(events[1].x, 30);
  EXPECT_EQ(events[1].y, 40);
  EXPECT_TRUE(events[1].penDown);
  EXPECT_EQ(events[2].type, X11Event::Type::kPenUp);
  EXPECT_FALSE(events[2].penDown);
  EXPECT_EQ(events[3].type, X11Event::Type::kKey);
  EXPECT_EQ(events[3].key, "Escape");
  EXPECT_EQ(x11->input().x, 31);
  EXPECT_EQ(x11->input().y, 41);
  EXPECT_FALSE(x11->input().penDown);

  // The window manager's close button: a kClose event, then present() reports the output gone.
  e = XEvent{};
  e.xclient.type = ClientMessage;
  e.xclient.message_type = XInternAtom(client, "WM_PROTOCOLS", 0);
  e.xclient.format = 32;
  e.xclient.data.l[0] = static_cast<long>(XInternAtom(client, "WM_DELETE_WINDOW", 0));
  sendEvent(client, window, e, NoEventMask);
  events = pollUntil(*x11, 1, &open);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, X11Event::Type::kClose);
  EXPECT_FALSE(open);
  EXPECT_FALSE(display.present(frame, {}, overlay));
  XCloseDisplay(client);
}

TEST(DisplayX11, ReportsALostServerWithoutCrashing) {
  const auto binary = Xvfb::findBinary();
  if (!binary) GTEST_SKIP() << "Xvfb not installed (apt install xvfb); x11 not tested";
  Xvfb server(*binary);
  ASSERT_FALSE(server.display().empty()) << "Xvfb did not start";
  ScopedEnv env("DISPLAY", server.display().c_str());
  auto created = createX11Display(kW, kH);
  ASSERT_TRUE(created.ok()) << created.error();
  const Image frame = patternFrame(kW, kH);
  ASSERT_TRUE((*created)->present(frame, {}, Overlay{}));
  server.stop();
  bool lost = false;
  for (int i = 0; i < 20 && !lost; ++i) {
    lost = !(*created)->present(frame, {}, Overlay{});
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_TRUE(lost);
  EXPECT_FALSE((*created)->present(frame, {}, Overlay{}));  // and stays lost
  created->reset();                                          // and closes without crashing
}

// ---- the factory

TEST(DisplayFactory, AutoFallsThroughToHeadlessHere) {
  if (haveDrmCards()) GTEST_SKIP() << "this machine has a GPU card; auto may pick kms";
  ScopedEnv noDisplay("DISPLAY", nullptr);
  std::string log;
  auto display = createDisplay("auto", kW, kH, &log);
  ASSERT_TRUE(display.ok()) << display.error();
  EXPECT_EQ((*display)->name().rfind("headless (EGL surfaceless, ", 0), 0u) << (*display)->name();
  EXPECT_EQ((*display)->width(), kW);
  EXPECT_EQ((*display)->height(), kH);
  EXPECT_EQ(log,
            "kms: no /dev/dri/card* (no GPU driver loaded)\n"
            "x11: $DISPLAY not set (no X server; on the kiosk use kms, for a test run use xvfb-run)\n"
            "headless: started " + (*display)->name() + " 320x200\n");
}

TEST(DisplayFactory, StartsTheKindAskedFor) {
  std::string log;
  auto display = createDisplay("osmesa", kW, kH, &log);
  ASSERT_TRUE(display.ok()) << display.error();
  EXPECT_EQ((*display)->name().rfind("osmesa (", 0), 0u);
  EXPECT_EQ(log, "osmesa: started " + (*display)->name() + " 320x200\n");
  EXPECT_EQ(displayKinds(), (std::vector<std::string>{"auto", "kms", "x11", "headless", "osmesa"}));
}

TEST(DisplayFactory, NamesTheKindsItKnows) {
  std::string log;
  auto display = createDisplay("wayland", kW, kH, &log);
  ASSERT_FALSE(display.ok());
  EXPECT_EQ(display.error(), "display: unknown kind 'wayland' (use auto, kms, x11, headless or osmesa)");
  EXPECT_EQ(log, display.error() + "\n");
}

TEST(DisplayFactory, ExplicitKindFailsWithThatKindsReason) {
  ScopedEnv noDisplay("DISPLAY", nullptr);
  auto display = createDisplay("x11", kW, kH, nullptr);
  ASSERT_FALSE(display.ok());
  EXPECT_EQ(display.error().rfind("x11: $DISPLAY not set", 0), 0u) << display.error();
}

// ---- a picture to look at: a sample frame under the kiosk's tool panel

Image sampleMetalFrame(int w, int h) {
  Image img(w, h);
  const float cx = w * 0.45f, cy = h * 0.55f;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      // Brushed copper with a soft embossed ring and a groove, lit from the top left.
      const float dx = x - cx, dy = y - cy;
      const float d = std::sqrt(dx * dx + dy * dy);
      const float bump = std::exp(-std::pow((d - h * 0.22f) / 14.0f, 2.0f));
      const float groove = -0.6f * std::exp(-std::pow((y - h * 0.25f - 0.15f * x) / 5.0f, 2.0f));
      const float slope = (dx + dy) / (d + 1e-3f) * bump * ((d - h * 0.22f) / 14.0f) * -0.8f + groove * 0.5f;
      const float brushed = 0.04f * std::sin(y * 1.7f + std::sin(x * 0.05f) * 3.0f);
      const float light = std::clamp(0.62f + slope * 0.9f + brushed + 0.15f * (1.0f - float(y) / h), 0.0f, 1.0f);
      std::uint8_t* p = img.pixel(x, y);
      p[0] = static_cast<std::uint8_t>(std::clamp(light * 255.0f * 1.00f, 0.0f, 255.0f));
      p[1] = static_cast<std::uint8_t>(std::clamp(light * 255.0f * 0.62f, 0.0f, 255.0f));
      p[2] = static_cast<std::uint8_t>(std::clamp(light * 255.0f * 0.42f, 0.0f, 255.0f));
      p[3] = 255;
    }
  }
  return img;
}

Overlay sampleToolOverlay(int w, int h) {
  Overlay o;
  const OverlayColor panel{0.08f, 0.09f, 0.11f, 0.82f};
  const OverlayColor white{1, 1, 1, 1};
  const OverlayColor dim{0.75f, 0.78f, 0.82f, 1};
  const OverlayColor accent{0.98f, 0.62f, 0.25f, 1};
  // Tool panel along the top left.
  o.rects.push_back({24, 24, 470, 76, panel, 18});
  o.rects.push_back({40, 44, 36, 36, accent, 18});  // the tool's colour dot
  o.texts.push_back({92, 50, 24, "Tracer  2 mm  Copper", white});
  // Pressure bar on the right edge.
  const float bx = w - 70.0f, by = 120.0f, bh = h - 240.0f;
  o.rects.push_back({bx - 16, by - 48, 64, bh + 76, panel, 16});
  o.rects.push_back({bx, by, 32, bh, {1, 1, 1, 0.18f}, 16});
  o.rects.push_back({bx, by + bh * 0.35f, 32, bh * 0.65f, accent, 16});
  o.texts.push_back({bx + 16 - measureOverlayText("Press", 14) / 2, by - 34, 14, "Press", dim});
  // The footprint ring under the pen, with a thin dark outline so it reads on bright metal.
  o.rings.push_back({w * 0.62f, h * 0.42f, 23, 6, {0, 0, 0, 0.45f}});
  o.rings.push_back({w * 0.62f, h * 0.42f, 23, 3, white});
  o.rects.push_back({w * 0.62f - 3, h * 0.42f - 3, 6, 6, white, 3});
  // A hint line at the bottom.
  const char* hint = "Press harder for a deeper line";
  o.rects.push_back({24, h - 64.0f, measureOverlayText(hint, 18) + 40, 40, panel, 20});
  o.texts.push_back({44, h - 53.0f, 18, hint, dim});
  return o;
}

TEST(DisplayDemo, WritesAScreenshotOfTheToolPanel) {
  constexpr int kDemoW = 800, kDemoH = 500;
  auto display = createHeadlessDisplay(kDemoW, kDemoH);
  ASSERT_TRUE(display.ok()) << display.error();
  const Image frame = sampleMetalFrame(kDemoW, kDemoH);
  const Overlay overlay = sampleToolOverlay(kDemoW, kDemoH);
  ASSERT_TRUE((*display)->present(frame, {}, overlay));
  const Image shot = (*display)->screenshot();
  // The panel darkens the metal, the text is bright on it, the metal far from the overlay is as sent.
  EXPECT_LT(shot.pixel(30, 90)[0], 60);
  EXPECT_TRUE(colorNear(shot, 400, 300, frame.pixel(400, 300)[0], frame.pixel(400, 300)[1], frame.pixel(400, 300)[2], 0));
  const std::filesystem::path out = test::scratchDir("display-demo") / "display-demo.png";
  ASSERT_TRUE(writePng(shot, out).ok());
  if (const char* extra = std::getenv("EMBOSS_DISPLAY_DEMO_PNG")) {
    ASSERT_TRUE(writePng(shot, extra).ok());
  }
  auto back = readPng(out);
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->width, kDemoW);
  // The osmesa picture must match the headless one (same shaders, same rasteriser).
  auto soft = createOsmesaDisplay(kDemoW, kDemoH);
  ASSERT_TRUE(soft.ok()) << soft.error();
  ASSERT_TRUE((*soft)->present(frame, {}, overlay));
  const Image softShot = (*soft)->screenshot();
  int off = 0;
  for (std::size_t i = 0; i < shot.rgba.size(); ++i) off += std::abs(shot.rgba[i] - softShot.rgba[i]) > 3;
  EXPECT_LT(off, static_cast<int>(shot.rgba.size() / 1000)) << "osmesa and headless pictures differ";
}

}  // namespace
}  // namespace emboss
