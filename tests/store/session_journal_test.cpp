// The session journal: what is written comes back, damage is found and kept out, old sessions go.
#include "store/session_journal.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <fstream>

#include "test_support.h"

namespace emboss {
namespace {

namespace fs = std::filesystem;

struct JournalTest : ::testing::Test {
  fs::path dir = fs::temp_directory_path() / ("journal-test-" + std::to_string(::getpid()) + "-" +
                                              ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::vector<std::string> lines;
  KioskLog log = [this](const std::string& l) { lines.push_back(l); };
  void SetUp() override { fs::remove_all(dir); }
  void TearDown() override { fs::remove_all(dir); }
  bool logged(const std::string& part) const {
    for (const auto& l : lines)
      if (l.find(part) != std::string::npos) return true;
    return false;
  }
};

JournalState stateOf(size_t cursor, std::vector<size_t> strokes, std::vector<size_t> redo, std::uint64_t made) {
  return JournalState{cursor, std::move(strokes), std::move(redo), "brass", made};
}

TEST_F(JournalTest, WhatIsWrittenComesBack) {
  {
    SessionJournal j(dir, log);
    ASSERT_TRUE(j.ok());
    EXPECT_FALSE(j.unfinished());
    j.begin("{\"format\":\"emboss-scene\"}");
    j.operations(0, {"{\"op\":\"a\"}", "{\"op\":\"b\"}"});
    j.state(stateOf(2, {2}, {}, 1));
    j.operations(2, {"{\"op\":\"c\"}"});
    j.state(stateOf(3, {2, 1}, {}, 2));
    j.state(stateOf(2, {2}, {1}, 2));         // undo
    j.operations(2, {"{\"op\":\"d\"}"});      // a new stroke replaces the undone one
    j.state(stateOf(3, {2, 1}, {}, 3));
    ASSERT_TRUE(j.flush(10));
    const auto durable = j.takeDurable();
    ASSERT_FALSE(durable.empty());
    EXPECT_EQ(durable.back().second, 3u);
  }
  SessionJournal j(dir, log);
  const auto s = j.unfinished();
  ASSERT_TRUE(s);
  EXPECT_EQ(s->head, "{\"format\":\"emboss-scene\"}");
  EXPECT_EQ(s->operations, (std::vector<std::string>{"{\"op\":\"a\"}", "{\"op\":\"b\"}", "{\"op\":\"d\"}"}));
  EXPECT_EQ(s->state.cursor, 3u);
  EXPECT_EQ(s->state.strokes, (std::vector<size_t>{2, 1}));
  EXPECT_EQ(s->state.metal, "brass");
  EXPECT_EQ(s->state.strokesMade, 3u);
  EXPECT_EQ(s->dropped, 0u);
  // Ended, it is no longer unfinished; a new session gets a new id.
  j.end();
  j.resume(s->id);
  j.end();
  ASSERT_TRUE(j.flush(10));
  EXPECT_FALSE(j.unfinished());
  const auto id2 = j.begin("{}");
  EXPECT_GT(id2, s->id);
}

TEST_F(JournalTest, AFlippedRecordAndWhatFollowsItAreDropped) {
  {
    SessionJournal j(dir, log);
    j.begin("{}");
    for (int i = 0; i < 5; ++i) {
      j.operations(size_t(i), {"{\"op\":" + std::to_string(i) + "}"});
      j.state(stateOf(size_t(i) + 1, std::vector<size_t>(size_t(i) + 1, 1), {}, std::uint64_t(i) + 1));
    }
    ASSERT_TRUE(j.flush(10));
  }
  // Change one record's body behind the journal's back, as a flipped bit would.
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open((dir / "sessions.db").c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "UPDATE records SET body = '{\"op\":7}' WHERE kind = 'op' AND idx = 3", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(db);
  SessionJournal j(dir, log);
  const auto s = j.unfinished();
  ASSERT_TRUE(s);
  EXPECT_EQ(s->operations.size(), 3u);  // ops 0..2; op 3 fails its checksum and nothing after it is applied
  EXPECT_EQ(s->state.cursor, 3u);
  EXPECT_EQ(s->state.strokesMade, 3u);
  EXPECT_GT(s->dropped, 0u);
}

TEST_F(JournalTest, AFileThatIsNotADatabaseIsMovedAsideAndTheJournalWorks) {
  fs::create_directories(dir);
  {
    std::ofstream f(dir / "sessions.db", std::ios::binary);
    for (int i = 0; i < 5000; ++i) f.put(char(i * 37));
  }
  SessionJournal j(dir, log);
  ASSERT_TRUE(j.ok());
  EXPECT_TRUE(logged("moved aside"));
  bool aside = false;
  for (const auto& e : fs::directory_iterator(dir)) aside |= e.path().filename().string().rfind("sessions.db.corrupt-", 0) == 0;
  EXPECT_TRUE(aside);
  j.begin("{}");
  j.operations(0, {"{}"});
  ASSERT_TRUE(j.flush(10));
  EXPECT_TRUE(j.unfinished());
}


// A database that is sound but not the kiosk's (a column renamed, a trigger, an absurd id) would
// take or refuse the writes for good: it is moved aside like a damaged one, what fits is kept.
TEST_F(JournalTest, ADatabaseWithAForeignSchemaIsMovedAsideAndTheJournalWorks) {
  const char* foreign[] = {
      // The records table without its crc column (what a fuzzer found).
      "CREATE TABLE sessions(id INTEGER PRIMARY KEY, started REAL NOT NULL, last REAL NOT NULL,"
      " ended REAL NOT NULL DEFAULT 0, head TEXT NOT NULL, crc INTEGER NOT NULL);"
      "CREATE TABLE records(session INTEGER NOT NULL, seq INTEGER NOT NULL, kind TEXT NOT NULL,"
      " idx INTEGER NOT NULL, body TEXT NOT NULL, cI crNTEGER NOT NULL, PRIMARY KEY(session, seq)) WITHOUT ROWID;"
      "INSERT INTO sessions VALUES(4, 1, 2, 0, '{\"kept\":1}', 0);",
      // A trigger that refuses every record.
      "CREATE TABLE sessions(id INTEGER PRIMARY KEY, started REAL NOT NULL, last REAL NOT NULL,"
      " ended REAL NOT NULL DEFAULT 0, head TEXT NOT NULL, crc INTEGER NOT NULL);"
      "CREATE TRIGGER no BEFORE INSERT ON sessions BEGIN SELECT RAISE(ABORT, 'no'); END;",
      // A session id the next one would overflow from.
      "CREATE TABLE sessions(id INTEGER PRIMARY KEY, started REAL NOT NULL, last REAL NOT NULL,"
      " ended REAL NOT NULL DEFAULT 0, head TEXT NOT NULL, crc INTEGER NOT NULL);"
      "INSERT INTO sessions VALUES(9223372036854775807, 1, 2, 1, '{}', 0);"
      "INSERT INTO sessions VALUES(4, 1, 2, 0, '{\"kept\":1}', 0);",
  };
  for (const char* sql : foreign) {
    SCOPED_TRACE(sql);
    fs::remove_all(dir);
    fs::create_directories(dir);
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open((dir / "sessions.db").c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, sql, nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
    lines.clear();
    SessionJournal j(dir, log);
    ASSERT_TRUE(j.ok());
    EXPECT_TRUE(logged("foreign schema"));
    EXPECT_TRUE(logged("moved aside"));
    for (const auto& s : j.list()) EXPECT_LE(s.id, std::int64_t(1) << 40);
    const auto id = j.begin("{}");
    EXPECT_GT(id, 0);
    j.operations(0, {"{}"});
    ASSERT_TRUE(j.flush(10));
    const auto s = j.unfinished();
    ASSERT_TRUE(s);
    EXPECT_EQ(s->id, id);
    EXPECT_EQ(s->operations.size(), 1u);
  }
}
TEST_F(JournalTest, AFolderThatCannotBeWrittenLeavesTheJournalOffNotTheKiosk) {
  fs::create_directories(dir);
  { std::ofstream f(dir / "not-a-folder"); }
  SessionJournal j(dir / "not-a-folder", log);
  EXPECT_FALSE(j.ok());
  EXPECT_TRUE(logged("not journalled"));
  j.begin("{}");  // harmless
  j.operations(0, {"{}"});
  EXPECT_TRUE(j.flush(1));
}

TEST_F(JournalTest, PruneDropsOldFinishedSessionsThenTheOldestBySize) {
  double now = 1000;
  SessionJournal j(dir, log, [&] { return now; });
  for (int s = 0; s < 4; ++s) {
    j.begin("{}");
    j.operations(0, {std::string(1000, 'x')});
    now += 100;
    j.end();
  }
  j.begin("{}");  // unfinished: never pruned
  j.operations(0, {std::string(1000, 'y')});
  ASSERT_TRUE(j.flush(10));
  EXPECT_EQ(j.prune(1150, 1u << 30), 1u);  // the first session ended at 1100
  EXPECT_EQ(j.list().size(), 4u);
  EXPECT_EQ(j.prune(0, 2500), 2u);         // two more go to fit 2500 bytes; the unfinished one stays
  const auto left = j.list();
  ASSERT_EQ(left.size(), 2u);
  EXPECT_EQ(left.back().ended, 0.0);
}

}  // namespace
}  // namespace emboss
