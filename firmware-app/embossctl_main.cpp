// embossctl: the staff tool. Speaks the staff protocol (src/staff) to the running kiosk over its Unix socket.
#include <sys/socket.h>
#include <sys/un.h>
#include <poll.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "staff/staff_protocol.h"
#include "system/staff_socket.h"
#include "version.h"

using namespace emboss;

namespace {

// Sends one request line, returns the answer line (or a message why there is none). Progress lines
// that come before it go to `progress`; each restarts the timeout, which counts silence.
Result<std::string> ask(const std::string& path, const std::string& line, double timeoutSeconds,
                        const std::function<void(const StaffProgress&)>& progress) {
  sockaddr_un addr{};
  if (path.size() >= sizeof addr.sun_path) return fail("the socket path is too long");
  addr.sun_family = AF_UNIX;
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return fail(std::strerror(errno));
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    const int err = errno;
    ::close(fd);
    return fail("cannot reach the kiosk at " + path + ": " + std::strerror(err) +
                (err == EACCES ? " (are you in the group emboss-staff?)" : err == ENOENT || err == ECONNREFUSED ? " (is emboss-kiosk running?)" : ""));
  }
  const std::string out = line + "\n";
  if (::send(fd, out.data(), out.size(), MSG_NOSIGNAL) != ssize_t(out.size())) {
    ::close(fd);
    return fail("cannot send the request");
  }
  std::string in;
  const auto silence = std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(timeoutSeconds));
  auto deadline = std::chrono::steady_clock::now() + silence;
  char buf[4096];
  for (;;) {
    // Whole lines first: progress lines are shown, the first other line is the answer.
    for (size_t nl; (nl = in.find('\n')) != std::string::npos;) {
      std::string got = in.substr(0, nl);
      in.erase(0, nl + 1);
      if (auto p = parseStaffProgress(got)) {
        if (progress) progress(*p);
        deadline = std::chrono::steady_clock::now() + silence;
        continue;
      }
      ::close(fd);
      return got;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) {
      ::close(fd);
      return fail("the kiosk did not answer within " + std::to_string(int(timeoutSeconds)) + " s");
    }
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, int(std::min<long long>(left, 1000))) <= 0) continue;
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) break;
    in.append(buf, size_t(n));
  }
  ::close(fd);
  return fail("the kiosk closed the connection without an answer");
}

void printValue(const std::string& key, const nlohmann::json& v, int indent) {
  const std::string pad(size_t(indent) * 2, ' ');
  if (v.is_object()) {
    std::printf("%s%s:\n", pad.c_str(), key.c_str());
    for (auto it = v.begin(); it != v.end(); ++it) printValue(it.key(), it.value(), indent + 1);
  } else if (v.is_array()) {
    std::printf("%s%s: %zu\n", pad.c_str(), key.c_str(), v.size());
    for (const auto& e : v) std::printf("%s  - %s\n", pad.c_str(), e.is_string() ? e.get<std::string>().c_str() : e.dump().c_str());
  } else {
    std::printf("%s%s: %s\n", pad.c_str(), key.c_str(), v.is_string() ? v.get<std::string>().c_str() : v.dump().c_str());
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"embossctl: the staff tool of the emboss kiosk (status, sessions, export, reset, wipe)"};
  std::string socketPath, since, dest;
  bool json = false, allowAnyDir = false;
  double olderThan = -1;
  cli.add_option("--socket", socketPath, "The kiosk's staff socket (default: " + StaffSocket::defaultPath() + ")");
  cli.add_flag("--json", json, "Print the kiosk's answer as it came (one JSON line)");
  cli.set_version_flag("--version", std::string("embossctl ") + emboss::versionString());
  cli.require_subcommand(1);
  cli.add_subcommand("status", "State, devices, frame rate, latency, sessions, disk");
  cli.add_subcommand("sessions", "The sessions kept");
  auto* exp = cli.add_subcommand("export", "Copy the sessions (scene files and pictures) to DEST, a mounted USB stick");
  exp->add_option("--since", since, "Only sessions since YYYY-MM-DD, or the last N days (7d)");
  exp->add_flag("--allow-any-dir", allowAnyDir, "Allow a folder on the kiosk's own disk (for tests)");
  exp->add_option("DEST", dest, "The folder to export into (the stick's mount point)")->required();
  cli.add_subcommand("reset", "End the visitor's session now (it is saved) and return to attract mode");
  auto* wipe = cli.add_subcommand("wipe", "Delete sessions finished more than DAYS days ago (privacy)");
  wipe->add_option("--older-than", olderThan, "DAYS")->required()->check(CLI::Range(0.0, 36500.0));
  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cli.exit(e) == 0 ? 0 : 2;
  }
  StaffRequest req;
  const std::string cmd = cli.get_subcommands().front()->get_name();
  double timeout = 10;
  if (cmd == "status") req.command = StaffRequest::Command::Status;
  else if (cmd == "sessions") req.command = StaffRequest::Command::Sessions;
  else if (cmd == "reset") req.command = StaffRequest::Command::Reset;
  else if (cmd == "wipe") req.command = StaffRequest::Command::Wipe, req.olderThanDays = olderThan;
  else {
    req.command = StaffRequest::Command::Export;
    char resolved[PATH_MAX];
    if (!::realpath(dest.c_str(), resolved)) {
      std::fprintf(stderr, "embossctl: export: '%s': %s\n", dest.c_str(), std::strerror(errno));
      return 1;
    }
    req.dest = resolved;
    req.allowAnyDir = allowAnyDir;
    if (!since.empty()) {
      const double now = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
      auto s = parseSince(since, now);
      if (!s) {
        std::fprintf(stderr, "embossctl: %s\n", s.error().c_str());
        return 2;
      }
      req.sinceUnix = *s;
    }
    req.progress = true;
    timeout = 600;  // without a word from the kiosk; every progress line starts it again
    std::fprintf(stderr, "embossctl: exporting to %s ...\n", req.dest.c_str());
  }
  const auto showProgress = [](const StaffProgress& p) {
    std::fprintf(stderr, "export: %s\n", staffProgressText(p).c_str());
    std::fflush(stderr);
  };
  auto a = ask(socketPath.empty() ? StaffSocket::defaultPath() : socketPath, staffRequestLine(req), timeout, showProgress);
  if (!a) {
    std::fprintf(stderr, "embossctl: %s\n", a.error().c_str());
    return 1;
  }
  const nlohmann::json j = nlohmann::json::parse(*a, nullptr, false);
  if (!j.is_object()) {
    std::fprintf(stderr, "embossctl: the kiosk's answer is not JSON: %s\n", a->c_str());
    return 1;
  }
  if (!j.value("ok", false)) {
    std::fprintf(stderr, "embossctl: %s\n", j.value("error", std::string("refused")).c_str());
    return 1;
  }
  if (json) std::printf("%s\n", a->c_str());
  else
    for (auto it = j.begin(); it != j.end(); ++it)
      if (it.key() != "ok") printValue(it.key(), it.value(), 0);
  return 0;
}
