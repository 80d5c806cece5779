// Structured journal entries through sd-journal; the decision whether stderr is the journal.
#include "system/journal_log.h"

#include <sys/stat.h>
#include <sys/uio.h>
#include <systemd/sd-journal.h>
#include <unistd.h>

#include <cinttypes>
#include <cstdio>
#include <cstdlib>

namespace emboss {

bool journalStreamIs(const char* value, dev_t device, ino_t inode) {
  if (!value || !*value) return false;
  std::uintmax_t dev = 0, ino = 0;
  char end = 0;
  if (std::sscanf(value, "%" SCNuMAX ":%" SCNuMAX "%c", &dev, &ino, &end) != 2) return false;
  return dev == std::uintmax_t(device) && ino == std::uintmax_t(inode);
}

bool stderrIsJournal() {
  struct stat st {};
  if (::fstat(STDERR_FILENO, &st) != 0) return false;
  return journalStreamIs(std::getenv("JOURNAL_STREAM"), st.st_dev, st.st_ino);
}

bool sendToJournal(const std::vector<std::string>& fields) {
  std::vector<iovec> iov;
  iov.reserve(fields.size());
  for (const auto& f : fields) iov.push_back({const_cast<char*>(f.data()), f.size()});
  return sd_journal_sendv(iov.data(), int(iov.size())) == 0;
}

}  // namespace emboss
