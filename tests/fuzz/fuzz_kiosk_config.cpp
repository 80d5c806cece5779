// libFuzzer target: the kiosk configuration file parser (a bad line is a warning, never a crash).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "app/kiosk_config.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> warnings;
  const emboss::KioskConfig c = emboss::parseKioskConfig(text, "fuzz.conf", emboss::KioskConfig{}, warnings);
  for (const auto& w : warnings)
    if (w.empty()) std::abort();  // every warning says something
  (void)c;
  return 0;
}
