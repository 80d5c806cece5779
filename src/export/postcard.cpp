// The postcard: a render in a frame on a card, and a caption.
#include "export/postcard.h"

#include <algorithm>
#include <cmath>
#include <ctime>

#include "render/camera.h"
#include "render/renderer.h"
#include "render/thread_pool.h"
#include "tools/metal.h"

namespace emboss {

namespace {

constexpr std::array<std::uint8_t, 3> kPaper = {244, 239, 228};
constexpr std::array<std::uint8_t, 3> kInk = {46, 40, 34};
constexpr std::array<std::uint8_t, 3> kGrey = {120, 112, 100};

void fill(Image& image, int x0, int y0, int x1, int y1, const std::array<std::uint8_t, 3>& rgb) {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0), x1 = std::min(x1, image.width), y1 = std::min(y1, image.height);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      std::uint8_t* p = image.pixel(x, y);
      p[0] = rgb[0], p[1] = rgb[1], p[2] = rgb[2], p[3] = 255;
    }
}

// The scene's camera moved along its line of sight (or, ortho, its view height changed) so that the
// sheet fills the window with a margin: a visitor's camera frames the bench, the card the piece.
CameraSpec framed(const CameraSpec& c, const Box3& sheet, double aspect) {
  auto sub = [](Vec3 a, Vec3 b) { return Vec3{a.x - b.x, a.y - b.y, a.z - b.z}; };
  auto dot = [](Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; };
  auto cross = [](Vec3 a, Vec3 b) { return Vec3{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; };
  auto unit = [&](Vec3 a) {
    const double l = std::sqrt(dot(a, a));
    return l > 0 ? Vec3{a.x / l, a.y / l, a.z / l} : a;
  };
  const Vec3 centre{0.5 * (sheet.x0 + sheet.x1), 0.5 * (sheet.y0 + sheet.y1), 0.5 * (sheet.z0 + sheet.z1)};
  const Vec3 back = unit(sub(c.eye, c.target));  // from the target toward the eye
  const Vec3 right = unit(cross(c.up, back));
  const Vec3 up = cross(back, right);
  if (!(dot(back, back) > 0.5 && dot(right, right) > 0.5)) return c;
  constexpr double kFill = 0.9;
  CameraSpec out = c;
  out.target = centre;
  const double tv = std::tan(0.5 * c.fovDeg * M_PI / 180.0) * kFill, th = tv * aspect;
  double dist = 0.0, halfH = 0.0;
  for (int k = 0; k < 8; ++k) {
    const Vec3 corner{k & 1 ? sheet.x1 : sheet.x0, k & 2 ? sheet.y1 : sheet.y0, k & 4 ? sheet.z1 : sheet.z0};
    const Vec3 p = sub(corner, centre);
    const double x = std::abs(dot(p, right)), y = std::abs(dot(p, up)), z = dot(p, back);
    dist = std::max({dist, z + y / tv, z + x / th});
    halfH = std::max({halfH, y, x / aspect});
  }
  if (c.type == CameraSpec::Type::Ortho) {
    out.eye = {centre.x + back.x * 200.0, centre.y + back.y * 200.0, centre.z + back.z * 200.0};
    out.height = 2.0 * halfH / kFill;
  } else {
    out.eye = {centre.x + back.x * dist, centre.y + back.y * dist, centre.z + back.z * dist};
  }
  return out;
}

std::string capitalised(std::string s) {
  if (!s.empty() && s[0] >= 'a' && s[0] <= 'z') s[0] = static_cast<char>(s[0] - 'a' + 'A');
  return s;
}

}  // namespace

std::string postcardDate(long long unixSeconds) {
  static const char* const kMonths[] = {"January", "February", "March",     "April",   "May",      "June",
                                        "July",    "August",   "September", "October", "November", "December"};
  const std::time_t t = static_cast<std::time_t>(unixSeconds);
  std::tm tm{};
  localtime_r(&t, &tm);
  return std::to_string(tm.tm_mday) + " " + kMonths[tm.tm_mon] + " " + std::to_string(1900 + tm.tm_year);
}

Result<Image> postcard(const Scene& scene, const Model& model, const PostcardOptions& options, TextPainter* text) {
  const int W = options.width, H = options.height;
  if (W < 200 || H < 150 || W > 16384 || H > 16384) return fail("a postcard must be 200x150 to 16384x16384 pixels");
  Image card(W, H);
  fill(card, 0, 0, W, H, kPaper);
  const int margin = static_cast<int>(std::lround(0.045 * std::min(W, H)));
  const int caption = static_cast<int>(std::lround(0.16 * H));
  const int px = margin, py = margin, pw = W - 2 * margin, ph = H - 2 * margin - caption;

  // The piece, with its own camera and metal, in the window.
  auto metal = metalByName(scene.metal);
  auto tinge = tingeByName(scene.tinge);
  if (!metal || !tinge) return fail("unknown metal or tinge in the scene");
  ThreadPool pool(options.threads);
  Renderer renderer(pool);
  Box3 sheet = model.workpiece().bounds();
  sheet.z0 -= 2.0, sheet.z1 += 2.0;  // room for the relief
  renderer.setCamera(Camera(framed(scene.camera, sheet, static_cast<double>(pw) / ph), pw, ph));
  ShadingParams shading;
  shading.metal = *metal;
  shading.tinge = *tinge;
  shading.frontZ = model.workpiece().bounds().z1;
  renderer.setShading(shading);
  renderer.sync(model);
  Image picture;
  renderer.renderFull(picture);
  const int frame = std::max(2, W / 600);
  fill(card, px - frame, py - frame, px + pw + frame, py + ph + frame, kInk);
  for (int y = 0; y < ph; ++y)
    for (int x = 0; x < pw; ++x) {
      const std::uint8_t* s = picture.pixel(x, y);
      std::uint8_t* d = card.pixel(px + x, py + y);
      d[0] = s[0], d[1] = s[1], d[2] = s[2], d[3] = 255;
    }

  if (text) {
    const std::string title = scene.title.empty() ? "Embossed at the museum" : scene.title;
    const std::string date = options.date.empty() ? postcardDate(static_cast<long long>(std::time(nullptr))) : options.date;
    const std::string line = capitalised(scene.metal) + (scene.tinge != "none" ? ", " + scene.tinge + " tinge" : "") +
                             ", embossed by hand on " + date;
    const float titleCap = 0.034f * H, lineCap = 0.019f * H;
    const float ty = static_cast<float>(py + ph + frame) + 0.045f * H;
    text->draw(card, title, static_cast<float>(px), ty, titleCap, kInk);
    text->draw(card, line, static_cast<float>(px), ty + titleCap * 1.9f, lineCap, kGrey);
    const std::string mark = "emboss";
    text->draw(card, mark, static_cast<float>(px + pw) - text->measure(mark, lineCap), ty + titleCap * 1.9f, lineCap, kGrey);
  }
  return card;
}

}  // namespace emboss
