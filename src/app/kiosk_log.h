// The kiosk's log: one line per event worth knowing, to stderr (the journal under systemd) or a test's list.
#pragma once

#include <functional>
#include <string>

namespace emboss {

// Receives one line without a trailing newline, already prefixed with its category ("session: ...").
using KioskLog = std::function<void(const std::string& line)>;

}  // namespace emboss
