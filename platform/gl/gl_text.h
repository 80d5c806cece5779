// Overlay text for the GL presenter: FreeType glyphs (DejaVu Sans) packed into a glyph atlas, and
// the layout rule of OverlayText (top of the capitals at y, baseline at y + size).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "util/result.h"

namespace emboss {

// A glyph that has been rasterised (8-bit coverage) and placed in the atlas.
struct AtlasGlyph {
  int atlasX = 0, atlasY = 0;  // top-left of the bitmap in the atlas
  int width = 0, height = 0;   // bitmap size (0 for blanks such as space)
  int left = 0;                // bitmap's left edge right of the pen
  int top = 0;                 // bitmap's top edge above the baseline
  int advance = 0;             // pen advance, 26.6 fixed point
};

// One glyph quad of laid-out text, in screen pixels (origin top left), integer aligned.
struct PlacedGlyph {
  int x = 0, y = 0;
  const AtlasGlyph* glyph = nullptr;
};

// A FreeType face plus a shelf-packed glyph atlas of kAtlasSize x kAtlasSize 8-bit texels. The
// atlas pixels are not kept here: every newly packed glyph is handed to `upload` (the GL side
// copies it into its texture). Not thread-safe.
class GlyphAtlas {
 public:
  static constexpr int kAtlasSize = 1024;
  using Upload = std::function<void(int x, int y, int w, int h, const std::uint8_t* coverage)>;

  // fontPath empty: $EMBOSS_FONT, else DejaVu Sans from the usual places.
  static Result<std::unique_ptr<GlyphAtlas>> create(const std::string& fontPath, Upload upload);
  ~GlyphAtlas();
  GlyphAtlas(const GlyphAtlas&) = delete;
  GlyphAtlas& operator=(const GlyphAtlas&) = delete;

  const std::string& fontPath() const { return fontPath_; }

  // Lays out UTF-8 `text` with capitals `capHeight` pixels tall, the top of the capitals at y
  // and the first pen position at x; '\n' starts a new line. Adds the visible glyphs to `out`.
  // Returns false when the atlas filled up on the way: draw what is in `out`, call reset(), and
  // lay the text out again.
  bool layout(const std::string& text, float x, float y, float capHeight, std::vector<PlacedGlyph>& out);
  // Width in pixels of the widest line of `text` at this cap height (for centring labels).
  float measure(const std::string& text, float capHeight);
  // Forgets every packed glyph (the texture's contents become garbage until re-uploaded).
  void reset();

 private:
  struct Face;
  GlyphAtlas(std::unique_ptr<Face> face, std::string path, Upload upload);
  bool setPixelSize(int ppem);
  int pixelSizeFor(float capHeight);
  int capTop(int ppem);
  const AtlasGlyph* glyph(int ppem, unsigned glyphIndex, bool* full);

  std::unique_ptr<Face> face_;
  std::string fontPath_;
  Upload upload_;
  int currentPpem_ = 0;
  std::map<std::pair<int, unsigned>, AtlasGlyph> glyphs_;
  std::map<int, int> capTops_;
  int shelfX_ = 0, shelfY_ = 0, shelfHeight_ = 0;
  std::vector<std::uint8_t> scratch_;
};

// Width in pixels of the widest line of `text` drawn as OverlayText with this size, for sizing
// panels and centring labels before the frame is built (no GL needed; the same font and layout as
// the presenter with the same fontPath). 0 when the font cannot be loaded. Thread-safe.
float measureOverlayText(const std::string& text, float size, const std::string& fontPath = "");

// Decodes UTF-8; malformed bytes become U+FFFD.
std::vector<char32_t> decodeUtf8(const std::string& text);

}  // namespace emboss
