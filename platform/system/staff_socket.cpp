// The staff socket: a Unix stream socket, non-blocking, polled by the kiosk's main loop.
#include "system/staff_socket.h"

#include <fcntl.h>
#include <grp.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace emboss {

namespace {
constexpr size_t kMaxRequest = 64 * 1024;  // a longer line is not a request
constexpr size_t kMaxClients = 8;
}  // namespace

std::string StaffSocket::defaultPath() {
  if (const char* r = std::getenv("RUNTIME_DIRECTORY"); r && *r) {
    std::string first(r);
    if (const auto colon = first.find(':'); colon != std::string::npos) first.resize(colon);
    return first + "/staff.sock";
  }
  if (const char* x = std::getenv("XDG_RUNTIME_DIR"); x && *x) return std::string(x) + "/emboss-kiosk-staff.sock";
  return "/tmp/emboss-kiosk-staff-" + std::to_string(::getuid()) + ".sock";
}

Result<std::unique_ptr<StaffSocket>> StaffSocket::listen(const std::string& path, const std::string& group) {
  sockaddr_un addr{};
  if (path.size() >= sizeof addr.sun_path) return fail("staff socket: the path '" + path + "' is too long");
  addr.sun_family = AF_UNIX;
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) return fail(std::string("staff socket: ") + std::strerror(errno));
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0 && S_ISSOCK(st.st_mode)) ::unlink(path.c_str());  // left by a kiosk that was killed
  const mode_t old = ::umask(0117);
  const int rc = ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
  const int err = errno;
  ::umask(old);
  if (rc != 0 || ::listen(fd, 4) != 0) {
    ::close(fd);
    return fail("staff socket: cannot listen at '" + path + "': " + std::strerror(rc != 0 ? err : errno));
  }
  ::chmod(path.c_str(), 0660);
  if (const struct group* g = ::getgrnam(group.c_str())) {
    if (::chown(path.c_str(), uid_t(-1), g->gr_gid) != 0) { /* not a member: the socket stays the kiosk's group */ }
  }
  return std::unique_ptr<StaffSocket>(new StaffSocket(fd, path));
}

StaffSocket::~StaffSocket() {
  for (auto& c : clients_) ::close(c.fd);
  if (fd_ >= 0) {
    ::close(fd_);
    ::unlink(path_.c_str());
  }
}

namespace {

// Sends all of `out` from `done` on. The lines are small; a peer that does not read them within a
// few tries is given up on (false).
bool sendRest(int fd, const std::string& out, size_t done) {
  for (int tries = 0; done < out.size() && tries < 50; ++tries) {
    const ssize_t n = ::send(fd, out.data() + done, out.size() - done, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n > 0) done += size_t(n);
    else if (n < 0 && errno != EAGAIN && errno != EINTR) return false;
    else ::usleep(1000);
  }
  return done == out.size();
}

}  // namespace

void StaffSocket::reply(Client& c, const std::string& line) {
  sendRest(c.fd, line + "\n", 0);
  ::close(c.fd);
  c.fd = -1;
}

void StaffSocket::note(Client& c, const std::string& line) {
  const std::string out = line + "\n";
  const ssize_t n = ::send(c.fd, out.data(), out.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) return;  // not read yet: this line is skipped
  if (n < 0 || !sendRest(c.fd, out, size_t(n))) {  // embossctl is gone (the export goes on)
    ::close(c.fd);
    c.fd = -1;
  }
}

void StaffSocket::poll(const Handler& handle, const Poller& pending) {
  for (;;) {
    const int c = ::accept4(fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (c < 0) break;
    if (clients_.size() >= kMaxClients) {
      ::close(c);
      continue;
    }
    clients_.push_back(Client{c, {}, false});
  }
  for (auto& c : clients_) {
    if (c.waiting) {
      StaffPending p = pending();
      for (const auto& line : p.progress)
        if (c.fd >= 0) note(c, line);
      if (p.answer && c.fd >= 0) reply(c, *p.answer);
      continue;
    }
    char buf[4096];
    for (;;) {
      const ssize_t n = ::recv(c.fd, buf, sizeof buf, 0);
      if (n > 0) {
        c.in.append(buf, size_t(n));
        if (c.in.size() > kMaxRequest) break;
        continue;
      }
      if (n == 0 && c.in.find('\n') == std::string::npos) {  // closed without a whole line
        ::close(c.fd), c.fd = -1;
      }
      break;
    }
    if (c.fd < 0) continue;
    if (c.in.size() > kMaxRequest) {
      reply(c, R"({"ok":false,"error":"the request is too long"})");
      continue;
    }
    const auto nl = c.in.find('\n');
    if (nl == std::string::npos) continue;
    const std::string line = c.in.substr(0, nl);
    if (auto a = handle(line)) reply(c, *a);
    else c.waiting = true;
  }
  std::erase_if(clients_, [](const Client& c) { return c.fd < 0; });
}

void StaffSocket::addPollFds(std::vector<pollfd>& out) const {
  out.push_back({fd_, POLLIN, 0});
  for (const Client& c : clients_)
    if (c.fd >= 0 && !c.waiting) out.push_back({c.fd, POLLIN, 0});
}

}  // namespace emboss
