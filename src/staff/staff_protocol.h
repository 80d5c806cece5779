// The staff protocol: one JSON object a line, spoken by embossctl and the kiosk over a Unix socket.
// A request is one line; its answer is one line with "ok". An export asked with "progress": true
// is answered first with progress lines ({"progress": {...}}, no "ok") as sessions are copied.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "util/result.h"

namespace emboss {

struct StaffRequest {
  enum class Command { Status, Sessions, Export, Reset, Wipe };
  Command command = Command::Status;
  std::filesystem::path dest;        // export: where to
  double sinceUnix = 0;              // export: sessions finished since then only (0: all)
  bool allowAnyDir = false;          // export: a folder on the root file system too (tests)
  bool progress = false;             // export: progress lines before the answer
  double olderThanDays = -1;         // wipe: sessions finished longer ago than this
};

// Parses a request line; the message names what is wrong.
Result<StaffRequest> parseStaffRequest(const std::string& line);
// The request as a line (embossctl writes it).
std::string staffRequestLine(const StaffRequest& r);

// An export's progress: sessions copied of all it copies, bytes written so far.
struct StaffProgress {
  std::uint64_t sessionsDone = 0, sessions = 0;
  std::uint64_t bytes = 0;
};
// The progress as a line, and back; nullopt: the line is not a progress line (it is the answer).
std::string staffProgressLine(const StaffProgress& p);
std::optional<StaffProgress> parseStaffProgress(const std::string& line);
// The progress as people read it: "3/12 sessions, 1.2 MB".
std::string staffProgressText(const StaffProgress& p);

// What the kiosk has for a client waiting on a long request: progress lines to send now, and the
// answer once there is one (the connection is closed after it).
struct StaffPending {
  std::vector<std::string> progress;
  std::optional<std::string> answer;
};

// "YYYY-MM-DD" (local midnight) or a number of days ago ("7d") as Unix seconds.
Result<double> parseSince(const std::string& text, double nowUnix);

// A destination fit for an export: an existing folder on a mounted file system other than the
// root's (a USB stick), unless `allowAnyDir`. The message says why not.
Status checkExportDestination(const std::filesystem::path& dest, bool allowAnyDir);

// A file or folder name with nothing but letters, digits, '-', '_' and '.', never "." or "..".
std::string sanitizeName(const std::string& name);

}  // namespace emboss
