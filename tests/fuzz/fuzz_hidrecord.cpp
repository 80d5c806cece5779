// libFuzzer target: the hid-recorder capture parser and its decoding.
#include <cstddef>
#include <cstdint>

#include "fuzz_hid_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  emboss::fuzz::fuzzHidRecord({data, size});
  return 0;
}
