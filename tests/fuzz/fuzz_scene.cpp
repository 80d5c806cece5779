// libFuzzer target: the scene-file parser, and evaluating whatever model it accepts.
#include <cstddef>
#include <cstdint>
#include <string>

#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  // vm paths resolve against a folder with no models, so they fail cleanly.
  auto scene = emboss::parseScene(text, "fuzz.json", "/nonexistent-fuzz-dir");
  if (!scene) return 0;
  auto model = scene->makeModel();
  if (!model) return 0;
  (void)model->evaluate(emboss::P3<double>{0.1, -0.2, 0.3});
  (void)model->evaluate(emboss::P3<emboss::Grad>{{0.1, 1, 0, 0}, {-0.2, 0, 1, 0}, {0.3, 0, 0, 1}});
  (void)model->evaluate(emboss::P3<emboss::Interval>{{-1, 1}, {-1, 1}, {-1, 1}});
  (void)emboss::sceneToJson(*scene, &*model);
  return 0;
}
