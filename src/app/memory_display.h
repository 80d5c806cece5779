// The memory display: a Display in plain memory, overlay drawn in software; the last-resort
// fallback when no back end starts, and the display of the app's tests.
#pragma once

#include <string>

#include "devices/display.h"

namespace emboss {

// Draws rectangles and rings of the overlay into the picture (antialiased); text is left to the
// GL back ends (it has no font here) and counted in textsSkipped().
class MemoryDisplay final : public Display {
 public:
  MemoryDisplay(int width, int height, std::string why = {});
  std::string name() const override;
  int width() const override { return w_; }
  int height() const override { return h_; }
  bool present(const Image& frame, std::span<const Rect> dirty, const Overlay& overlay) override;
  Image screenshot() override { return shown_; }
  size_t presents() const { return presents_; }
  size_t textsSkipped() const { return textsSkipped_; }

 private:
  int w_, h_;
  std::string why_;
  Image shown_;
  size_t presents_ = 0, textsSkipped_ = 0;
};

// Blends the overlay's rectangles and rings into `image` (the software path of display.h).
void drawOverlayInto(Image& image, const Overlay& overlay);

}  // namespace emboss
