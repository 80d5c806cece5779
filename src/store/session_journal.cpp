// The session journal on SQLite: schema, the writer thread, reading back, salvaging a damaged store.
#include "store/session_journal.h"

#include <sqlite3.h>
#include <zlib.h>

#include <chrono>
#include <ctime>

#include <nlohmann/json.hpp>

#include "util/file_stamp.h"

namespace emboss {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr double kRetrySeconds = 1.0;  // a write the disk refused is tried again this often (recovery within 2 s)

// The two tables, as SQLite keeps their text in sqlite_master (without "IF NOT EXISTS").
#define EMBOSS_SESSIONS_TABLE                                                                       \
  "sessions(id INTEGER PRIMARY KEY, started REAL NOT NULL, last REAL NOT NULL,"                    \
  " ended REAL NOT NULL DEFAULT 0, head TEXT NOT NULL, crc INTEGER NOT NULL)"
#define EMBOSS_RECORDS_TABLE                                                                        \
  "records(session INTEGER NOT NULL, seq INTEGER NOT NULL, kind TEXT NOT NULL,"                    \
  " idx INTEGER NOT NULL, body TEXT NOT NULL, crc INTEGER NOT NULL, PRIMARY KEY(session, seq)) WITHOUT ROWID"
const char* const kSchema =
    "CREATE TABLE IF NOT EXISTS " EMBOSS_SESSIONS_TABLE ";"
    "CREATE TABLE IF NOT EXISTS " EMBOSS_RECORDS_TABLE ";";
const char* const kSessionsSql = "CREATE TABLE " EMBOSS_SESSIONS_TABLE;
const char* const kRecordsSql = "CREATE TABLE " EMBOSS_RECORDS_TABLE;
#undef EMBOSS_SESSIONS_TABLE
#undef EMBOSS_RECORDS_TABLE

// Session ids a kiosk can reach (one a minute for two thousand years is far below); a store with
// larger ones was not written by the kiosk, and the next id must not overflow.
constexpr std::int64_t kMaxSessionId = std::int64_t(1) << 40;

// A prepared statement that finalizes itself.
class Stmt {
 public:
  Stmt(sqlite3* db, const char* sql) { rc_ = sqlite3_prepare_v2(db, sql, -1, &s_, nullptr); }
  ~Stmt() { sqlite3_finalize(s_); }
  Stmt(const Stmt&) = delete;
  Stmt& operator=(const Stmt&) = delete;
  bool ok() const { return rc_ == SQLITE_OK && s_; }
  sqlite3_stmt* get() const { return s_; }
  Stmt& bind(int i, std::int64_t v) { sqlite3_bind_int64(s_, i, v); return *this; }
  Stmt& bind(int i, double v) { sqlite3_bind_double(s_, i, v); return *this; }
  Stmt& bind(int i, const std::string& v) { sqlite3_bind_text(s_, i, v.data(), int(v.size()), SQLITE_TRANSIENT); return *this; }
  int step() { return s_ ? sqlite3_step(s_) : rc_; }
  void reset() { sqlite3_reset(s_); sqlite3_clear_bindings(s_); }
  std::int64_t i64(int c) const { return sqlite3_column_int64(s_, c); }
  double real(int c) const { return sqlite3_column_double(s_, c); }
  std::string text(int c) const {
    const auto* p = sqlite3_column_text(s_, c);
    return p ? std::string(reinterpret_cast<const char*>(p), size_t(sqlite3_column_bytes(s_, c))) : std::string();
  }

