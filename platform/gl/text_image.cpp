// AtlasTextPainter: GlyphAtlas uploads into a CPU atlas; glyphs blended by coverage.
#include "gl/text_image.h"

#include <algorithm>
#include <cstring>

namespace emboss {

Result<std::unique_ptr<AtlasTextPainter>> AtlasTextPainter::create(const std::string& fontPath) {
  std::unique_ptr<AtlasTextPainter> p(new AtlasTextPainter());
  p->atlas_.assign(static_cast<size_t>(GlyphAtlas::kAtlasSize) * GlyphAtlas::kAtlasSize, 0);
  auto* atlas = &p->atlas_;
  auto glyphs = GlyphAtlas::create(fontPath, [atlas](int x, int y, int w, int h, const std::uint8_t* coverage) {
    for (int r = 0; r < h; ++r)
      std::memcpy(&(*atlas)[static_cast<size_t>(y + r) * GlyphAtlas::kAtlasSize + x], coverage + static_cast<size_t>(r) * w, w);
  });
  if (!glyphs) return fail(glyphs.error());
  p->glyphs_ = std::move(*glyphs);
  return p;
}

float AtlasTextPainter::measure(const std::string& text, float capHeight) { return glyphs_->measure(text, capHeight); }

void AtlasTextPainter::draw(Image& image, const std::string& text, float x, float y, float capHeight,
                            const std::array<std::uint8_t, 3>& rgb) {
  std::vector<PlacedGlyph> placed;
  if (!glyphs_->layout(text, x, y, capHeight, placed)) {
    glyphs_->reset();
    placed.clear();
    glyphs_->layout(text, x, y, capHeight, placed);
  }
  for (const PlacedGlyph& g : placed) {
    for (int r = 0; r < g.glyph->height; ++r) {
      const int iy = g.y + r;
      if (iy < 0 || iy >= image.height) continue;
      for (int c = 0; c < g.glyph->width; ++c) {
        const int ix = g.x + c;
        if (ix < 0 || ix >= image.width) continue;
        const int a = atlas_[static_cast<size_t>(g.glyph->atlasY + r) * GlyphAtlas::kAtlasSize + g.glyph->atlasX + c];
        if (a == 0) continue;
        std::uint8_t* p = image.pixel(ix, iy);
        for (int k = 0; k < 3; ++k) p[k] = static_cast<std::uint8_t>((rgb[k] * a + p[k] * (255 - a) + 127) / 255);
      }
    }
  }
}

}  // namespace emboss
