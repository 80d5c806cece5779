// The visitor's postcard: the piece rendered on a card with its title, metal and date.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "frep/model.h"
#include "render/image.h"
#include "scene/scene.h"
#include "util/result.h"

namespace emboss {

// Draws text into an image (the platform's FreeType painter; tests may pass their own).
class TextPainter {
 public:
  virtual ~TextPainter() = default;
  // Width in pixels of `text` with capitals `capHeight` tall.
  virtual float measure(const std::string& text, float capHeight) = 0;
  // Blends `text` in `rgb`, the top of the capitals at y, the pen starting at x.
  virtual void draw(Image& image, const std::string& text, float x, float y, float capHeight,
                    const std::array<std::uint8_t, 3>& rgb) = 0;
};

struct PostcardOptions {
  int width = 1800, height = 1200;  // 6 x 4 inches at 300 dpi
  int threads = 0;
  std::string date;  // as printed, e.g. "25 November 2026"; empty: today
};

// A paper-coloured card: the piece ray traced in a framed window (the scene camera's direction,
// brought close enough for the sheet to fill it), and under it
// the title (or "Embossed at the museum"), the metal and the date, and the program's name. Without
// a painter (no font) the card has the picture and no words.
Result<Image> postcard(const Scene& scene, const Model& model, const PostcardOptions& options, TextPainter* text);

// "25 November 2026" for a Unix time, in local time.
std::string postcardDate(long long unixSeconds);

}  // namespace emboss
