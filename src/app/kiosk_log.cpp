// The kiosk's log lines: priorities, the session they are about, their journal fields.
#include "app/kiosk_log.h"

#include <atomic>

namespace emboss {

namespace {
std::atomic<std::int64_t> gLogSession{0};
}  // namespace

LogLine splitLogPriority(std::string_view line) {
  LogLine l{6, line};
  if (line.size() >= 3 && line[0] == '<' && line[1] >= '0' && line[1] <= '7' && line[2] == '>') {
    l.priority = line[1] - '0';
    l.text.remove_prefix(3);
  }
  return l;
}

std::int64_t logSession() { return gLogSession.load(std::memory_order_relaxed); }
void setLogSession(std::int64_t id) { gLogSession.store(id, std::memory_order_relaxed); }

std::vector<std::string> journalFields(std::string_view text, int priority, std::int64_t session, std::string_view identifier) {
  std::vector<std::string> f;
  f.push_back("MESSAGE=" + std::string(text));
  f.push_back("PRIORITY=" + std::to_string(priority < 0 ? 0 : priority > 7 ? 7 : priority));
  f.push_back("SYSLOG_IDENTIFIER=" + std::string(identifier));
  if (session > 0) f.push_back("EMBOSS_SESSION=" + std::to_string(session));
  return f;
}

}  // namespace emboss
