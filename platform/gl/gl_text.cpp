// Overlay text: FreeType rasterisation, the glyph atlas's shelf packing, and text layout.
#include "gl/gl_text.h"

#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_TRUETYPE_TABLES_H

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>

namespace emboss {
namespace {

constexpr FT_Int32 kLoadFlags = FT_LOAD_TARGET_LIGHT;  // vertical-only hinting: crisp, not squashed
constexpr int kMinPpem = 4;
constexpr int kMaxPpem = 400;
constexpr int kPadding = 1;  // empty texels between glyphs

const char* const kFontCandidates[] = {
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",  // Debian, Raspberry Pi OS
    "/usr/share/fonts/TTF/DejaVuSans.ttf",              // Arch
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",           // Fedora, Alpine
    "/usr/share/fonts/dejavu-sans-fonts/DejaVuSans.ttf",
};

}  // namespace

struct GlyphAtlas::Face {
  FT_Library library = nullptr;
  FT_Face face = nullptr;
  float capRatio = 0.73f;  // cap height / em
  ~Face() {
    if (face != nullptr) FT_Done_Face(face);
    if (library != nullptr) FT_Done_FreeType(library);
  }
};

std::vector<char32_t> decodeUtf8(const std::string& text) {
  std::vector<char32_t> out;
  out.reserve(text.size());
  const auto* s = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t n = text.size();
  for (std::size_t i = 0; i < n;) {
    const unsigned char c = s[i];
    int extra = 0;
    char32_t cp = 0;
    if (c < 0x80) {
      cp = c;
    } else if ((c & 0xE0) == 0xC0) {
      extra = 1;
      cp = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
      extra = 2;
      cp = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
      extra = 3;
      cp = c & 0x07;
    } else {
      out.push_back(0xFFFD);
      ++i;
      continue;
    }
    bool ok = i + static_cast<std::size_t>(extra) < n;
    for (int k = 1; ok && k <= extra; ++k) {
      if ((s[i + k] & 0xC0) != 0x80) ok = false;
      else cp = (cp << 6) | (s[i + k] & 0x3F);
    }
    if (!ok) {
      out.push_back(0xFFFD);
      ++i;
      continue;
    }
    out.push_back(cp);
    i += 1 + extra;
  }
  return out;
}

Result<std::unique_ptr<GlyphAtlas>> GlyphAtlas::create(const std::string& fontPath, Upload upload) {
  std::string path = fontPath;
  if (path.empty()) {
    if (const char* env = std::getenv("EMBOSS_FONT"); env != nullptr && *env != '\0') path = env;
  }
  if (path.empty()) {
    for (const char* candidate : kFontCandidates) {
      std::error_code ec;
      if (std::filesystem::is_regular_file(candidate, ec)) {
        path = candidate;
        break;
      }
    }
    if (path.empty()) {
      return fail("overlay font: DejaVuSans.ttf not found (install fonts-dejavu-core, or set "
                  "EMBOSS_FONT=/path/to/font.ttf)");
    }
  }
  auto face = std::make_unique<Face>();
  if (FT_Init_FreeType(&face->library) != 0) return fail("overlay font: FreeType failed to start");
  if (FT_New_Face(face->library, path.c_str(), 0, &face->face) != 0) {
    return fail("overlay font: cannot load '" + path + "' (missing or not a font; check EMBOSS_FONT)");
  }
  if (!FT_IS_SCALABLE(face->face)) return fail("overlay font: '" + path + "' is not a scalable font");
  FT_Select_Charmap(face->face, FT_ENCODING_UNICODE);
  if (auto* os2 = static_cast<TT_OS2*>(FT_Get_Sfnt_Table(face->face, FT_SFNT_OS2));
      os2 != nullptr && os2->version >= 2 && os2->sCapHeight > 0) {
    face->capRatio = static_cast<float>(os2->sCapHeight) / static_cast<float>(face->face->units_per_EM);
  }
  return std::unique_ptr<GlyphAtlas>(new GlyphAtlas(std::move(face), path, std::move(upload)));
}

GlyphAtlas::GlyphAtlas(std::unique_ptr<Face> face, std::string path, Upload upload)
    : face_(std::move(face)), fontPath_(std::move(path)), upload_(std::move(upload)) {}

GlyphAtlas::~GlyphAtlas() = default;

void GlyphAtlas::reset() {
  glyphs_.clear();
  shelfX_ = shelfY_ = shelfHeight_ = 0;
}

bool GlyphAtlas::setPixelSize(int ppem) {
  if (ppem == currentPpem_) return true;
  if (FT_Set_Pixel_Sizes(face_->face, 0, static_cast<FT_UInt>(ppem)) != 0) return false;
  currentPpem_ = ppem;
  return true;
}

int GlyphAtlas::pixelSizeFor(float capHeight) {
  const int ppem = static_cast<int>(std::lround(capHeight / face_->capRatio));
  return std::clamp(ppem, kMinPpem, kMaxPpem);
}

int GlyphAtlas::capTop(int ppem) {
  if (auto it = capTops_.find(ppem); it != capTops_.end()) return it->second;
  int top = static_cast<int>(std::lround(ppem * face_->capRatio));
  if (setPixelSize(ppem)) {
    const FT_UInt h = FT_Get_Char_Index(face_->face, 'H');
    if (h != 0 && FT_Load_Glyph(face_->face, h, kLoadFlags | FT_LOAD_RENDER) == 0) {
      top = face_->face->glyph->bitmap_top;
    }
  }
  capTops_[ppem] = top;
  return top;
}

const AtlasGlyph* GlyphAtlas::glyph(int ppem, unsigned glyphIndex, bool* full) {
  *full = false;
  const auto key = std::make_pair(ppem, glyphIndex);
  if (auto it = glyphs_.find(key); it != glyphs_.end()) return &it->second;
  if (!setPixelSize(ppem)) return nullptr;
  if (FT_Load_Glyph(face_->face, glyphIndex, kLoadFlags | FT_LOAD_RENDER) != 0) return nullptr;
  const FT_GlyphSlot slot = face_->face->glyph;
  if (slot->bitmap.pixel_mode != FT_PIXEL_MODE_GRAY && slot->bitmap.width > 0) {
    FT_Render_Glyph(slot, FT_RENDER_MODE_LIGHT);
  }
  AtlasGlyph g;
  g.width = static_cast<int>(slot->bitmap.width);
  g.height = static_cast<int>(slot->bitmap.rows);
  g.left = slot->bitmap_left;
  g.top = slot->bitmap_top;
  g.advance = static_cast<int>(slot->advance.x);
  if (g.width > 0 && g.height > 0) {
    if (g.width + kPadding > kAtlasSize || g.height + kPadding > kAtlasSize) {
      g.width = g.height = 0;  // larger than the whole atlas: draw nothing rather than fail
    } else {
      if (shelfX_ + g.width + kPadding > kAtlasSize) {  // next shelf
        shelfY_ += shelfHeight_;
        shelfX_ = 0;
        shelfHeight_ = 0;
      }
      if (shelfY_ + g.height + kPadding > kAtlasSize) {
        *full = true;
        return nullptr;
      }
      g.atlasX = shelfX_;
      g.atlasY = shelfY_;
      shelfX_ += g.width + kPadding;
      shelfHeight_ = std::max(shelfHeight_, g.height + kPadding);
      // Copy to a tightly packed buffer (FreeType rows may be padded or bottom-up).
      scratch_.assign(static_cast<std::size_t>(g.width) * g.height, 0);
      const int pitch = slot->bitmap.pitch;
      for (int row = 0; row < g.height; ++row) {
        const unsigned char* src = pitch >= 0 ? slot->bitmap.buffer + row * pitch
                                              : slot->bitmap.buffer + (g.height - 1 - row) * -pitch;
        std::memcpy(&scratch_[static_cast<std::size_t>(row) * g.width], src, static_cast<std::size_t>(g.width));
      }
      if (upload_) upload_(g.atlasX, g.atlasY, g.width, g.height, scratch_.data());
    }
  }
  return &glyphs_.emplace(key, g).first->second;
}

bool GlyphAtlas::layout(const std::string& text, float x, float y, float capHeight,
                        std::vector<PlacedGlyph>& out) {
  if (!(capHeight > 0)) return true;
  const int ppem = pixelSizeFor(capHeight);
  const int top = capTop(ppem);
  if (!setPixelSize(ppem)) return true;
  const int lineHeight = static_cast<int>((face_->face->size->metrics.height + 63) >> 6);
  const long originX = std::lround(x) * 64;
  long penX = originX;
  int baseline = static_cast<int>(std::lround(y)) + top;
  FT_UInt previous = 0;
  const bool kerning = FT_HAS_KERNING(face_->face);
  for (char32_t cp : decodeUtf8(text)) {
    if (cp == U'\n') {
      penX = originX;
      baseline += lineHeight;
      previous = 0;
      continue;
    }
    const FT_UInt index = FT_Get_Char_Index(face_->face, cp);
    if (kerning && previous != 0 && index != 0) {
      setPixelSize(ppem);
      FT_Vector delta;
      if (FT_Get_Kerning(face_->face, previous, index, FT_KERNING_DEFAULT, &delta) == 0) penX += delta.x;
    }
    bool full = false;
    const AtlasGlyph* g = glyph(ppem, index, &full);
    if (full) return false;
    if (g == nullptr) continue;
    if (g->width > 0) {
      const int px = static_cast<int>((penX + 32) >> 6) + g->left;
      out.push_back(PlacedGlyph{px, baseline - g->top, g});
    }
    penX += g->advance;
    previous = index;
  }
  return true;
}

float GlyphAtlas::measure(const std::string& text, float capHeight) {
  if (!(capHeight > 0)) return 0;
  const int ppem = pixelSizeFor(capHeight);
  if (!setPixelSize(ppem)) return 0;
  long pen = 0, widest = 0;
  FT_UInt previous = 0;
  const bool kerning = FT_HAS_KERNING(face_->face);
  for (char32_t cp : decodeUtf8(text)) {
    if (cp == U'\n') {
      widest = std::max(widest, pen);
      pen = 0;
      previous = 0;
      continue;
    }
    const FT_UInt index = FT_Get_Char_Index(face_->face, cp);
    if (kerning && previous != 0 && index != 0) {
      FT_Vector delta;
      if (FT_Get_Kerning(face_->face, previous, index, FT_KERNING_DEFAULT, &delta) == 0) pen += delta.x;
    }
    if (FT_Load_Glyph(face_->face, index, kLoadFlags) == 0) pen += face_->face->glyph->advance.x;
    previous = index;
  }
  widest = std::max(widest, pen);
  return static_cast<float>(widest) / 64.0f;
}

float measureOverlayText(const std::string& text, float size, const std::string& fontPath) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<GlyphAtlas>> fonts;  // measuring only: no uploads
  std::lock_guard lock(mutex);
  auto it = fonts.find(fontPath);
  if (it == fonts.end()) {
    auto atlas = GlyphAtlas::create(fontPath, nullptr);
    it = fonts.emplace(fontPath, atlas ? std::move(*atlas) : nullptr).first;
  }
  return it->second ? it->second->measure(text, size) : 0.0f;
}

}  // namespace emboss
