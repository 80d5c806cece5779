// libFuzzer target: the Wacom and UC-Logic report decoders (first byte: which; then a model or parameter string and length-prefixed reports).
#include <cstddef>
#include <cstdint>

#include "fuzz_hid_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const emboss::fuzz::Bytes rest(data + 1, size - 1);
  if (data[0] & 1) emboss::fuzz::fuzzWacom(rest);
  else emboss::fuzz::fuzzUclogic(rest);
  return 0;
}
