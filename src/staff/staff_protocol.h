// The staff protocol: one JSON object a line, spoken by embossctl and the kiosk over a Unix socket.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "util/result.h"

namespace emboss {

struct StaffRequest {
  enum class Command { Status, Sessions, Export, Reset, Wipe };
  Command command = Command::Status;
  std::filesystem::path dest;        // export: where to
  double sinceUnix = 0;              // export: sessions finished since then only (0: all)
  bool allowAnyDir = false;          // export: a folder on the root file system too (tests)
  double olderThanDays = -1;         // wipe: sessions finished longer ago than this
};

// Parses a request line; the message names what is wrong.
Result<StaffRequest> parseStaffRequest(const std::string& line);
// The request as a line (embossctl writes it).
std::string staffRequestLine(const StaffRequest& r);

// "YYYY-MM-DD" (local midnight) or a number of days ago ("7d") as Unix seconds.
Result<double> parseSince(const std::string& text, double nowUnix);

// A destination fit for an export: an existing folder on a mounted file system other than the
// root's (a USB stick), unless `allowAnyDir`. The message says why not.
Status checkExportDestination(const std::filesystem::path& dest, bool allowAnyDir);

// A file or folder name with nothing but letters, digits, '-', '_' and '.', never "." or "..".
std::string sanitizeName(const std::string& name);

}  // namespace emboss
