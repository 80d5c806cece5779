// The kiosk's log lines: priority prefixes, and the journal fields a line becomes.
#include "app/kiosk_log.h"

#include <gtest/gtest.h>

namespace emboss {
namespace {

TEST(KioskLog, PriorityPrefixesAreSplitOff) {
  EXPECT_EQ(splitLogPriority("<7>journal: stroke 3 durable").priority, 7);
  EXPECT_EQ(splitLogPriority("<7>journal: stroke 3 durable").text, "journal: stroke 3 durable");
  EXPECT_EQ(splitLogPriority("<3>journal: cannot write").priority, 3);
  EXPECT_EQ(splitLogPriority("session: saved").priority, 6);
  EXPECT_EQ(splitLogPriority("session: saved").text, "session: saved");
  EXPECT_EQ(splitLogPriority("<9>not a priority").priority, 6);  // only 0..7
  EXPECT_EQ(splitLogPriority("<9>not a priority").text, "<9>not a priority");
  EXPECT_EQ(splitLogPriority("<7").text, "<7");
}

TEST(KioskLog, JournalFieldsCarryTheSessionWhenThereIsOne) {
  const auto f = journalFields("journal: stroke 3 durable", 7, 12, "emboss-kiosk");
  const std::vector<std::string> want = {"MESSAGE=journal: stroke 3 durable", "PRIORITY=7", "SYSLOG_IDENTIFIER=emboss-kiosk",
                                         "EMBOSS_SESSION=12"};
  EXPECT_EQ(f, want);
  const auto none = journalFields("attract: playing 'Rosette'", 6, 0, "emboss-kiosk");
  ASSERT_EQ(none.size(), 3u);
  for (const auto& field : none) EXPECT_EQ(field.rfind("EMBOSS_SESSION=", 0), std::string::npos) << field;
  EXPECT_EQ(journalFields("x", 42, 0, "k")[1], "PRIORITY=7");  // kept within syslog's 0..7
}

TEST(KioskLog, TheSessionIsSetAndCleared) {
  const std::int64_t before = logSession();
  setLogSession(5);
  EXPECT_EQ(logSession(), 5);
  setLogSession(0);
  EXPECT_EQ(logSession(), 0);
  setLogSession(before);
}

}  // namespace
}  // namespace emboss
