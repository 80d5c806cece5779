// Whether stderr is the journal: JOURNAL_STREAM must name stderr's own device and inode.
#include "system/journal_log.h"

#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "test_support.h"

namespace emboss {
namespace {

TEST(JournalLog, JournalStreamMustNameTheFile) {
  const auto dir = test::scratchDir("journal-stream");
  std::ofstream(dir / "stream") << "x";
  struct stat st {};
  ASSERT_EQ(::stat((dir / "stream").c_str(), &st), 0);
  const std::string value = std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
  EXPECT_TRUE(journalStreamIs(value.c_str(), st.st_dev, st.st_ino));
  EXPECT_FALSE(journalStreamIs((std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino + 1)).c_str(), st.st_dev, st.st_ino));
  EXPECT_FALSE(journalStreamIs((value + "x").c_str(), st.st_dev, st.st_ino));
  EXPECT_FALSE(journalStreamIs("", st.st_dev, st.st_ino));
  EXPECT_FALSE(journalStreamIs(nullptr, st.st_dev, st.st_ino));
  EXPECT_FALSE(journalStreamIs("garbage", st.st_dev, st.st_ino));
}

TEST(JournalLog, StderrIsTheJournalOnlyWhenJournalStreamNamesIt) {
  const char* saved = std::getenv("JOURNAL_STREAM");
  const std::string keep = saved ? saved : "";
  struct stat st {};
  ASSERT_EQ(::fstat(STDERR_FILENO, &st), 0);
  ::setenv("JOURNAL_STREAM", (std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino)).c_str(), 1);
  EXPECT_TRUE(stderrIsJournal());
  ::setenv("JOURNAL_STREAM", "1:1", 1);  // inherited from a unit, stderr redirected elsewhere
  EXPECT_FALSE(stderrIsJournal());
  ::unsetenv("JOURNAL_STREAM");
  EXPECT_FALSE(stderrIsJournal());
  if (saved) ::setenv("JOURNAL_STREAM", keep.c_str(), 1);
}

}  // namespace
}  // namespace emboss