 private:
  sqlite3_stmt* s_ = nullptr;
  int rc_ = SQLITE_ERROR;
};

// What a record's checksum covers: its kind, index and body.
std::uint32_t recordCrc(const std::string& kind, std::int64_t idx, const std::string& body) {
  return recordChecksum(kind + "|" + std::to_string(idx) + "|" + body);
}

std::string errorOf(sqlite3* db, const char* what) { return std::string(what) + ": " + (db ? sqlite3_errmsg(db) : "no database"); }

bool exec(sqlite3* db, const char* sql, std::string* error = nullptr) {
  char* msg = nullptr;
  const int rc = sqlite3_exec(db, sql, nullptr, nullptr, &msg);
  if (rc != SQLITE_OK && error) *error = msg ? msg : sqlite3_errstr(rc);
  sqlite3_free(msg);
  return rc == SQLITE_OK;
}

// Empty when the store holds exactly the kiosk's two tables and sane ids, else what is foreign
// about it: a database with other tables, triggers, views or columns of the same names would
// take the store's writes into something else, or refuse them for good.
std::string foreignSchema(sqlite3* db) {
  Stmt s(db, "SELECT type, name, sql FROM sqlite_master");
  if (!s.ok()) return errorOf(db, "schema");
  int ours = 0;
  int rc;
  while ((rc = s.step()) == SQLITE_ROW) {
    const std::string type = s.text(0), name = s.text(1), sql = s.text(2);
    if (type == "table" && name == "sessions" && sql == kSessionsSql) ++ours;
    else if (type == "table" && name == "records" && sql == kRecordsSql) ++ours;
    else if (type == "index" && name.rfind("sqlite_autoindex_", 0) == 0 && sqlite3_column_type(s.get(), 2) == SQLITE_NULL) continue;
    else return "foreign schema: " + type + " " + name;
  }
  if (rc != SQLITE_DONE) return errorOf(db, "schema");
  if (ours != 2) return "foreign schema: tables missing";
  Stmt ids(db, "SELECT COUNT(*) FROM sessions WHERE id < 1 OR id > ?");
  if (!ids.ok() || ids.bind(1, kMaxSessionId).step() != SQLITE_ROW) return errorOf(db, "ids");
  if (ids.i64(0) != 0) return "foreign schema: session ids out of range";
  return {};
}

}  // namespace

std::uint32_t recordChecksum(const std::string& text) {
  return std::uint32_t(crc32(0L, reinterpret_cast<const Bytef*>(text.data()), uInt(text.size())));
}

SessionJournal::SessionJournal(fs::path dir, KioskLog log, WallClock wall)
    : dir_(std::move(dir)), path_(dir_ / "sessions.db"), log_(std::move(log)), wall_(std::move(wall)) {
  open();
  if (db_) thread_ = std::thread([this] { run(); });
}

