// libFuzzer target: the button configuration parser, the button gestures, and capture drawing on small images.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "capture/capture_drawing.h"
#include "devices/button_config.h"
#include "devices/button_gestures.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::uint8_t mode = data[0] % 3;
  data += 1, size -= 1;
  if (mode == 0) {  // JSON text
    (void)emboss::parseButtonConfig(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
  } else if (mode == 1) {  // edges: (button, level, time step in ms) triples
    emboss::ButtonGestures g(emboss::defaultButtonConfig());
    std::vector<emboss::ButtonEvent> out;
    double t = 0;
    for (std::size_t i = 0; i + 2 < size; i += 3) {
      t += data[i + 2] * 0.004;
      g.edge(data[i] % g.size(), data[i + 1] & 1, t, out);
    }
    g.advance(t + 10, out);
  } else {  // a gray photo: width from the first byte, then the pixels
    const int w = 32 + data[0] % 64;
    const int h = static_cast<int>((size - 1) / static_cast<std::size_t>(w));
    if (h < 8) return 0;
    emboss::Image img(w, h);
    for (int i = 0; i < w * h; ++i) {
      std::uint8_t* p = &img.rgba[static_cast<std::size_t>(i) * 4];
      p[0] = p[1] = p[2] = data[1 + i], p[3] = 255;
    }
    (void)emboss::captureDrawing(img, 100, 80);
  }
  return 0;
}
