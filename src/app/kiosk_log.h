// The kiosk's log: one line per event worth knowing, to stderr (the journal under systemd) or a test's list.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace emboss {

// Receives one line without a trailing newline, already prefixed with its category ("session: ...").
// A line may start with a syslog priority, "<3>" (error) .. "<7>" (debug); none is info (6).
using KioskLog = std::function<void(const std::string& line)>;

// A line's priority prefix split off: "<7>journal: ..." -> 7, "journal: ...". None: 6 (info).
struct LogLine {
  int priority = 6;
  std::string_view text;
};
LogLine splitLogPriority(std::string_view line);

// The journal id of the visitor's session the kiosk is working on now (0: none), for a sink that
// files it with each line (emboss-kiosk: the journal field EMBOSS_SESSION). The kiosk sets it as a
// session begins, is restored and ends; any thread may read it.
std::int64_t logSession();
void setLogSession(std::int64_t id);

// A line as systemd journal fields ("NAME=value"): MESSAGE, PRIORITY, SYSLOG_IDENTIFIER, and
// EMBOSS_SESSION when `session` > 0.
std::vector<std::string> journalFields(std::string_view text, int priority, std::int64_t session, std::string_view identifier);

}  // namespace emboss
