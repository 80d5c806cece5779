// libFuzzer target: the HID report descriptor parser and pen finder, then reports through the decoder it picks (2 bytes length, 4 bytes vendor and product, descriptor, reports).
#include <cstddef>
#include <cstdint>

#include "fuzz_hid_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  emboss::fuzz::fuzzDescriptor({data, size});
  return 0;
}
