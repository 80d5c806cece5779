// The postcard: the piece in its window on a paper card, the caption handed to the painter.
#include <gtest/gtest.h>

#include <vector>

#include "export/postcard.h"
#include "scene/scene.h"

namespace emboss {
namespace {

struct RecordingPainter : TextPainter {
  std::vector<std::string> texts;
  float measure(const std::string& text, float capHeight) override { return 0.5f * capHeight * text.size(); }
  void draw(Image& image, const std::string& text, float x, float y, float capHeight,
            const std::array<std::uint8_t, 3>& rgb) override {
    EXPECT_GE(x, 0.0f);
    EXPECT_LE(x + measure(text, capHeight), image.width + 0.5f) << text;
    EXPECT_LE(y + capHeight, image.height) << text;
    texts.push_back(text);
  }
};

TEST(Postcard, ThePieceOnPaperWithItsTitleMetalAndDate) {
  auto scene = parseScene(R"({"title":"Rosette","metal":"brass","workpiece":{"type":"plate","w":30,"h":20,"d":0.5},
    "operations":[{"op":"punch","side":"back","a":4,"p":0.5,"q":1,"at":[0,0,0.5]}]})",
                          "t.json", ".");
  ASSERT_TRUE(scene.ok()) << scene.error();
  auto model = scene->makeModel();
  ASSERT_TRUE(model.ok());
  RecordingPainter painter;
  PostcardOptions o;
  o.width = 600;
  o.height = 400;
  o.date = "25 November 2026";
  auto card = postcard(*scene, *model, o, &painter);
  ASSERT_TRUE(card.ok()) << card.error();
  EXPECT_EQ(card->width, 600);
  EXPECT_EQ(card->height, 400);
  const std::uint8_t* corner = card->pixel(2, 2);
  EXPECT_EQ(corner[0], 244);  // paper
  EXPECT_EQ(corner[3], 255);
  // The middle of the window is the rendered piece, not paper.
  const std::uint8_t* mid = card->pixel(300, 160);
  EXPECT_FALSE(mid[0] == 244 && mid[1] == 239 && mid[2] == 228);
  ASSERT_EQ(painter.texts.size(), 3u);
  EXPECT_EQ(painter.texts[0], "Rosette");
  EXPECT_EQ(painter.texts[1], "Brass, embossed by hand on 25 November 2026");
  // Without a painter: the same card, no caption.
  auto bare = postcard(*scene, *model, o, nullptr);
  ASSERT_TRUE(bare.ok());
  EXPECT_FALSE(postcard(*scene, *model, PostcardOptions{100, 50, 0, ""}, nullptr).ok());
}

TEST(Postcard, DateIsSpelledOut) {
  EXPECT_NE(postcardDate(0).find("19"), std::string::npos);  // 1 January 1970 (or 31 December 1969 west of UTC)
  EXPECT_NE(postcardDate(1795651200).find("2026"), std::string::npos);
}

}  // namespace
}  // namespace emboss
