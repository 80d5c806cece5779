// Parsing and checking staff requests: the protocol's one definition.
#include "staff/staff_protocol.h"

#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>

#include <nlohmann/json.hpp>

namespace emboss {

namespace fs = std::filesystem;
using nlohmann::json;

Result<StaffRequest> parseStaffRequest(const std::string& line) {
  const json j = json::parse(line, nullptr, false);
  if (!j.is_object()) return fail("a request is one JSON object on a line");
  const auto cmd = j.find("cmd");
  if (cmd == j.end() || !cmd->is_string()) return fail("the request has no \"cmd\"");
  StaffRequest r;
  const std::string c = cmd->get<std::string>();
  if (c == "status") r.command = StaffRequest::Command::Status;
  else if (c == "sessions") r.command = StaffRequest::Command::Sessions;
  else if (c == "reset") r.command = StaffRequest::Command::Reset;
  else if (c == "export") {
    r.command = StaffRequest::Command::Export;
    const auto d = j.find("dest");
    if (d == j.end() || !d->is_string() || d->get<std::string>().empty()) return fail("export needs \"dest\", a folder");
    r.dest = d->get<std::string>();
    if (!r.dest.is_absolute()) return fail("export's \"dest\" must be an absolute path, not '" + r.dest.string() + "'");
    if (const auto s = j.find("since"); s != j.end()) {
      if (!s->is_number() || !std::isfinite(s->get<double>()) || s->get<double>() < 0) return fail("\"since\" must be Unix seconds");
      r.sinceUnix = s->get<double>();
    }
    if (const auto a = j.find("allow_any_dir"); a != j.end()) {
      if (!a->is_boolean()) return fail("\"allow_any_dir\" must be true or false");
      r.allowAnyDir = a->get<bool>();
    }
    if (const auto p = j.find("progress"); p != j.end()) {
      if (!p->is_boolean()) return fail("\"progress\" must be true or false");
      r.progress = p->get<bool>();
    }
  } else if (c == "wipe") {
    r.command = StaffRequest::Command::Wipe;
    const auto d = j.find("older_than_days");
    if (d == j.end() || !d->is_number() || !std::isfinite(d->get<double>()) || d->get<double>() < 0 || d->get<double>() > 36500)
      return fail("wipe needs \"older_than_days\", a number of days 0..36500");
    r.olderThanDays = d->get<double>();
  } else {
    return fail("unknown command '" + c + "' (status, sessions, export, reset, wipe)");
  }
  return r;
}

std::string staffRequestLine(const StaffRequest& r) {
  json j;
  switch (r.command) {
    case StaffRequest::Command::Status: j["cmd"] = "status"; break;
    case StaffRequest::Command::Sessions: j["cmd"] = "sessions"; break;
    case StaffRequest::Command::Reset: j["cmd"] = "reset"; break;
    case StaffRequest::Command::Export:
      j["cmd"] = "export";
      j["dest"] = r.dest.string();
      if (r.sinceUnix > 0) j["since"] = r.sinceUnix;
      if (r.allowAnyDir) j["allow_any_dir"] = true;
      if (r.progress) j["progress"] = true;
      break;
    case StaffRequest::Command::Wipe:
      j["cmd"] = "wipe";
      j["older_than_days"] = r.olderThanDays;
      break;
  }
  return j.dump();
}

std::string staffProgressLine(const StaffProgress& p) {
  return json{{"progress", {{"sessions_done", p.sessionsDone}, {"sessions", p.sessions}, {"bytes", p.bytes}}}}.dump();
}

std::optional<StaffProgress> parseStaffProgress(const std::string& line) {
  const json j = json::parse(line, nullptr, false);
  if (!j.is_object() || j.contains("ok")) return std::nullopt;
  const auto p = j.find("progress");
  if (p == j.end() || !p->is_object()) return std::nullopt;
  const auto count = [&](const char* key) -> std::optional<std::uint64_t> {
    const auto v = p->find(key);
    if (v == p->end() || !v->is_number_unsigned()) return std::nullopt;
    return v->get<std::uint64_t>();
  };
  const auto done = count("sessions_done"), all = count("sessions"), bytes = count("bytes");
  if (!done || !all || !bytes) return std::nullopt;
  return StaffProgress{*done, *all, *bytes};
}

std::string staffProgressText(const StaffProgress& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%llu/%llu sessions, %.1f MB", static_cast<unsigned long long>(p.sessionsDone),
                static_cast<unsigned long long>(p.sessions), double(p.bytes) / 1e6);
  return buf;
}

Result<double> parseSince(const std::string& text, double nowUnix) {
  if (!text.empty() && text.back() == 'd') {
    try {
      size_t used = 0;
      const double days = std::stod(text.substr(0, text.size() - 1), &used);
      if (used == text.size() - 1 && std::isfinite(days) && days >= 0 && days <= 36500) return nowUnix - days * 86400.0;
    } catch (const std::exception&) {
    }
    return fail("--since must be YYYY-MM-DD or a number of days such as 7d, not '" + text + "'");
  }
  std::tm tm{};
  const char* end = strptime(text.c_str(), "%Y-%m-%d", &tm);
  if (!end || *end) return fail("--since must be YYYY-MM-DD or a number of days such as 7d, not '" + text + "'");
  tm.tm_isdst = -1;
  const std::time_t t = std::mktime(&tm);
  if (t == std::time_t(-1)) return fail("--since: '" + text + "' is not a date");
  return double(t);
}

Status checkExportDestination(const fs::path& dest, bool allowAnyDir) {
  struct stat d {}, root {};
  if (::stat(dest.c_str(), &d) != 0 || !S_ISDIR(d.st_mode)) return fail("'" + dest.string() + "' is not a folder (is the stick plugged in and mounted?)");
  if (allowAnyDir) return Ok{};
  if (::stat("/", &root) != 0) return fail("cannot look at the root file system");
  if (d.st_dev == root.st_dev)
    return fail("'" + dest.string() + "' is on the kiosk's own disk, not a stick: nothing is mounted there (plug in a USB stick)");
  return Ok{};
}

std::string sanitizeName(const std::string& name) {
  std::string out;
  for (char ch : name) {
    const bool keep = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '-' || ch == '_' || ch == '.';
    out += keep ? ch : '_';
  }
  if (out.empty() || out == "." || out == "..") out = "_" + out;
  if (out.size() > 100) out.resize(100);
  return out;
}

}  // namespace emboss
