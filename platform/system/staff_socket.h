// The kiosk's end of the staff socket: embossctl's requests, one JSON line each, answered on the main loop.
#pragma once

#include <poll.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "staff/staff_protocol.h"
#include "util/result.h"

namespace emboss {

class StaffSocket {
 public:
  // Answers a request line now, or not yet (nullopt: the poller is asked on later calls, for
  // progress lines to send and, in the end, the answer).
  using Handler = std::function<std::optional<std::string>(const std::string& line)>;
  using Poller = std::function<StaffPending()>;

  // Listens at `path` (a stale socket there is replaced), mode 0660, group `group` when it exists.
  static Result<std::unique_ptr<StaffSocket>> listen(const std::string& path, const std::string& group = "emboss-staff");
  ~StaffSocket();
  StaffSocket(const StaffSocket&) = delete;
  StaffSocket& operator=(const StaffSocket&) = delete;

  // Non-blocking: takes new connections, reads what they sent, answers what can be answered.
  void poll(const Handler& handle, const Poller& pending);
  const std::string& path() const { return path_; }
  // Appends the descriptors to wait on for the next poll() (the listening socket, the connections
  // with a request still to read), POLLIN each.
  void addPollFds(std::vector<pollfd>& out) const;

  // Where the socket is by default: $RUNTIME_DIRECTORY/staff.sock under systemd, else
  // $XDG_RUNTIME_DIR/emboss-kiosk-staff.sock, else /tmp/emboss-kiosk-staff-UID.sock.
  static std::string defaultPath();

 private:
  struct Client {
    int fd = -1;
    std::string in;
    bool waiting = false;
  };
  StaffSocket(int fd, std::string path) : fd_(fd), path_(std::move(path)) {}
  void reply(Client& c, const std::string& line);
  // A progress line: sent if the socket takes it now, skipped if not (the answer still comes);
  // a peer that has gone is closed.
  void note(Client& c, const std::string& line);

  int fd_ = -1;
  std::string path_;
  std::vector<Client> clients_;
};

}  // namespace emboss
