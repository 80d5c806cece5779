// libFuzzer target: the evemu recording parser and its conversion to pen samples.
#include <cstddef>
#include <cstdint>

#include "fuzz_hid_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  emboss::fuzz::fuzzEvemu({data, size});
  return 0;
}
