// Logging to the systemd journal with fields of its own (sd-journal), when stderr is the journal.
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace emboss {

// Whether JOURNAL_STREAM's value ("DEVICE:INODE", as systemd sets it for a unit's stdout/stderr)
// names the file with this device and inode.
bool journalStreamIs(const char* value, dev_t device, ino_t inode);
// Whether stderr is the journal's stream: JOURNAL_STREAM set and naming stderr (not a terminal or
// a file it was redirected to, where it would only be inherited).
bool stderrIsJournal();
// Sends one entry of fields ("NAME=value") with sd_journal_sendv. False when the journal did not take it.
bool sendToJournal(const std::vector<std::string>& fields);

}  // namespace emboss