SessionJournal::~SessionJournal() {
  {
    std::lock_guard lock(m_);
    stop_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (!queue_.empty() && log_)
    log_("<3>journal: " + std::to_string(queue_.size()) + " records could not be written (" + error_ + ")");
  if (db_) sqlite3_close_v2(db_);
}

double SessionJournal::now() const {
  if (wall_) return wall_();
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

void SessionJournal::open() {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  std::string why;
  for (int attempt = 0; attempt < 2; ++attempt) {
    if (db_) sqlite3_close_v2(db_), db_ = nullptr;
    const int rc = sqlite3_open_v2(path_.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX, nullptr);
    if (rc != SQLITE_OK) {
      why = errorOf(db_, "cannot open");
    } else {
      sqlite3_busy_timeout(db_, 2000);
      std::string err;
      std::string check;
      if (!exec(db_, "PRAGMA journal_mode=WAL", &err) || !exec(db_, "PRAGMA synchronous=FULL", &err)) {
        why = err;
      } else {
        Stmt qc(db_, "PRAGMA quick_check");
        if (qc.ok() && qc.step() == SQLITE_ROW) check = qc.text(0);
        else why = errorOf(db_, "quick_check");
        if (why.empty() && check != "ok") why = "quick_check: " + check;
        if (why.empty() && !exec(db_, kSchema, &err)) why = err;
        if (why.empty()) why = foreignSchema(db_);
      }
    }
    if (why.empty()) break;
    // A folder that cannot be written is not the store's fault: leave the store alone.
    if (rc == SQLITE_CANTOPEN || rc == SQLITE_READONLY || rc == SQLITE_PERM || rc == SQLITE_IOERR || attempt == 1 ||
        why.find("readonly") != std::string::npos || why.find("disk I/O") != std::string::npos) {
      if (log_) log_("<3>journal: " + path_.string() + ": " + why + "; sessions are not journalled");
      if (db_) sqlite3_close_v2(db_), db_ = nullptr;
      return;
    }
    if (!salvage(why)) {
      if (db_) sqlite3_close_v2(db_), db_ = nullptr;
      return;
    }
    why.clear();
  }
  Stmt max(db_, "SELECT COALESCE(MAX(id), 0) FROM sessions");
  nextId_ = (max.ok() && max.step() == SQLITE_ROW ? max.i64(0) : 0) + 1;
}

bool SessionJournal::salvage(const std::string& why) {
  if (db_) sqlite3_close_v2(db_), db_ = nullptr;
  const fs::path aside = dir_ / ("sessions.db.corrupt-" + fileStamp());
  std::error_code ec;
  fs::rename(path_, aside, ec);
  if (ec) {
    if (log_) log_("<3>journal: " + path_.string() + " is damaged (" + why + ") and cannot be moved aside: " + ec.message());
    return false;
  }
  for (const char* suffix : {"-wal", "-shm"}) {
    const fs::path p = path_.string() + suffix;
    if (fs::exists(p, ec)) fs::rename(p, aside.string() + suffix, ec);
  }
  // A fresh store, then what can still be read of the old one, row by row until it fails.
  sqlite3* fresh = nullptr;
  if (sqlite3_open_v2(path_.c_str(), &fresh, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) != SQLITE_OK ||
      !exec(fresh, "PRAGMA journal_mode=WAL") || !exec(fresh, "PRAGMA synchronous=FULL") || !exec(fresh, kSchema)) {
    if (log_) log_("<3>journal: cannot create a fresh " + path_.string() + ": " + errorOf(fresh, "open"));
    sqlite3_close_v2(fresh);
    return false;
  }
  size_t sessions = 0, records = 0;
  sqlite3* old = nullptr;
  if (sqlite3_open_v2(aside.c_str(), &old, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    exec(fresh, "BEGIN");
    {
      Stmt in(old, "SELECT id, started, last, ended, head, crc FROM sessions WHERE id >= 1 AND id <= ?");
      if (in.ok()) in.bind(1, kMaxSessionId);
      Stmt out(fresh, "INSERT OR IGNORE INTO sessions VALUES(?,?,?,?,?,?)");
      while (in.ok() && out.ok() && in.step() == SQLITE_ROW) {
        out.bind(1, in.i64(0)).bind(2, in.real(1)).bind(3, in.real(2)).bind(4, in.real(3)).bind(5, in.text(4)).bind(6, in.i64(5));
        if (out.step() == SQLITE_DONE) ++sessions;
        out.reset();
      }
    }
    {
      Stmt in(old, "SELECT session, seq, kind, idx, body, crc FROM records WHERE session >= 1 AND session <= ?");
      if (in.ok()) in.bind(1, kMaxSessionId);
      Stmt out(fresh, "INSERT OR IGNORE INTO records VALUES(?,?,?,?,?,?)");
      while (in.ok() && out.ok() && in.step() == SQLITE_ROW) {
        out.bind(1, in.i64(0)).bind(2, in.i64(1)).bind(3, in.text(2)).bind(4, in.i64(3)).bind(5, in.text(4)).bind(6, in.i64(5));
        if (out.step() == SQLITE_DONE) ++records;
        out.reset();
      }
    }
    exec(fresh, "COMMIT");
  }
  sqlite3_close_v2(old);
  sqlite3_close_v2(fresh);
  if (log_)
    log_("<4>journal: " + path_.string() + " was damaged (" + why + "); moved aside as " + aside.filename().string() + ", kept " +
         std::to_string(sessions) + " sessions and " + std::to_string(records) + " records that could be read");
  return true;
}

std::optional<JournalSession> SessionJournal::unfinished() {
  flush(5.0);
  std::lock_guard lock(dbm_);
  if (!db_) return std::nullopt;
  Stmt s(db_, "SELECT id, started, last, head, crc FROM sessions WHERE ended = 0 ORDER BY id DESC LIMIT 1");
  if (!s.ok() || s.step() != SQLITE_ROW) return std::nullopt;
  JournalSession js;
  js.id = s.i64(0), js.started = s.real(1), js.last = s.real(2), js.head = s.text(3);
  if (recordChecksum(js.head) != std::uint32_t(s.i64(4))) {
    if (log_) log_("<4>journal: session " + std::to_string(js.id) + "'s head fails its checksum; it is not restored");
    return std::nullopt;
  }
  Stmt r(db_, "SELECT kind, idx, body, crc FROM records WHERE session = ? ORDER BY seq");
  r.bind(1, js.id);
  bool broken = false;
  while (r.ok() && r.step() == SQLITE_ROW) {
    if (broken) {
      ++js.dropped;
      continue;
    }
    const std::string kind = r.text(0), body = r.text(2);
    const std::int64_t idx = r.i64(1);
    if (recordCrc(kind, idx, body) != std::uint32_t(r.i64(3)) || idx < 0) {
      broken = true;  // nothing after a damaged record can be trusted to apply to what came before
      ++js.dropped;
      continue;
    }
    ++js.records;
    if (kind == "op") {
      if (size_t(idx) > js.operations.size()) {
        broken = true, ++js.dropped;
        continue;
      }
      js.operations.resize(size_t(idx));
      js.operations.push_back(body);
    } else if (kind == "state") {
      try {
        const json j = json::parse(body);
        js.state.cursor = j.at("cursor").get<size_t>();
        js.state.strokes = j.at("strokes").get<std::vector<size_t>>();
        js.state.redo = j.at("redo").get<std::vector<size_t>>();
        js.state.metal = j.at("metal").get<std::string>();
        js.state.strokesMade = j.at("made").get<std::uint64_t>();
      } catch (const std::exception&) {
        broken = true, ++js.dropped;
      }
    }
  }
  if (js.state.cursor > js.operations.size()) js.state.cursor = js.operations.size();
  return js;
}

std::vector<SessionJournal::Summary> SessionJournal::list() {
  flush(5.0);
  std::lock_guard lock(dbm_);
  std::vector<Summary> out;
  if (!db_) return out;
  Stmt s(db_, "SELECT id, started, ended, (SELECT COUNT(*) FROM records r WHERE r.session = s.id AND r.kind = 'op')"
              " FROM sessions s ORDER BY id");
  while (s.ok() && s.step() == SQLITE_ROW) out.push_back({s.i64(0), s.real(1), s.real(2), size_t(s.i64(3))});
  return out;
}

void SessionJournal::push(Record r) {
  if (!db_) return;
  {
    std::lock_guard lock(m_);
    queue_.push_back(std::move(r));
  }
  cv_.notify_all();
}

std::int64_t SessionJournal::begin(const std::string& head) {
  const std::int64_t id = nextId_++;
  Record r;
  r.kind = Record::Kind::Begin;
  r.id = id, r.head = head, r.at = now();
  push(std::move(r));
  return id;
}

void SessionJournal::resume(std::int64_t id) {
  if (id >= nextId_) nextId_ = id + 1;
  Record r;
  r.kind = Record::Kind::Resume;
  r.id = id;
  push(std::move(r));
}

void SessionJournal::operations(size_t from, std::vector<std::string> ops) {
  if (ops.empty()) return;
  Record r;
  r.kind = Record::Kind::Ops;
  r.from = from, r.texts = std::move(ops), r.at = now();
  push(std::move(r));
}

void SessionJournal::state(const JournalState& s) {
  Record r;
  r.kind = Record::Kind::State;
  r.texts.push_back(json{{"cursor", s.cursor}, {"strokes", s.strokes}, {"redo", s.redo}, {"metal", s.metal}, {"made", s.strokesMade}}.dump());
  r.stroke = s.strokesMade, r.at = now();
  push(std::move(r));
}

void SessionJournal::end() {
  Record r;
  r.kind = Record::Kind::End;
  r.at = now();
  push(std::move(r));
}

void SessionJournal::endSession(std::int64_t id) {
  Record r;
  r.kind = Record::Kind::EndId;
  r.id = id, r.at = now();
  push(std::move(r));
}

size_t SessionJournal::prune(double before, std::uintmax_t maxBytes) {
  if (!db_) return 0;
  flush(5.0);
  std::lock_guard lock(dbm_);
  size_t n = 0;
  Stmt del(db_, "DELETE FROM records WHERE session = ?");
  Stmt dels(db_, "DELETE FROM sessions WHERE id = ?");
  auto drop = [&](std::int64_t id) {
    del.bind(1, id).step(), del.reset();
    if (dels.bind(1, id).step() == SQLITE_DONE && sqlite3_changes(db_) > 0) ++n;
    dels.reset();
  };
  exec(db_, "BEGIN IMMEDIATE");
  {
    Stmt old(db_, "SELECT id FROM sessions WHERE ended > 0 AND ended < ? ORDER BY id");
    old.bind(1, before);
    std::vector<std::int64_t> ids;
    while (old.ok() && old.step() == SQLITE_ROW) ids.push_back(old.i64(0));
    for (auto id : ids) drop(id);
  }
  // Then by size: the bytes of the records and heads, oldest finished sessions first.
  for (;;) {
    Stmt size(db_, "SELECT COALESCE((SELECT SUM(LENGTH(body)) FROM records), 0) + COALESCE((SELECT SUM(LENGTH(head)) FROM sessions), 0)");
    if (!size.ok() || size.step() != SQLITE_ROW || std::uintmax_t(size.i64(0)) <= maxBytes) break;
    Stmt oldest(db_, "SELECT id FROM sessions WHERE ended > 0 ORDER BY id LIMIT 1");
    if (!oldest.ok() || oldest.step() != SQLITE_ROW) break;
    drop(oldest.i64(0));
  }
  std::string err;
  if (!exec(db_, "COMMIT", &err)) {
    exec(db_, "ROLLBACK");
    if (log_) log_("<4>journal: pruning failed: " + err);
    return 0;
  }
  if (n) exec(db_, "PRAGMA wal_checkpoint(TRUNCATE)");
  return n;
}

std::vector<std::pair<std::int64_t, std::uint64_t>> SessionJournal::takeDurable() {
  std::lock_guard lock(m_);
  std::vector<std::pair<std::int64_t, std::uint64_t>> out;
  out.swap(durable_);
  return out;
}

size_t SessionJournal::queued() const {
  std::lock_guard lock(m_);
  return queue_.size() + (writing_ ? 1 : 0);
}

std::string SessionJournal::lastError() const {
  std::lock_guard lock(m_);
  return error_;
}

bool SessionJournal::flush(double seconds) {
  std::unique_lock lock(m_);
  if (!db_) return true;
  return idle_.wait_for(lock, std::chrono::duration<double>(seconds), [&] { return queue_.empty() && !writing_; });
}

bool SessionJournal::write(std::deque<Record>& batch, std::vector<std::pair<std::int64_t, std::uint64_t>>& durable) {
  if (!exec(db_, "BEGIN IMMEDIATE")) return false;
  bool ok = true;
  std::int64_t cur = current_;
  double last = 0;
  {
    Stmt seq(db_, "SELECT COALESCE(MAX(seq), 0) FROM records WHERE session = ?");
    Stmt rec(db_, "INSERT OR REPLACE INTO records(session, seq, kind, idx, body, crc) VALUES(?,?,?,?,?,?)");
    Stmt beg(db_, "INSERT OR REPLACE INTO sessions(id, started, last, ended, head, crc) VALUES(?,?,?,0,?,?)");
    Stmt end(db_, "UPDATE sessions SET ended = ?, last = MAX(last, ?) WHERE id = ?");
    Stmt touch(db_, "UPDATE sessions SET last = ? WHERE id = ?");
    ok = seq.ok() && rec.ok() && beg.ok() && end.ok() && touch.ok();
    std::int64_t next = 0;
    auto nextSeq = [&]() {
      if (next == 0) {
        seq.bind(1, cur);
        next = (seq.step() == SQLITE_ROW ? seq.i64(0) : 0) + 1;
        seq.reset();
      }
      return next++;
    };
    auto record = [&](const char* kind, std::int64_t idx, const std::string& body) {
      rec.bind(1, cur).bind(2, nextSeq()).bind(3, std::string(kind)).bind(4, idx).bind(5, body);
      rec.bind(6, std::int64_t(recordCrc(kind, idx, body)));
      ok = ok && rec.step() == SQLITE_DONE;
      rec.reset();
    };
    for (const Record& r : batch) {
      if (!ok) break;
      switch (r.kind) {
        case Record::Kind::Begin:
          cur = r.id, next = 0;
          beg.bind(1, r.id).bind(2, r.at).bind(3, r.at).bind(4, r.head).bind(5, std::int64_t(recordChecksum(r.head)));
          ok = beg.step() == SQLITE_DONE;
          beg.reset();
          break;
        case Record::Kind::Resume: cur = r.id, next = 0; break;
        case Record::Kind::Ops:
          if (cur == 0) break;
          for (size_t i = 0; i < r.texts.size(); ++i) record("op", std::int64_t(r.from + i), r.texts[i]);
          last = r.at;
          break;
        case Record::Kind::State:
          if (cur == 0) break;
          record("state", 0, r.texts[0]);
          last = r.at;
          if (r.stroke) durable.emplace_back(cur, r.stroke);
          break;
        case Record::Kind::End:
        case Record::Kind::EndId: {
          const std::int64_t id = r.kind == Record::Kind::End ? cur : r.id;
          if (id == 0) break;
          end.bind(1, r.at).bind(2, r.at).bind(3, id);
          ok = end.step() == SQLITE_DONE;
          end.reset();
          if (id == cur) cur = 0, next = 0, last = 0;
          break;
        }
      }
    }
    if (ok && cur && last > 0) {
      touch.bind(1, last).bind(2, cur);
      ok = touch.step() == SQLITE_DONE;
    }
  }
  if (!ok || !exec(db_, "COMMIT")) {
    const std::string err = sqlite3_errmsg(db_);
    exec(db_, "ROLLBACK");
    writeError_ = err;
    durable.clear();
    return false;
  }
  current_ = cur;
  return true;
}

void SessionJournal::run() {
  std::unique_lock lock(m_);
  for (;;) {
    cv_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (queue_.empty()) break;  // stopping with nothing left
    std::deque<Record> batch;
    batch.swap(queue_);
    writing_ = true;
    std::vector<std::pair<std::int64_t, std::uint64_t>> durable;
    // Queuing goes on while a batch is written (the main loop never waits for the disk); reads
    // (unfinished, list, prune) take dbm_, so they never see half a batch.
    lock.unlock();
    std::unique_lock<std::mutex> dbLock(dbm_);
    const bool ok = write(batch, durable);
    dbLock.unlock();
    lock.lock();
    writing_ = false;
    if (ok) {
      if (!error_.empty() && log_) log_("<5>journal: writing again after: " + error_);
      error_.clear();
      durable_.insert(durable_.end(), durable.begin(), durable.end());
      if (queue_.empty()) idle_.notify_all();
      continue;
    }
    // The disk refused (full, read-only, gone): keep the records in order, try again later; on the
    // way out, once more only.
    const bool first = error_.empty();
    error_ = writeError_;
    if (first && log_) log_("<3>journal: cannot write (" + error_ + "); " + std::to_string(batch.size()) + " records kept in memory");
    for (auto it = batch.rbegin(); it != batch.rend(); ++it) queue_.push_front(std::move(*it));
    if (stop_) break;
    cv_.wait_for(lock, std::chrono::duration<double>(kRetrySeconds), [&] { return stop_; });
  }
  idle_.notify_all();
}

}  // namespace emboss
