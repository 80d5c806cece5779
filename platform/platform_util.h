// Small helpers the platform back ends share: a message logged once per process, the monotonic clock.
#pragma once

#include <string>

namespace emboss {

// Writes "emboss: MESSAGE" to stderr the first time this exact message is seen (thread-safe), so a
// device that fails the same way on every probe is reported once, not every few seconds.
void logOnce(const std::string& message);

// Seconds on CLOCK_MONOTONIC.
double monotonicSeconds();

}  // namespace emboss
