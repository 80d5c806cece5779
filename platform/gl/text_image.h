// Text drawn into a CPU image with the overlay's FreeType glyphs (for the postcard).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "export/postcard.h"
#include "gl/gl_text.h"

namespace emboss {

class AtlasTextPainter : public TextPainter {
 public:
  // fontPath empty: $EMBOSS_FONT, else DejaVu Sans. Fails when no font can be loaded.
  static Result<std::unique_ptr<AtlasTextPainter>> create(const std::string& fontPath = "");
  float measure(const std::string& text, float capHeight) override;
  void draw(Image& image, const std::string& text, float x, float y, float capHeight,
            const std::array<std::uint8_t, 3>& rgb) override;

 private:
  AtlasTextPainter() = default;
  std::vector<std::uint8_t> atlas_;  // kAtlasSize^2 coverage, filled by the atlas's uploads
  std::unique_ptr<GlyphAtlas> glyphs_;
};

}  // namespace emboss
