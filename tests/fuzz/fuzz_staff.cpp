// Fuzz target: the staff protocol's request parser (what embossctl, or anything that reaches the
// socket, sends the kiosk), its progress lines (what embossctl reads back) and the export folder
// names it makes.
#include <cstddef>
#include <cstdint>
#include <string>

#include "staff/staff_protocol.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string line(reinterpret_cast<const char*>(data), size);
  if (auto r = emboss::parseStaffRequest(line)) {
    const auto again = emboss::parseStaffRequest(emboss::staffRequestLine(*r));
    if (!again || again->command != r->command || again->dest != r->dest) __builtin_trap();  // the round trip holds
  }
  if (auto p = emboss::parseStaffProgress(line)) {
    const auto again = emboss::parseStaffProgress(emboss::staffProgressLine(*p));
    if (!again || again->sessionsDone != p->sessionsDone || again->sessions != p->sessions || again->bytes != p->bytes)
      __builtin_trap();
    (void)emboss::staffProgressText(*p);
  }
  const std::string n = emboss::sanitizeName(line);
  if (n.empty() || n == "." || n == ".." || n.find('/') != std::string::npos) __builtin_trap();
  (void)emboss::parseSince(line, 1.8e9);
  return 0;
}
