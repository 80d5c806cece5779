// libFuzzer target: the GPIO buttons configuration parser.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "devices/button_config.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  auto c = emboss::parseButtonConfig(text, "fuzz.json");
  if (!c && c.error().empty()) std::abort();  // every failure must say something
  return 0;
}
